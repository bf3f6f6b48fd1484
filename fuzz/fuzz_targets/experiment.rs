#![no_main]

use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;
use vitro_tools::{load_experiment, runner_for};

/// A directory with the demo scenario in it; each input is written as an experiment beside
/// it (experiments are read through their path and name their scenario relative to it).
fn dir() -> &'static std::path::Path {
    static DIR: OnceLock<std::path::PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("vitro-fuzz-exp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary directory");
        let demo = include_str!("../../scenarios/demo.toml");
        std::fs::write(dir.join("demo.toml"), demo).expect("the scenario is written");
        dir
    })
}

fuzz_target!(|data: &[u8]| {
    let path = dir().join("experiment.toml");
    if std::fs::write(&path, data).is_ok() {
        let runner = runner_for(&path);
        let _ = load_experiment(&path, runner.as_ref());
    }
});
