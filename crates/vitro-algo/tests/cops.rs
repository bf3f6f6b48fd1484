//! Cop numbers against known answers, and the solved strategies played out.

use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vitro_algo::cops::{CopOptions, CopsGame, Decision, Outcome, Turn, cop_number};
use vitro_algo::graph::{self, Graph, NodeId};

const GRAPHS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/graphs");

fn no_domination() -> CopOptions {
    CopOptions {
        use_domination: false,
        ..CopOptions::default()
    }
}

/// Cop number and time, checked with and without the domination shortcut.
fn check(name: &str, g: &Graph, expected: usize) {
    let start = Instant::now();
    let fast = cop_number(g, &CopOptions::default()).unwrap();
    let fast_time = start.elapsed();
    let start = Instant::now();
    let full = cop_number(g, &no_domination()).unwrap();
    let full_time = start.elapsed();
    eprintln!(
        "{name:>22}: n={:>2} m={:>2} cop number {} ({} states, {:.2?}); retrograde only: {} ({} states, {:.2?})",
        g.node_count(),
        g.edge_count(),
        fast.cop_number,
        fast.states_explored,
        fast_time,
        full.cop_number,
        full.states_explored,
        full_time,
    );
    assert_eq!(fast.cop_number, expected, "{name}");
    assert_eq!(full.cop_number, expected, "{name} (retrograde only)");
    assert!(
        full.components
            .iter()
            .all(|c| c.decided_by == Decision::Retrograde)
    );
}

/// The cop number stated in a data file's first line: "# name: ..., cop number K".
fn stated_cop_number(text: &str) -> usize {
    let first = text.lines().next().unwrap_or("");
    let (_, tail) = first
        .split_once("cop number")
        .unwrap_or_else(|| panic!("no cop number in {first:?}"));
    tail.trim().parse().unwrap()
}

#[test]
fn every_data_file_has_its_stated_cop_number() {
    let mut paths: Vec<_> = std::fs::read_dir(GRAPHS)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "edges"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 9, "data files missing: {paths:?}");
    for path in paths {
        let text = std::fs::read_to_string(&path).unwrap();
        let g = Graph::parse_edge_list(&text).unwrap();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        check(&name, &g, stated_cop_number(&text));
    }
}

#[test]
fn trees_need_one_cop() {
    check("path1", &graph::path(1).unwrap(), 1);
    check("path9", &graph::path(9).unwrap(), 1);
    check("star7", &graph::tree(7, 1).unwrap(), 1);
    check("binary tree h4", &graph::tree(2, 4).unwrap(), 1);
    check("ternary tree h2", &graph::tree(3, 2).unwrap(), 1);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for n in [5, 12, 20] {
        // Random recursive tree: vertex v hangs under a random earlier vertex.
        let edges: Vec<_> = (1..n).map(|v| (rng.random_range(0..v), v)).collect();
        check("random tree", &Graph::from_edges(n, &edges).unwrap(), 1);
    }
}

#[test]
fn cycles_grids_complete_graphs() {
    check("C3", &graph::cycle(3).unwrap(), 1);
    for n in 4..=10 {
        check(&format!("C{n}"), &graph::cycle(n).unwrap(), 2);
    }
    for n in 1..=7 {
        check(&format!("K{n}"), &graph::complete(n).unwrap(), 1);
    }
    for (r, c) in [(2, 2), (2, 5), (3, 3), (3, 4), (4, 5), (5, 5)] {
        check(&format!("grid{r}x{c}"), &graph::grid(r, c).unwrap(), 2);
    }
}

#[test]
fn hypercubes_petersen_dodecahedron_heawood() {
    // Maamoun & Meyniel (1987): c(Q_d) = ceil((d + 1) / 2).
    for d in 1..=5u32 {
        let expected = (d as usize + 2) / 2;
        check(&format!("Q{d}"), &graph::hypercube(d).unwrap(), expected);
    }
    check("petersen", &graph::petersen(), 3);
    // Planar (so at most 3, Aigner & Fromme) with girth 5 and minimum degree 3 (so at least 3).
    check("dodecahedron", &graph::dodecahedron(), 3);
    // Heawood graph (LCF [5,-5]^7): incidence graph of the Fano plane, cop number q + 1 = 3.
    let heawood: Vec<_> = (0..14)
        .flat_map(|v| {
            let chord = if v % 2 == 0 {
                (v + 5) % 14
            } else {
                (v + 9) % 14
            };
            [(v, (v + 1) % 14), (v, chord)]
        })
        .collect();
    check("heawood", &Graph::from_edges(14, &heawood).unwrap(), 3);
}

