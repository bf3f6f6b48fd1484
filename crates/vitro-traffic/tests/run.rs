//! The traffic scenario through the plug-in interface: it runs at the discrete and
//! interpolated levels with sensible metrics, and the same seed gives the same trace.

use std::path::PathBuf;
use vitro::time::SimTime;
use vitro_mission::{BuildOptions, Metric, Mission as _, Run};
use vitro_traffic::Traffic;

fn path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/traffic.toml")
}

fn run(seed: u64, level: &str, until: u64) -> Box<dyn Run> {
    let text = std::fs::read_to_string(path()).unwrap();
    let options = BuildOptions {
        seed: Some(seed),
        fidelity: Some(level.to_owned()),
    };
    let mut run = Traffic.build(&path(), &text, &options).unwrap();
    run.set_end(SimTime::from_secs(until));
    while run.advance(run.end()).unwrap() {}
    run
}

fn num(run: &dyn Run, name: &str) -> Option<f64> {
    let m = run.metrics();
    m.iter()
        .find(|(k, _)| *k == name)
        .and_then(|(_, v)| v.number())
}

fn check_level(level: &str) {
    let (a, b, c) = (
        run(3, level, 1200),
        run(3, level, 1200),
        run(4, level, 1200),
    );
    assert_eq!(a.trace_hash(), b.trace_hash(), "{level}");
    assert_eq!(a.metrics(), b.metrics(), "{level}");
    assert_ne!(a.trace_hash(), c.trace_hash(), "{level}");
    let n = |k| num(a.as_ref(), k).unwrap_or_else(|| panic!("{level}: no {k}"));
    assert_eq!(n("vehicles"), 20.0);
    assert_eq!(n("troopers"), 10.0);
    assert!((n("vehicle_hours") - 20.0 * 1200.0 / 3600.0).abs() < 1e-9);
    // 20 minutes on a town a few kilometres across: every vehicle finishes trips, troopers
    // on foot some.
    assert!(n("trips_completed") >= 60.0, "{level}: {:?}", a.metrics());
    assert!(n("trooper_trips") >= 1.0, "{level}: {:?}", a.metrics());
    let trip = n("mean_trip_s");
    assert!(trip > 10.0 && trip < 1200.0, "{level}: mean trip {trip} s");
    let wait = n("deadlock_s");
    assert!((0.0..=1200.0).contains(&wait), "{level}: deadlock {wait} s");
    assert_eq!(n("stopped"), 0.0, "{level}: {:?}", a.metrics());
    let collisions = a.metrics().into_iter().find(|(k, _)| *k == "collisions");
    assert_eq!(collisions.map(|c| c.1), Some(Metric::Missing));
}

#[test]
fn discrete_traffic_runs_and_repeats() {
    check_level("discrete");
}

#[test]
fn interpolated_traffic_runs_and_repeats() {
    check_level("interpolated");
}

#[test]
fn the_scenario_validates() {
    let text = std::fs::read_to_string(path()).unwrap();
    let line = Traffic.validate(&path(), &text).unwrap();
    assert!(line.contains("20 vehicles, 10 troopers"), "{line}");
}

#[test]
fn a_bad_file_is_located() {
    let text = std::fs::read_to_string(path())
        .unwrap()
        .replace("check_s = 1.0", "check_s = -1.0");
    let e = Traffic.validate(&path(), &text).unwrap_err().to_string();
    assert!(e.contains("traffic.toml:"), "{e}");
    assert!(e.contains("`traffic.check_s`"), "{e}");
}

#[test]
fn more_vehicles_than_junctions_are_refused() {
    let text = std::fs::read_to_string(path())
        .unwrap()
        .replace("count = 7\n", "count = 19000\n");
    let e = Traffic.validate(&path(), &text).unwrap_err().to_string();
    assert!(e.contains("one per junction of the town"), "{e}");
}

#[test]
fn the_referee_and_frames_do_not_change_the_run() {
    let text = std::fs::read_to_string(path()).unwrap();
    let options = BuildOptions {
        seed: Some(5),
        fidelity: Some("interpolated".to_owned()),
    };
    let end = SimTime::from_secs(300);
    let mut plain = Traffic.build(&path(), &text, &options).unwrap();
    plain.set_end(end);
    while plain.advance(end).unwrap() {}
    let looked = text.replace("check_s = 1.0", "check_s = 0.25");
    let mut watched = Traffic.build(&path(), &looked, &options).unwrap();
    watched.set_end(end);
    let mut t = 0;
    while t < 300 {
        t += 7;
        watched.advance(SimTime::from_secs(t.min(300))).unwrap();
        let frame = watched.frame();
        assert_eq!(frame.entities.len(), 30);
    }
    while watched.advance(end).unwrap() {}
    assert_eq!(plain.trace_hash(), watched.trace_hash());
}
