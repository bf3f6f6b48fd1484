//! Snapshot files are a fixed point: a run saved at any time, its file read back and resumed
//! onto a fresh build, saves to the same bytes again (for each mission, at seeds and times
//! drawn at random).

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use vitro::time::SimTime;
use vitro_mission::{BuildOptions, Snapshot};
use vitro_tools::registry;

fn scenario(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name)
}

/// Saves `file`'s run (seed `seed`) at `at_s`, reads the file back, resumes it and saves
/// again: the two files are the same bytes.
fn round_trip(file: &Path, seed: u64, at_s: u64) -> Result<(), TestCaseError> {
    let (mission, text) = registry().read(file).expect("the scenario reads");
    let options = BuildOptions {
        seed: Some(seed),
        fidelity: None,
    };
    let mut run = registry()
        .build(file, &options)
        .expect("the scenario builds");
    run.advance(SimTime::from_secs(at_s)).expect("the run goes");
    let snap = Snapshot::of(mission.kind(), file, &text, &options, run.as_ref()).expect("saves");
    let mut first = Vec::new();
    snap.write(&mut first).expect("writes");

    let read = Snapshot::read(first.as_slice()).expect("reads back");
    let resumed = registry().resume(&read, None).expect("resumes");
    prop_assert_eq!(resumed.now(), run.now());
    prop_assert_eq!(resumed.trace_hash(), run.trace_hash());
    let again =
        Snapshot::of(mission.kind(), file, &text, &options, resumed.as_ref()).expect("saves again");
    let mut second = Vec::new();
    again.write(&mut second).expect("writes");
    prop_assert!(
        first == second,
        "{} at {at_s} s (seed {seed}): the bytes differ",
        file.display()
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4, ..ProptestConfig::default() })]

    #[test]
    fn a_demo_snapshot_saves_to_the_same_bytes(seed in 0u64..1000, at_s in 0u64..120) {
        round_trip(&scenario("demo.toml"), seed, at_s)?;
    }
}

proptest! {
    // The surveillance and the evacuation load their site on every case: few cases.
    #![proptest_config(ProptestConfig { cases: 2, ..ProptestConfig::default() })]

    #[test]
    fn a_surveillance_snapshot_saves_to_the_same_bytes(seed in 0u64..1000, at_s in 0u64..30) {
        round_trip(&scenario("surveillance.toml"), seed, at_s)?;
    }

    #[test]
    fn an_evacuation_snapshot_saves_to_the_same_bytes(seed in 0u64..1000, at_s in 0u64..30) {
        round_trip(&scenario("evacuation.toml"), seed, at_s)?;
    }
}
