//! The perimeter watch end to end: through a registry, at the discrete and the interpolated
//! level, the same trace hash on a rerun, and bad input refused with its place.

use std::path::{Path, PathBuf};
use vitro_guide::watch::PerimeterWatch;
use vitro_mission::{BuildOptions, Metric, Mission, Registry, Run};

static WATCH: PerimeterWatch = PerimeterWatch;

fn scenario() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/watch.toml")
}

fn metric(run: &dyn Run, name: &str) -> Metric {
    let m = run.metrics().into_iter().find(|(k, _)| *k == name);
    m.unwrap_or_else(|| panic!("no metric {name}")).1
}

fn count(run: &dyn Run, name: &str) -> i64 {
    match metric(run, name) {
        Metric::Int(n) => n,
        other => panic!("{name} is {other:?}"),
    }
}

/// Runs the scenario at `fidelity` to its end: the run, for its metrics and hash.
fn run(registry: &Registry, fidelity: &str) -> Box<dyn Run> {
    let options = BuildOptions {
        seed: None,
        fidelity: Some(fidelity.into()),
    };
    let mut run = registry.build(&scenario(), &options).unwrap();
    while run.advance(run.end()).unwrap() {}
    run
}

#[test]
fn the_watch_runs_at_two_levels_and_again_the_same() {
    let registry = Registry::new(vec![&WATCH]);
    let (mission, summary) = registry.validate(&scenario()).unwrap();
    assert_eq!(
        (mission.kind(), summary.as_str()),
        ("watch", "2 guards, 6 walkers")
    );
    for level in ["discrete", "interpolated"] {
        let r = run(&registry, level);
        println!("{level}: {:?}", r.summary());
        assert_eq!(r.now().as_secs_f64(), 900.0, "{level}");
        assert_eq!(count(&*r, "walkers"), 6);
        let seen = count(&*r, "walkers_seen");
        assert!((1..=6).contains(&seen), "{level}: {seen} seen");
        // The walkers make it to the depot, in the guards' ring: each is seen on the way in.
        let at_depot = count(&*r, "walkers_at_depot");
        assert!(at_depot >= 1, "{level}: {at_depot} at the depot");
        let Metric::Float(first) = metric(&*r, "first_sighting_s") else {
            panic!("{level}: nobody seen")
        };
        assert!(first > 0.0 && first < 900.0, "{level}: first at {first}");
        assert_eq!(count(&*r, "stalls"), 0, "{level}");
        // The same scenario and seed: the same run.
        let again = run(&registry, level);
        assert_eq!(again.trace_hash(), r.trace_hash(), "{level}");
        assert_eq!(again.metrics(), r.metrics(), "{level}");
    }
}

#[test]
fn a_bad_watch_table_is_refused_with_its_place() {
    let text = std::fs::read_to_string(scenario()).unwrap();
    let bad = text
        .replace("ring_m = 150.0", "ring_m = -5.0")
        .replace("type = \"trooper\"", "type = \"vidar\"\naltitude_m = 100.0");
    let e = WATCH.validate(&scenario(), &bad).unwrap_err().to_string();
    println!("{e}");
    assert!(e.contains("watch.toml:24:"), "{e}");
    assert!(e.contains("ring_m"), "{e}");
    assert!(e.contains("has no part here"), "{e}");
}

#[test]
fn the_guards_drive_as_rigid_bodies_too() {
    let registry = Registry::new(vec![&WATCH]);
    let mut r = run(&registry, "physical");
    println!("physical: {:?}", r.summary());
    let frame = r.frame();
    let guards: Vec<_> = frame.entities.iter().filter(|e| e.kind == "ugv").collect();
    assert_eq!(guards.len(), 2);
    for g in guards {
        assert_eq!(
            (g.level.as_str(), g.status.as_str()),
            ("physical", "active")
        );
    }
    // A rigid body backs out and turns in several moves where the ring turns sharply, as a
    // junction hop never has to: no trip given up.
    assert_eq!(count(&*r, "stalls"), 0);
    assert_eq!(count(&*r, "walkers_at_depot"), 6);
    let again = run(&registry, "physical");
    assert_eq!(again.trace_hash(), r.trace_hash());
}