#[test]
fn disconnected_graphs_sum_over_components() {
    // C4 + P3 + an isolated vertex: 2 + 1 + 1.
    let g = Graph::from_edges(8, &[(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6)]).unwrap();
    let result = cop_number(&g, &CopOptions::default()).unwrap();
    assert_eq!(result.cop_number, 4);
    let per: Vec<_> = result.components.iter().map(|c| c.cop_number).collect();
    assert_eq!(per, vec![2, 1, 1]);
    // The same answer from the game on the whole graph, without splitting it.
    assert!(
        !CopsGame::solve(&g, 3, &CopOptions::default())
            .unwrap()
            .cops_win()
    );
    assert!(
        CopsGame::solve(&g, 4, &CopOptions::default())
            .unwrap()
            .cops_win()
    );
}

/// Independent reference: naive value iteration over ordered cop tuples (no symmetry
/// reduction, no retrograde bookkeeping). Returns the capture time in cop moves, if the cops win.
fn naive_capture_time(g: &Graph, k: usize) -> Option<u32> {
    let n = g.node_count();
    let closed = |v: usize| {
        let mut l = g.neighbors(v).to_vec();
        l.push(v);
        l
    };
    let tuples: Vec<Vec<NodeId>> = (0..n.pow(k as u32))
        .map(|mut x| {
            (0..k)
                .map(|_| {
                    let c = x % n;
                    x /= n;
                    c
                })
                .collect()
        })
        .collect();
    let index = |t: &[NodeId]| t.iter().rev().fold(0, |acc, &c| acc * n + c);
    let moves = |t: &[NodeId]| -> Vec<usize> {
        let mut out = vec![Vec::new()];
        for &c in t {
            out = out
                .into_iter()
                .flat_map(|p: Vec<NodeId>| {
                    closed(c).into_iter().map(move |d| {
                        let mut q = p.clone();
                        q.push(d);
                        q
                    })
                })
                .collect();
        }
        out.iter().map(|q| index(q)).collect()
    };
    let all_moves: Vec<Vec<usize>> = tuples.iter().map(|t| moves(t)).collect();
    const NO: u32 = u32::MAX;
    // Plies to capture, cop-to-move and robber-to-move.
    let mut cop = vec![NO; tuples.len() * n];
    let mut rob = vec![NO; tuples.len() * n];
    for (i, t) in tuples.iter().enumerate() {
        for &c in t {
            cop[i * n + c] = 0;
            rob[i * n + c] = 0;
        }
    }
    for ply in 1.. {
        let (old_cop, old_rob) = (cop.clone(), rob.clone());
        for i in 0..tuples.len() {
            for r in 0..n {
                if cop[i * n + r] == NO && all_moves[i].iter().any(|&j| old_rob[j * n + r] != NO) {
                    cop[i * n + r] = ply;
                }
                if rob[i * n + r] == NO && closed(r).iter().all(|&s| old_cop[i * n + s] != NO) {
                    rob[i * n + r] = ply;
                }
            }
        }
        if cop == old_cop && rob == old_rob {
            break;
        }
    }
    (0..tuples.len())
        .filter_map(|i| {
            let row = &cop[i * n..i * n + n];
            (!row.contains(&NO)).then(|| *row.iter().max().unwrap_or(&0))
        })
        .min()
        .map(|plies| plies.div_ceil(2))
}

