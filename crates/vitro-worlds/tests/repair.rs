//! Multi-agent plan execution and repair on the dock-worker and Depots domains.

use std::path::Path;

use vitro::time::SimDuration;
use vitro_algo::planning::validate::validate_plan;
use vitro_algo::repair::{Ownership, RepairKind, Scenario, Strategy};
use vitro_worlds::repair::{Disturbance, RepairConfig, RunFailure, RunReport, Trigger, run};

fn scenario(domain: &str, problem: &str) -> Scenario {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/planning");
    Scenario::from_files(
        &root.join(domain),
        &root.join(problem),
        &Ownership::first_parameter(),
    )
    .expect("the reference problem loads")
}

fn dwr() -> Scenario {
    scenario("dwr/domain.pddl", "dwr/problem-02.pddl")
}

fn config(strategy: Strategy, p: f64) -> RepairConfig {
    RepairConfig {
        strategy,
        failure_probability: p,
        ..RepairConfig::default()
    }
}

/// The world's changes replayed by the independent PDDL validator from the initial state.
fn assert_valid_trace(s: &Scenario, r: &RunReport) {
    let applied = r.applied();
    if let Err(e) = validate_plan(s.domain(), s.problem(), &applied) {
        panic!("executed trace invalid: {e}\n{applied:#?}");
    }
}

#[test]
fn dwr_agents_are_the_robot_and_the_cranes() {
    let s = dwr();
    assert_eq!(s.agents(), ["r1", "k1", "k2"]);
    assert_eq!(s.owner_of("(move r1 l1 l2)"), Some("r1"));
    assert_eq!(s.owner_of("(take k1 l1 cc cb p1)"), Some("k1"));
    assert_eq!(s.owner_of("(load k2 l2 cc r1)"), Some("k2"));
    // The robot sees where it is and which locations are free, nothing about piles.
    let view = s.view_of("r1").expect("an agent");
    assert!(view.contains(&"(atl r1 l1)") && view.contains(&"(free l2)"));
    assert!(!view.iter().any(|f| f.starts_with("(top")));
    assert_eq!(s.plan().len(), 35);
}

#[test]
fn another_owning_parameter_can_be_named() {
    // Loading and unloading belong to the robot (parameter 3) instead of the crane.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/planning/dwr");
    let own = Ownership::first_parameter()
        .with("load", 3)
        .with("unload", 3);
    let s = Scenario::from_files(
        &root.join("domain.pddl"),
        &root.join("problem-02.pddl"),
        &own,
    )
    .expect("loads");
    assert_eq!(s.owner_of("(load k2 l2 cc r1)"), Some("r1"));
    assert_eq!(s.owner_of("(take k1 l1 cc cb p1)"), Some("k1"));
}

#[test]
fn without_failures_every_strategy_executes_the_original_plan() {
    let s = dwr();
    for strategy in Strategy::ALL {
        let r = run(&s, &config(strategy, 0.0), 1).expect("runs");
        assert!(r.succeeded(), "{strategy}: {r}");
        assert_eq!(r.applied(), s.plan(), "{strategy}");
        assert_eq!(r.executed, s.plan().len());
        assert!(r.repairs.is_empty() && r.expanded == 0);
        assert_eq!(r.messages.plans, 0);
        // 35 steps of 10 s; turn messages take 1 ms each.
        assert!(r.end_time.as_secs_f64() >= 350.0 && r.end_time.as_secs_f64() < 351.0);
        // The last agent asks the two others whether the goal holds: 2 questions, 2 answers.
        assert_eq!(r.messages.queries, 4, "{strategy}");
    }
}

#[test]
fn turns_are_passed_only_between_different_agents() {
    let s = dwr();
    let plan = s.plan();
    let owners: Vec<&str> = plan.iter().map(|a| s.owner_of(a).expect("owned")).collect();
    let handovers = owners.windows(2).filter(|w| w[0] != w[1]).count() as u64;
    let r = run(&s, &config(Strategy::Replan, 0.0), 3).expect("runs");
    assert_eq!(r.messages.turns, handovers);
}

#[test]
fn with_failures_successful_traces_are_valid_plans() {
    let s = dwr();
    for strategy in Strategy::ALL {
        let mut failures = 0;
        for seed in 0..12 {
            let r = run(&s, &config(strategy, 0.2), seed).expect("runs");
            assert!(r.succeeded(), "{strategy} seed {seed}: {r}");
            assert_valid_trace(&s, &r);
            failures += r.failures();
            // Every failure the world saw was noticed by an agent (or absorbed lazily).
            assert!(
                r.detected >= r.failures() || r.skipped > 0,
                "{strategy}: {r}"
            );
        }
        assert!(failures > 0, "{strategy}: p = 0.2 should make actions fail");
    }
}

