//! The evacuation through the mission plug-in interface: the same run as the crate's own API.

use std::path::Path;
use vitro::time::SimTime;
use vitro_evac::{Evacuation, Mission};
use vitro_mission::{BuildOptions, Metric, Mission as _, MissionError};

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

#[test]
fn a_run_built_through_the_plugin_is_the_same_run() {
    let path = Path::new(SCENARIO);
    let text = std::fs::read_to_string(path).unwrap();
    let until = SimTime::from_secs(120);
    let options = BuildOptions {
        seed: Some(7),
        fidelity: None,
    };
    let mut run = Evacuation.build(path, &text, &options).unwrap();
    run.set_end(until);
    while run.advance(until).unwrap() {}

    let mut direct = Mission::from_file(path, Some(7)).unwrap();
    direct.end = until;
    direct.run();

    assert_eq!(run.trace_hash(), direct.sim.trace_hash());
    assert_eq!(run.seed(), 7);
    let names = Evacuation.metric_names();
    let metrics = run.metrics();
    assert_eq!(
        metrics.iter().map(|(k, _)| *k).collect::<Vec<_>>(),
        names,
        "metrics come in the order metric_names promises"
    );
    let trace = metrics.iter().find(|(k, _)| *k == "trace_hash").unwrap();
    assert_eq!(
        trace.1,
        Metric::Text(format!("{:016x}", direct.sim.trace_hash()))
    );
    assert!(run.report().contains_key("levels"));
}

#[test]
fn a_bad_fidelity_or_scenario_is_bad_input_with_its_place() {
    let path = Path::new(SCENARIO);
    let text = std::fs::read_to_string(path).unwrap();
    let options = BuildOptions {
        seed: None,
        fidelity: Some("quantum".into()),
    };
    let Err(MissionError::Scenario(e)) = Evacuation.build(path, &text, &options) else {
        panic!("a fidelity no level has is bad input");
    };
    assert!(e.contains("discrete, interpolated, physical"), "{e}");

    let broken = text.replacen("seed = ", "seed = \"x\" #", 1);
    let Err(MissionError::Scenario(e)) = Evacuation.validate(path, &broken) else {
        panic!("a seed that is not a number is bad input");
    };
    assert!(e.contains("evacuation.toml:"), "the file and its line: {e}");
}