#[test]
fn retrograde_agrees_with_naive_value_iteration_on_random_graphs() {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let mut wins = [0usize; 2];
    for trial in 0..60 {
        let n = rng.random_range(1..=7);
        let p = rng.random_range(0.15..0.7);
        let edges: Vec<_> = (0..n)
            .flat_map(|u| (u + 1..n).map(move |v| (u, v)))
            .filter(|_| rng.random_bool(p))
            .collect();
        let g = Graph::from_edges(n, &edges).unwrap();
        for k in 1..=2 {
            let game = CopsGame::solve(&g, k, &CopOptions::default()).unwrap();
            let expected = naive_capture_time(&g, k);
            assert_eq!(
                game.capture_time(),
                expected,
                "trial {trial}, k={k}, {edges:?}"
            );
            wins[k - 1] += usize::from(expected.is_some());
        }
    }
    // Both outcomes occur, so the comparison is not vacuous.
    assert!(wins[0] > 5 && wins[0] < 55, "{wins:?}");
    assert!(wins[1] > wins[0], "{wins:?}");
}

fn assert_legal(g: &Graph, from: NodeId, to: NodeId) {
    assert!(
        from == to || g.has_edge(from, to),
        "illegal move {from} -> {to}"
    );
}

#[test]
fn winning_cops_catch_any_robber_in_time() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for g in [
        graph::dodecahedron(),
        graph::grid(4, 5).unwrap(),
        graph::petersen(),
    ] {
        let k = cop_number(&g, &CopOptions::default()).unwrap().cop_number;
        let game = CopsGame::solve(&g, k, &CopOptions::default()).unwrap();
        let limit = game.capture_time().unwrap();
        for play in 0..20 {
            let mut cops = game.cop_placement();
            // First play: the robber's own best strategy; later plays: a random robber.
            let mut robber = if play == 0 {
                game.robber_placement(&cops).unwrap()
            } else {
                rng.random_range(0..g.node_count())
            };
            let mut rounds = 0;
            while !cops.contains(&robber) {
                let next = game.cop_move(&cops, robber).unwrap();
                for (a, b) in cops.iter().zip(&next) {
                    assert_legal(&g, *a, *b);
                }
                cops = next;
                rounds += 1;
                if cops.contains(&robber) {
                    break;
                }
                let options: Vec<_> = g
                    .neighbors(robber)
                    .iter()
                    .copied()
                    .chain([robber])
                    .collect();
                robber = if play == 0 {
                    game.robber_move(&cops, robber).unwrap()
                } else {
                    options[rng.random_range(0..options.len())]
                };
                assert!(rounds <= limit, "no capture within {limit} rounds");
            }
            assert!(rounds <= limit);
            if play == 0 {
                assert_eq!(
                    rounds, limit,
                    "optimal robber is caught exactly at the minimax time"
                );
            }
        }
    }
}

#[test]
fn robber_escapes_too_few_cops_forever() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for (g, k) in [
        (graph::petersen(), 2),
        (graph::dodecahedron(), 2),
        (graph::cycle(7).unwrap(), 1),
    ] {
        let game = CopsGame::solve(&g, k, &CopOptions::default()).unwrap();
        assert!(!game.cops_win());
        for play in 0..10 {
            let mut cops = game.cop_placement();
            let mut robber = game.robber_placement(&cops).unwrap();
            assert_eq!(
                game.outcome(&cops, robber, Turn::Cops).unwrap(),
                Outcome::RobberEscapes
            );
            for _ in 0..200 {
                // Play 0: the cops' own pursuit; later plays: random cops.
                cops = if play == 0 {
                    game.cop_move(&cops, robber).unwrap()
                } else {
                    cops.iter()
                        .map(|&c| {
                            let opts: Vec<_> = g.neighbors(c).iter().copied().chain([c]).collect();
                            opts[rng.random_range(0..opts.len())]
                        })
                        .collect()
                };
                assert!(!cops.contains(&robber), "robber caught");
                let next = game.robber_move(&cops, robber).unwrap();
                assert_legal(&g, robber, next);
                robber = next;
                assert!(!cops.contains(&robber), "robber walked into a cop");
            }
        }
    }
}

#[test]
fn queries_reject_bad_positions() {
    let game = CopsGame::solve(&graph::cycle(5).unwrap(), 2, &CopOptions::default()).unwrap();
    assert!(game.outcome(&[0], 1, Turn::Cops).is_err());
    assert!(game.outcome(&[0, 9], 1, Turn::Cops).is_err());
    assert!(game.cop_move(&[0, 2], 7).is_err());
    assert!(game.cop_move(&[0, 2], 2).is_err());
    assert!(game.robber_move(&[0, 2], 0).is_err());
}
