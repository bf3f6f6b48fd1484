//! The Vidars' cover plan under failures: looks fail (the scenario's `repair.failure_rate`,
//! occlusion), Vidars are recalled, messages are lost; the lead detects it from what it
//! hears and repairs by each strategy of the repair framework.

use vitro::entity::EntityId;
use vitro::time::SimTime;
use vitro_evac::Mission;
use vitro_evac::agents::air::Aircraft;
use vitro_evac::referee::Metrics;
use vitro_evac::scenario::{RepairStrategy, ScenarioFile};
use vitro_tactical::scenario::{FidelitySpec, Preset};

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// The default mission (discrete, 900 s) with `strategy`, `rate` and `max_depth`; its
/// metrics and the lead Vidar's repair counts.
fn run(
    strategy: RepairStrategy,
    rate: f64,
    max_depth: Option<u32>,
    seed: u64,
) -> (Metrics, vitro_algo::repair::RepairTally) {
    run_with(strategy, rate, max_depth, seed, 2)
}

/// [`run`] with a cover team of `vidars`.
fn run_with(
    strategy: RepairStrategy,
    rate: f64,
    max_depth: Option<u32>,
    seed: u64,
    vidars: u32,
) -> (Metrics, vitro_algo::repair::RepairTally) {
    let mut v = ScenarioFile::validate(SCENARIO).expect("validates");
    let team = v
        .loaded
        .file
        .entities
        .iter_mut()
        .find(|e| e.name == "vidar");
    team.expect("the Vidar group").count = vidars;
    v.loaded.file.repair.strategy = strategy;
    v.loaded.file.repair.failure_rate = rate;
    v.loaded.file.repair.max_depth = max_depth;
    v.loaded.file.fidelity = FidelitySpec {
        level: Preset::Discrete,
        ..FidelitySpec::default()
    };
    let mut m = Mission::build(v, Some(seed)).expect("builds");
    m.end = SimTime::from_secs(900);
    m.run();
    let tally = (0..1000)
        .filter_map(|i| m.sim.agent(EntityId(i)))
        .filter_map(|a| a.as_any().downcast_ref::<Aircraft>())
        .find_map(|a| a.cover.as_ref().map(|c| c.tally()))
        .expect("a lead Vidar");
    (m.metrics(), tally)
}

#[test]
fn failures_are_detected_and_each_strategy_reacts_its_way() {
    use RepairStrategy::*;
    let (m, t) = run(Replan, 0.3, None, 42);
    assert!(m.success, "{m:?}");
    assert!(m.plan_failures > 0, "looks fail at rate 0.3: {m:?}");
    assert!(t.repairs > 0 && m.plan_repairs == t.repairs);
    // Lazy leaves failures of its plan for the plan's end.
    let (m, t) = run(Lazy, 0.3, None, 42);
    assert!(m.plan_failures > 0);
    assert!(t.deferred > 0, "lazy repaired at once: {t:?}");
    let (_, t) = run(BackOnTrack, 0.3, None, 42);
    assert!(t.repairs > 0, "{t:?}");
}

#[test]
fn back_on_track_tells_fewer_vidars_per_repair_than_replanning() {
    // A team of four (discrete, failure rate 0.3, seeds 1-3): replanning sends every Vidar
    // with a step its new plan; back-on-track only the Vidar whose step failed (and those
    // that take over a lost Vidar's looks).
    let total = |s| -> (u64, u64) {
        [1, 2, 3].iter().fold((0, 0), |(msg, rep), &seed| {
            let (m, _) = run_with(s, 0.3, None, seed, 4);
            (msg + m.plan_messages, rep + m.plan_repairs)
        })
    };
    let (replan, replan_repairs) = total(RepairStrategy::Replan);
    let (back, back_repairs) = total(RepairStrategy::BackOnTrack);
    eprintln!(
        "plan messages: back-on-track {back} / {back_repairs} repairs, replan {replan} / {replan_repairs}"
    );
    assert!(replan_repairs > 0 && back_repairs > 0);
    let per = |m: u64, r: u64| m as f64 / r as f64;
    assert!(
        per(back, back_repairs) < per(replan, replan_repairs),
        "plan messages per repair: back-on-track {back}/{back_repairs}, replan {replan}/{replan_repairs}"
    );
}

#[test]
fn the_depth_bound_cuts_repairs_and_counts_them() {
    let (m, t) = run(RepairStrategy::Replan, 0.3, Some(1), 42);
    assert!(m.plan_cuts > 0 && m.plan_cuts == t.cuts, "{m:?}");
    let (m, _) = run(RepairStrategy::Replan, 0.3, None, 42);
    assert_eq!(m.plan_cuts, 0);
}
