//! The guide's mission in the `vitro` command: a mission crate's own `vitro` is
//! `vitro_cli::run` with the mission installed beside the stock ones, and it runs, validates
//! and batches `kind = "watch"` files as the stock command does its own (one process, one
//! registry: this file holds one test).

use std::path::Path;
use vitro_guide::watch::PerimeterWatch;

static WATCH: PerimeterWatch = PerimeterWatch;

#[test]
fn the_vitro_command_runs_a_mission_installed_beside_the_stock_ones() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let watch = dir.join("scenarios/watch.toml");
    let watch = watch.to_str().unwrap();
    let demo = dir.join("../../scenarios/demo.toml");
    let demo = demo.to_str().unwrap();
    // The mission's own `vitro`: its kind validates and runs ...
    assert_eq!(
        vitro_cli::run(vec![&WATCH], ["vitro", "validate", watch]),
        0
    );
    let run = ["vitro", "run", watch, "--until", "120", "--quiet"];
    assert_eq!(vitro_cli::run(Vec::new(), run), 0);
    // ... and the stock kinds still do.
    let kinds = vitro_tools::registry().kinds();
    assert!(
        kinds.contains(&"watch") && kinds.contains(&"evacuation"),
        "{kinds:?}"
    );
    assert_eq!(vitro_cli::run(Vec::new(), ["vitro", "validate", demo]), 0);
    // A bad argument is bad input, as in the stock command.
    assert_eq!(vitro_cli::run(Vec::new(), ["vitro", "run"]), 2);
    // The registry is set once: a second install is refused, with exit code 1.
    assert_eq!(
        vitro_cli::run(vec![&WATCH], ["vitro", "validate", watch]),
        1
    );
}
