#![no_main]

use libfuzzer_sys::fuzz_target;
use std::cell::RefCell;
use vitro_mission::{BuildOptions, Run, Snapshot};

thread_local! {
    /// A demo run built once; each input is also restored onto it as mission state.
    static RUN: RefCell<Box<dyn Run>> = RefCell::new({
        let path = std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../scenarios/demo.toml"
        ));
        vitro_tools::registry()
            .build(path, &BuildOptions::default())
            .expect("the demo builds")
    });
}

fuzz_target!(|data: &[u8]| {
    let _ = Snapshot::read(data);
    RUN.with(|run| {
        let _ = run.borrow_mut().restore_state(data);
    });
});
