//! The mission through the plug-in interface: deterministic, the same run as the crate's
//! own API, metrics in the promised order, bad input located, standalone files.

mod common;

use common::path;
use std::path::Path;
use vitro::time::SimTime;
use vitro_mission::{BuildOptions, Metric, Mission as _, MissionError, Run};
use vitro_surveillance::{Operation, Surveillance};

fn run(seed: u64, until: u64) -> Box<dyn Run> {
    let text = std::fs::read_to_string(path()).unwrap();
    let options = BuildOptions {
        seed: Some(seed),
        fidelity: None,
    };
    let mut run = Surveillance.build(&path(), &text, &options).unwrap();
    run.set_end(SimTime::from_secs(until));
    while run.advance(run.end()).unwrap() {}
    run
}

#[test]
fn the_same_seed_gives_the_same_trace_hash() {
    let (a, b, c) = (run(7, 400), run(7, 400), run(8, 400));
    assert_eq!(a.trace_hash(), b.trace_hash());
    assert_eq!(a.metrics(), b.metrics());
    assert_ne!(a.trace_hash(), c.trace_hash());
}

#[test]
fn a_run_built_through_the_plugin_is_the_same_run() {
    let mut plugin = run(7, 300);
    let mut direct = Operation::from_file(path(), Some(7)).unwrap();
    direct.end = SimTime::from_secs(300);
    direct.run();
    assert_eq!(plugin.trace_hash(), direct.sim.trace_hash());
    let names = Surveillance.metric_names();
    let metrics = plugin.metrics();
    assert_eq!(metrics.iter().map(|(k, _)| *k).collect::<Vec<_>>(), names);
    let trace = metrics.iter().find(|(k, _)| *k == "trace_hash").unwrap();
    assert_eq!(
        trace.1,
        Metric::Text(format!("{:016x}", direct.sim.trace_hash()))
    );
    let report = plugin.report();
    assert!(report.contains_key("red") && report.contains_key("levels"));
    // Frames do not change the run.
    let scene = plugin.scene();
    assert!(scene.places.keys().any(|k| k.starts_with("sector ")));
    let frame = plugin.frame();
    assert!(frame.entities.iter().any(|e| e.kind == "skeldar"));
    assert!(frame.entities.iter().any(|e| e.status == "tracked"));
    assert_eq!(plugin.trace_hash(), direct.sim.trace_hash());
}

#[test]
fn sampling_and_frames_do_not_change_the_run() {
    let text = std::fs::read_to_string(path()).unwrap();
    let options = BuildOptions {
        seed: Some(3),
        fidelity: None,
    };
    let mut framed = Surveillance.build(&path(), &text, &options).unwrap();
    framed.set_end(SimTime::from_secs(200));
    let mut t = 0;
    while framed.advance(SimTime::from_secs(t)).unwrap() {
        framed.frame();
        t += 7;
    }
    assert_eq!(framed.trace_hash(), run(3, 200).trace_hash());
}

#[test]
fn every_fidelity_preset_runs() {
    let text = std::fs::read_to_string(path()).unwrap();
    for level in Surveillance.fidelity_levels() {
        let options = BuildOptions {
            seed: Some(1),
            fidelity: Some((*level).to_owned()),
        };
        let mut run = Surveillance.build(&path(), &text, &options).unwrap();
        run.set_end(SimTime::from_secs(60));
        while run.advance(run.end()).unwrap() {}
        assert_eq!(run.now(), SimTime::from_secs(60), "{level}");
    }
}

#[test]
fn bad_input_is_located() {
    let text = std::fs::read_to_string(path()).unwrap();
    let bad = text.replacen("loss = 0.05", "loss = 1.5", 1);
    let Err(MissionError::Scenario(e)) = Surveillance.validate(&path(), &bad) else {
        panic!("a loss above 1 is bad input");
    };
    let line = bad
        .lines()
        .position(|l| l.starts_with("loss = 1.5"))
        .unwrap()
        + 1;
    assert!(
        e.contains(&format!(
            "surveillance.toml:{line}:8: invalid value 1.5 for `channel.loss`"
        )),
        "{e}"
    );

    let bad = text.replacen("uav = \"uav-2\"", "uav = \"uav-9\"", 1);
    let Err(MissionError::Scenario(e)) = Surveillance.validate(&path(), &bad) else {
        panic!("a loss of a UAV that does not exist is bad input");
    };
    assert!(
        e.contains("no UAV is named `uav-9`") && e.contains("uav-1, uav-2"),
        "{e}"
    );

    let bad = text.replacen("start = [-579.4, -783.8]", "start = [99999.0, 0.0]", 1);
    let Err(MissionError::Scenario(e)) = Surveillance.validate(&path(), &bad) else {
        panic!("a station outside the town is bad input");
    };
    assert!(
        e.contains("`station.start` [99999.0, 0.0] lies outside the town"),
        "{e}"
    );

    let options = BuildOptions {
        seed: None,
        fidelity: Some("quantum".into()),
    };
    assert!(matches!(
        Surveillance.build(&path(), &text, &options),
        Err(MissionError::Scenario(_))
    ));
}

#[test]
fn validation_summarises_the_scenario() {
    let text = std::fs::read_to_string(path()).unwrap();
    let line = Surveillance.validate(&path(), &text).unwrap();
    assert!(
        line.starts_with("\"wide-area surveillance\": 4 UAVs, 8 red units"),
        "{line}"
    );
}

#[test]
fn a_standalone_file_makes_the_same_run() {
    let text = std::fs::read_to_string(path()).unwrap();
    let table: toml::Table = toml::from_str(&text).unwrap();
    let dir = std::env::temp_dir().join(format!("vitro-surv-standalone-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let from = path().parent().unwrap().to_path_buf();
    let out = Surveillance
        .standalone(&table, 7, Some(300.0), &from, &dir)
        .unwrap();
    let file = dir.join("min.toml");
    std::fs::write(&file, &out).unwrap();
    let mut again = Surveillance
        .build(Path::new(&file), &out, &BuildOptions::default())
        .unwrap();
    while again.advance(again.end()).unwrap() {}
    assert_eq!(again.trace_hash(), run(7, 300).trace_hash());
    std::fs::remove_dir_all(&dir).ok();
}
