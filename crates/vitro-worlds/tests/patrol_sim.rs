//! The patrol plan played in the simulator: units sampling their policies, convoys on their
//! timetables, an attacker striking at its computed best moments; the estimates agree with the
//! computed capture probabilities within their 99% intervals.

use vitro_algo::graph::{self, Graph, NodeId};
use vitro_worlds::patrol::{AttackOrder, SimOptions, best_replies, simulate, worst_choices};
/// Steps an attack takes.
const DEADLINE: u32 = 4;
use vitro_algo::patrol::{Instance, PatrolPlan, Patroller, PlanParams, Target, TargetPosition};

/// Two convoys shuttling on the two halves of a road of seven junctions, meeting in the middle;
/// one unit, attacks of DEADLINE steps: it cannot ride with both.
fn two_convoys() -> (Graph, Vec<Target>) {
    let road = graph::path(7).unwrap();
    let convoy = |name: &str, schedule: Vec<NodeId>| Target {
        name: name.into(),
        position: TargetPosition::Schedule(schedule),
        value: 1.0,
        deadline: DEADLINE,
    };
    let targets = vec![
        convoy("west", vec![0, 1, 2, 3, 3, 2, 1, 0]),
        convoy("east", vec![6, 5, 4, 3, 3, 4, 5, 6]),
    ];
    (road, targets)
}

fn instance(g: &Graph, targets: &[Target], units: usize) -> Instance {
    let patrollers = (0..units)
        .map(|i| Patroller {
            name: format!("unit{i}"),
        })
        .collect();
    Instance::new(g.clone(), targets.to_vec(), patrollers).unwrap()
}

#[test]
fn simulated_captures_agree_with_the_computed_ones() {
    let (g, targets) = two_convoys();
    let inst = instance(&g, &targets, 1);
    let plan = PatrolPlan::solve(&g, &targets, 1, &PlanParams::default()).unwrap();
    eprintln!(
        "value {:.6}, capture {:.6}",
        plan.value, plan.capture_probability
    );
    // A real trade-off: neither hopeless nor certain.
    assert!(plan.capture_probability > 0.05 && plan.capture_probability < 0.95);
    // The attacker's best reply at every target and phase (ties pooled).
    let choices = worst_choices(&inst, &plan, 1e-9).unwrap();
    assert_eq!(choices.len(), 2 * 8);
    let options = SimOptions {
        seed: 11,
        trials: 2000,
        ..SimOptions::default()
    };
    let report = simulate(&inst, &plan, &choices, &options).unwrap();

    assert_eq!(report.refused_moves, 0);
    for (estimate, threat) in report.choices.iter().zip(&plan.threats) {
        let (lo, hi) = estimate.interval;
        let computed = estimate.computed;
        eprintln!(
            "target {} phase {:?}: computed {computed:.4}, simulated {:.4} [{lo:.4}, {hi:.4}]",
            estimate.choice.target, estimate.choice.phase, estimate.capture_probability
        );
        assert_eq!((estimate.trials, estimate.abandoned), (2000, 0));
        // The attacks made were the solver's worst for that target and phase...
        assert_eq!(
            (threat.target, Some(threat.phase)),
            (estimate.choice.target, estimate.choice.phase)
        );
        assert!((computed - threat.capture_probability).abs() < 1e-8);
        // ... and were caught as often as computed.
        assert!(lo <= computed && computed <= hi);
        assert!(hi - lo < 0.1);
    }
    let (lo, hi) = report.value_interval;
    assert!(
        lo <= plan.value && plan.value <= hi,
        "{lo} {} {hi}",
        plan.value
    );
}

#[test]
fn two_units_in_random_order_and_the_run_is_reproducible() {
    // Two units, three convoys on a 4 x 4 grid, attacks of three steps (randomised patrols);
    // the attacker picks its choices at random.
    let g = graph::grid(4, 4).unwrap();
    let convoy = |schedule: Vec<NodeId>| Target {
        name: "c".into(),
        position: TargetPosition::Schedule(schedule),
        value: 1.0,
        deadline: 3,
    };
    let targets = vec![
        convoy(vec![0, 1, 2, 3, 2, 1]),
        convoy(vec![12, 13, 14, 15, 14, 13]),
        convoy(vec![3, 7, 11, 15, 11, 7]),
    ];
    let inst = instance(&g, &targets, 2);
    let plan = PatrolPlan::solve(&g, &targets, 2, &PlanParams::default()).unwrap();
    assert!(plan.capture_probability > 0.05 && plan.capture_probability < 0.95);
    let choices = best_replies(&inst, &plan, 0.02).unwrap();
    assert_eq!(choices.len(), 3);
    let options = SimOptions {
        seed: 5,
        trials: 800,
        order: AttackOrder::Random,
        ..SimOptions::default()
    };
    let report = simulate(&inst, &plan, &choices, &options).unwrap();
    for estimate in &report.choices {
        let (lo, hi) = estimate.interval;
        assert_eq!(estimate.trials, 800);
        assert!(lo <= estimate.computed && estimate.computed <= hi);
        assert!(estimate.computed <= estimate.choice.threshold);
    }
    let again = simulate(&inst, &plan, &choices, &options).unwrap();
    assert_eq!(again.trace_hash, report.trace_hash);
    assert_eq!(again.choices, report.choices);
    let other = simulate(&inst, &plan, &choices, &SimOptions { seed: 6, ..options }).unwrap();
    assert_ne!(other.trace_hash, report.trace_hash);
}

#[test]
fn bad_choices_are_refused() {
    let (g, targets) = two_convoys();
    let inst = instance(&g, &targets, 1);
    let plan = PatrolPlan::solve(&g, &targets, 1, &PlanParams::default()).unwrap();
    let mut choices = worst_choices(&inst, &plan, 0.0).unwrap();
    choices[0].target = 9;
    assert!(simulate(&inst, &plan, &choices, &SimOptions::default()).is_err());
    assert!(simulate(&inst, &plan, &[], &SimOptions::default()).is_err());
    // A plan for two units does not fit a one-unit instance.
    let two = PatrolPlan::solve(&g, &targets, 2, &PlanParams::default()).unwrap();
    let choices = worst_choices(&inst, &plan, 0.0).unwrap();
    assert!(simulate(&inst, &two, &choices, &SimOptions::default()).is_err());
}
