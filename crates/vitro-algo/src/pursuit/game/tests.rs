use super::*;
use crate::cops::{CopOptions, cop_number};
use crate::graph::Graph;
use crate::pursuit::{Budget, FullVisibility, HopRange};

/// A reference graph of `data/graphs` (each states its cop number).
fn load(name: &str) -> Graph {
    let path = format!(
        "{}/../../data/graphs/{name}.edges",
        env!("CARGO_MANIFEST_DIR")
    );
    Graph::load(&path).unwrap()
}

/// Makes a fresh pursuer team.
type MakeTeam = dyn Fn() -> Box<dyn TeamStrategy>;

fn mcts(b: u64) -> MoIsmcts {
    MoIsmcts::new(MoIsmctsConfig {
        budget: Budget::iterations(b),
        ..MoIsmctsConfig::default()
    })
}

fn minimax(b: u64) -> WorstCaseMinimax {
    WorstCaseMinimax::new(WorstCaseMinimaxConfig {
        budget: Budget::iterations(b),
        ..WorstCaseMinimaxConfig::default()
    })
}

/// Captures out of `episodes` by `k` pursuers playing `team` against the exact evader.
fn captures(arena: &Arena, k: usize, episodes: usize, rounds: u32, team: &MakeTeam) -> EvalSummary {
    let exact = ExactEvader::new(arena, k).unwrap();
    evaluate(arena, k, episodes, rounds, 11, &mut || team(), &mut || {
        Box::new(exact.clone())
    })
    .unwrap()
}

/// The theory check: with full visibility, as many pursuers as the cop number capture the
/// exact evader in every episode, one fewer never do.
#[test]
fn cop_number_pursuers_capture_and_one_fewer_never_do() {
    for (name, rounds) in [
        ("tree_balanced_2_3", 20),
        ("cycle5", 20),
        ("cycle8", 20),
        ("grid4x4", 20),
        ("petersen", 20),
    ] {
        let g = load(name);
        let c = cop_number(&g, &CopOptions::default()).unwrap().cop_number;
        let arena = Arena::new(g, &FullVisibility).unwrap();
        let teams: [(&str, &MakeTeam); 2] = [
            ("mcts", &|| Box::new(mcts(300))),
            ("minimax", &|| Box::new(minimax(3000))),
        ];
        for (alg, team) in teams {
            let s = captures(&arena, c, 4, rounds, team);
            assert_eq!(
                s.captures, 4,
                "{name}: {c} pursuers ({alg}) must capture: {s:?}"
            );
            if c > 1 {
                let s = captures(&arena, c - 1, 4, rounds, team);
                assert_eq!(
                    s.captures,
                    0,
                    "{name}: {} pursuers ({alg}) must not: {s:?}",
                    c - 1
                );
            }
        }
    }
}

#[test]
fn truth_stays_in_the_pursuers_information_set() {
    let g = graph_grid(5, 5);
    let arena = Arena::new(g.clone(), &HopRange::new(&g, 1)).unwrap();
    for evader in 0..3 {
        let s = evaluate(
            &arena,
            2,
            3,
            25,
            5,
            &mut || Box::new(mcts(60)),
            &mut || match evader {
                0 => Box::new(ExactEvader::new(&arena, 2).unwrap()),
                1 => Box::new(FleeingHider),
                _ => Box::new(mcts(60)),
            },
        )
        .unwrap();
        assert!(s.truth_in_belief, "evader {evader}: {s:?}");
        assert!(
            s.mean_in_sight < 1.0,
            "hops 1 on a 5x5 grid hides sometimes: {s:?}"
        );
    }
}

fn graph_grid(r: usize, c: usize) -> Graph {
    crate::graph::grid(r, c).unwrap()
}

/// The evader's decisions are in the search: as the evader, MO-ISMCTS keeps away from a
/// lone pursuer on a cycle (cop number 2) as the exact evader does, where a random walker
/// would be caught.
#[test]
fn searching_evader_escapes_one_pursuer_on_a_cycle() {
    let arena = Arena::new(load("cycle8"), &FullVisibility).unwrap();
    let s = evaluate(
        &arena,
        1,
        4,
        30,
        3,
        &mut || Box::new(minimax(2000)),
        &mut || Box::new(mcts(200)),
    )
    .unwrap();
    assert_eq!(s.captures, 0, "{s:?}");
}

#[test]
fn wilson_interval_matches_the_formula() {
    let (lo, hi) = wilson_interval(0, 10);
    assert!(lo == 0.0 && (hi - 0.2775).abs() < 1e-3, "{lo} {hi}");
    let (lo, hi) = wilson_interval(5, 10);
    assert!(
        (lo - 0.2366).abs() < 1e-3 && (hi - 0.7634).abs() < 1e-3,
        "{lo} {hi}"
    );
    assert_eq!(wilson_interval(0, 0), (0.0, 1.0));
}

#[test]
fn no_pursuers_is_an_error() {
    let arena = Arena::new(load("cycle5"), &FullVisibility).unwrap();
    let r = evaluate(&arena, 0, 1, 5, 0, &mut || Box::new(mcts(5)), &mut || {
        Box::new(FleeingHider)
    });
    assert!(matches!(r, Err(crate::pursuit::PursuitError::NoPursuers)));
}

/// Anytime: more budget captures more, beyond the noise (fixed seed and sample size; the
/// 95 % Wilson intervals of the two budgets do not overlap). MO-ISMCTS on the 4 x 4 grid
/// with one-hop sight; the worst-case minimax with full sight and a short horizon, where
/// depth decides.
#[test]
fn more_budget_captures_more() {
    let g = load("grid4x4");
    let arena = Arena::new(g.clone(), &HopRange::new(&g, 1)).unwrap();
    let low = captures(&arena, 2, 20, 10, &|| Box::new(mcts(10)));
    let high = captures(&arena, 2, 20, 10, &|| Box::new(mcts(300)));
    assert!(
        high.capture_rate_ci95.0 > low.capture_rate_ci95.1,
        "MO-ISMCTS: {low:?} with 10 iterations, {high:?} with 300"
    );
    let arena = Arena::new(g, &FullVisibility).unwrap();
    let low = captures(&arena, 2, 30, 6, &|| Box::new(minimax(30)));
    let high = captures(&arena, 2, 30, 6, &|| Box::new(minimax(3000)));
    assert!(
        high.capture_rate_ci95.0 > low.capture_rate_ci95.1,
        "minimax: {low:?} with 30 nodes, {high:?} with 3000"
    );
}