#[test]
fn strategies_repair_as_documented() {
    let s = dwr();
    let r = run(&s, &config(Strategy::BackOnTrack, 0.2), 4).expect("runs");
    assert!(!r.repairs.is_empty());
    for rep in &r.repairs {
        assert_eq!(rep.kind, RepairKind::BackOnTrack);
        assert!(
            !rep.fell_back,
            "DWR actions are reversible: always back on track"
        );
    }
    // Lazy: the original plan is run to its end before the one lazy repair.
    let r = run(&s, &config(Strategy::Lazy, 0.2), 4).expect("runs");
    let first = r.repairs.first().expect("a repair");
    assert_eq!(
        (first.kind, &first.trigger),
        (RepairKind::Lazy, &Trigger::PlanEnd)
    );
    assert!(r.repairs[1..].iter().all(|x| x.kind == RepairKind::Replan));
    // Repeated lazy: only lazy repairs, each at the end of a plan.
    let r = run(&s, &config(Strategy::RepeatedLazy, 0.3), 4).expect("runs");
    assert!(r.repairs.len() >= 2, "{r}");
    assert!(
        r.repairs
            .iter()
            .all(|x| x.kind == RepairKind::Lazy && x.trigger == Trigger::PlanEnd)
    );
    // Replanning.
    let r = run(&s, &config(Strategy::Replan, 0.2), 4).expect("runs");
    assert!(r.repairs.iter().all(|x| x.kind == RepairKind::Replan));
}

#[test]
fn same_seed_same_trace() {
    let s = dwr();
    for strategy in Strategy::ALL {
        let a = run(&s, &config(strategy, 0.2), 9).expect("runs");
        let b = run(&s, &config(strategy, 0.2), 9).expect("runs");
        assert_eq!(a.trace_hash, b.trace_hash, "{strategy}");
        assert_eq!(a.log, b.log);
        let c = run(&s, &config(strategy, 0.2), 10).expect("runs");
        assert_ne!(
            a.trace_hash, c.trace_hash,
            "{strategy}: seeds should matter"
        );
    }
}

#[test]
fn the_expansion_bound_is_honoured_and_reported() {
    let s = dwr();
    // A bound of one expansion cuts every repair that needs more than one step.
    let mut cfg = config(Strategy::Replan, 0.2);
    cfg.max_expansions = Some(1);
    let r = run(&s, &cfg, 4).expect("runs");
    assert!(r.repairs.iter().all(|x| x.expanded <= 1));
    assert!(r.truncated_searches() > 0);
    assert_eq!(r.outcome, Err(RunFailure::NoPlan { repairs: 1 }));
    assert!(
        r.to_string()
            .contains("the expansion bound cut 1 repair search"),
        "{r}"
    );
    // Back-on-track searches twice (back, then to the goal): each within the bound.
    cfg.strategy = Strategy::BackOnTrack;
    cfg.max_expansions = Some(3);
    let r = run(&s, &cfg, 4).expect("runs");
    assert!(r.repairs.iter().all(|x| x.expanded <= 6), "{r}");
    // A generous bound changes nothing.
    let free = run(&s, &config(Strategy::Replan, 0.2), 4).expect("runs");
    let mut cfg = config(Strategy::Replan, 0.2);
    cfg.max_expansions = Some(1_000_000);
    let bounded = run(&s, &cfg, 4).expect("runs");
    assert_eq!(free.trace_hash, bounded.trace_hash);
    assert_eq!(bounded.truncated_searches(), 0);
}

#[test]
fn planning_time_is_charged_per_expanded_state() {
    let s = dwr();
    let cfg = config(Strategy::Replan, 0.2);
    let r = run(&s, &cfg, 5).expect("runs");
    assert!(!r.repairs.is_empty());
    for rep in &r.repairs {
        assert_eq!(rep.planning_time, cfg.cost.cost(rep.expanded));
    }
    // A slower planner ends the run later by exactly the extra thinking time.
    let mut slow = cfg.clone();
    slow.cost.per_unit = cfg.cost.per_unit * 2;
    let r2 = run(&s, &slow, 5).expect("runs");
    assert_eq!(r.log.len(), r2.log.len());
    let extra = SimDuration::from_nanos(cfg.cost.per_unit.as_nanos() * r.expanded);
    assert_eq!(r2.end_time, r.end_time + extra);
}

#[test]
fn disturbances_change_the_world_under_the_agents() {
    let s = dwr();
    for strategy in Strategy::ALL {
        let mut cfg = config(strategy, 0.0);
        cfg.disturbance = Some(Disturbance {
            period: SimDuration::from_secs(25),
            probability: 0.5,
        });
        let mut disturbed = 0;
        for seed in 0..6 {
            let r = run(&s, &cfg, seed).expect("runs");
            assert!(r.succeeded(), "{strategy} seed {seed}: {r}");
            assert_valid_trace(&s, &r);
            disturbed += r.log.iter().filter(|a| a.by.is_none()).count();
        }
        assert!(disturbed > 0);
    }
}

#[test]
fn depot_trucks_and_hoists_repair_too() {
    let s = scenario("depot/domain.pddl", "depot/p02.pddl");
    assert_eq!(
        s.agents(),
        ["truck0", "truck1", "hoist0", "hoist1", "hoist2"]
    );
    for strategy in Strategy::ALL {
        for seed in 0..4 {
            let r = run(&s, &config(strategy, 0.15), seed).expect("runs");
            assert!(r.succeeded(), "{strategy} seed {seed}: {r}");
            assert_valid_trace(&s, &r);
        }
    }
}

#[test]
fn invalid_settings_are_refused() {
    let s = dwr();
    let e = run(&s, &config(Strategy::Replan, 1.5), 0).expect_err("invalid");
    assert_eq!(
        e.to_string(),
        "failure_probability must be a probability in [0, 1], found 1.5"
    );
    let mut cfg = config(Strategy::Replan, 0.1);
    cfg.disturbance = Some(Disturbance {
        period: SimDuration::ZERO,
        probability: 0.1,
    });
    assert!(run(&s, &cfg, 0).is_err());
}
