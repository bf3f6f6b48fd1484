//! The LP backends agree: the certified game values of the data instances are the same with
//! microlp and Clarabel (to the solver's tolerance), and so is the phase-locked patrol of a
//! convoy on a road.

use vitro_algo::graph;
use vitro_algo::patrol::{
    self, Instance, LpBackend, PatrolPlan, PlanParams, SolveOptions, Target, TargetPosition,
};

fn data(name: &str) -> Instance {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    Instance::load(format!("{root}/data/patrol/{name}.toml")).expect("a data instance")
}

#[test]
fn certified_values_are_the_same_with_every_backend() {
    let cases = [
        ("static", false, 4.0 * 3f64.sqrt() - 6.0),
        ("convoy", false, (3.0 - 5f64.sqrt()) / 2.0),
        ("convoy", true, 0.0),
    ];
    for (name, time_dependent, known) in cases {
        let instance = data(name);
        for lp in LpBackend::ALL {
            let options = SolveOptions {
                time_dependent,
                lp,
                ..SolveOptions::default()
            };
            let s = patrol::solve_with(&instance, &options).expect("solved");
            assert!(s.exact, "{name} {lp:?}: not certified");
            assert!(
                (s.value - known).abs() < 1e-4,
                "{name} (time-dependent {time_dependent}) with {}: {} against {known}",
                lp.name(),
                s.value
            );
            assert_eq!(s.stats.lp.backend, lp);
        }
    }
}

#[test]
fn a_phase_locked_convoy_patrol_is_the_same_with_every_backend() {
    let road = graph::path(6).expect("a path");
    let convoy = Target {
        name: "convoy".into(),
        position: TargetPosition::Schedule(vec![0, 1, 2, 3, 4, 5, 4, 3, 2, 1]),
        value: 1.0,
        deadline: 3,
    };
    let post = Target {
        name: "post".into(),
        position: TargetPosition::Static(5),
        value: 1.0,
        deadline: 3,
    };
    let values: Vec<f64> = LpBackend::ALL
        .iter()
        .map(|&lp| {
            let params = PlanParams {
                iterations: 20,
                restarts: 0,
                lp,
                ..PlanParams::default()
            };
            PatrolPlan::solve(&road, &[convoy.clone(), post.clone()], 1, &params)
                .expect("solved")
                .value
        })
        .collect();
    assert!((values[0] - values[1]).abs() < 1e-3, "{values:?}");
}
