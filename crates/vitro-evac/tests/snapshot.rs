//! Snapshot and restore of the evacuation at every fidelity level: a run saved mid-way and
//! restored into a fresh build of the scenario ends with the trace hash and the metrics of
//! the uninterrupted run, the rigid-body world of the physical level included.

use vitro::time::SimTime;
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_mission::{Run, SnapshotError};
use vitro_tactical::scenario::Preset;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// The end of the runs: the VIP is out after nine to twelve minutes; the snapshot is taken
/// while the truck drives and the squad walks.
const END_S: u64 = 600;

fn build(preset: Preset) -> EvacRun {
    let mut m = Mission::at_fidelity(SCENARIO, Some(42), preset).expect("the scenario builds");
    m.end = SimTime::from_secs(END_S);
    m
}

/// The physical level runs shorter (rigid-body steps are slow in a debug build): two
/// minutes after the snapshot.
const PHYSICAL_AFTER_S: u64 = 120;

/// Runs uninterrupted; then saved at `save_s` (going on to the end: saving must not change
/// the run) and restored into a fresh build that runs to the end. All three end alike.
fn resumes_the_same_run(preset: Preset, save_s: u64, end_s: u64) -> usize {
    let build = |preset| {
        let mut m = build(preset);
        m.end = SimTime::from_secs(end_s);
        m
    };
    let mut whole = build(preset);
    whole.run();

    let mut saved = build(preset);
    saved.advance(SimTime::from_secs(save_s));
    let at = (saved.sim.now(), saved.sim.trace_hash());
    let bytes = saved.save_state().expect("the run saves");
    saved.run();
    assert_eq!(
        saved.sim.trace_hash(),
        whole.sim.trace_hash(),
        "{preset:?}: saving changed the run"
    );

    let mut resumed = build(preset);
    resumed.restore_state(&bytes).expect("the state restores");
    assert_eq!((resumed.sim.now(), resumed.sim.trace_hash()), at);
    resumed.run();
    assert_eq!(
        resumed.sim.trace_hash(),
        whole.sim.trace_hash(),
        "{preset:?}: the resumed run differs from the uninterrupted one"
    );
    assert_eq!(resumed.metrics(), whole.metrics());
    assert_eq!(resumed.sim.events_fired(), whole.sim.events_fired());
    bytes.len()
}

#[test]
fn save_and_restore_at_the_discrete_level() {
    let size = resumes_the_same_run(Preset::Discrete, 200, END_S);
    eprintln!("discrete: {size} bytes of state");
}

#[test]
fn save_and_restore_at_the_interpolated_level() {
    let size = resumes_the_same_run(Preset::Interpolated, 200, END_S);
    eprintln!("interpolated: {size} bytes of state");
}

#[test]
fn save_and_restore_at_the_physical_level_keeps_the_rigid_bodies() {
    // Saved while the truck is a rigid body driving at speed: the first 10 s mark at which
    // it goes faster than 3 m/s.
    let mut probe = build(Preset::Physical);
    let truck = probe.brief.truck;
    let mut t = 0;
    let speed = |m: &EvacRun| {
        m.sim
            .env()
            .chassis
            .get(truck)
            .map_or(0.0, |c| c.speed.abs())
    };
    while speed(&probe) < 3.0 {
        t += 10;
        assert!(t < END_S, "the truck never drives at speed");
        probe.advance(SimTime::from_secs(t));
    }
    assert!(probe.sim.env().physics.is_some());
    let size = resumes_the_same_run(Preset::Physical, t, t + PHYSICAL_AFTER_S);
    eprintln!("physical: saved at {t} s, {size} bytes of state");
}

#[test]
fn a_damaged_state_is_an_error_not_a_panic() {
    let mut m = build(Preset::Discrete);
    m.advance(SimTime::from_secs(60));
    let bytes = m.save_state().expect("the run saves");
    for cut in [0, 1, bytes.len() / 3, bytes.len() - 1] {
        let mut fresh = build(Preset::Discrete);
        let e = fresh.restore_state(&bytes[..cut]).unwrap_err();
        assert!(matches!(e, SnapshotError::Corrupt(_)), "cut at {cut}: {e}");
    }
    let mut fresh = build(Preset::Discrete);
    let e = fresh.restore_state(b"not a state at all").unwrap_err();
    assert!(matches!(e, SnapshotError::Corrupt(_)), "{e}");
}
