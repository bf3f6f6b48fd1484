//! Patrolling games: known optima, a brute-force grid over policies, Monte-Carlo agreement,
//! and the instance format.

use std::time::Instant;

use vitro_algo::graph::{self, Graph, NodeId};
use vitro_algo::patrol::{
    self, Instance, MonteCarloOptions, PatrolError, Patroller, Policy, SolveOptions, Target,
    TargetPosition, monte_carlo,
};

const GRAPHS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/graphs");

/// An instance with static targets `(vertex, value, deadline)` and one patroller.
fn instance(g: Graph, targets: &[(NodeId, f64, u32)]) -> Instance {
    let targets = targets
        .iter()
        .enumerate()
        .map(|(i, &(node, value, deadline))| Target {
            name: format!("t{i}"),
            position: TargetPosition::Static(node),
            value,
            deadline,
        })
        .collect();
    let patrollers = vec![Patroller { name: "p".into() }];
    Instance::new(g, targets, patrollers).unwrap()
}

/// Small instances (at most 5 vertices) and the grid resolution used to brute-force them.
fn small_instances() -> Vec<(&'static str, Instance, usize)> {
    let house = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (3, 0), (2, 4), (3, 4)]).unwrap();
    vec![
        (
            "path3, both ends, D=2",
            instance(graph::path(3).unwrap(), &[(0, 1.0, 2), (2, 1.0, 2)]),
            12,
        ),
        (
            "triangle, all vertices, D=1",
            instance(
                graph::complete(3).unwrap(),
                &[(0, 1.0, 1), (1, 1.0, 1), (2, 1.0, 1)],
            ),
            6,
        ),
        (
            "star K1,3, leaves, D=2",
            instance(
                graph::tree(3, 1).unwrap(),
                &[(1, 1.0, 2), (2, 1.0, 2), (3, 1.0, 2)],
            ),
            6,
        ),
        (
            "path4, ends, values 1 and 2, D=3",
            instance(graph::path(4).unwrap(), &[(0, 1.0, 3), (3, 2.0, 3)]),
            6,
        ),
        (
            "cycle5, two targets, D=2 and 3",
            instance(graph::cycle(5).unwrap(), &[(0, 1.0, 2), (2, 1.0, 3)]),
            2,
        ),
        (
            "star K1,4, two leaves, values 1 and 2",
            instance(graph::tree(4, 1).unwrap(), &[(1, 1.0, 2), (2, 2.0, 3)]),
            4,
        ),
        (
            "house, roof and a floor corner, D=2",
            instance(house, &[(0, 1.0, 2), (4, 1.0, 2)]),
            2,
        ),
        (
            // The ends are 4 apart: guarding the valuable end means giving up the other.
            "path5, ends, values 1 and 2, D=3 and 4",
            instance(graph::path(5).unwrap(), &[(0, 1.0, 3), (4, 2.0, 4)]),
            4,
        ),
    ]
}

/// Independent evaluation (not the library's): worst `value · (1 − P)` over targets and
/// support starts, for rows given per support vertex as (successor, probability).
fn brute_loss(inst: &Instance, support: &[NodeId], rows: &[Vec<(NodeId, f64)>]) -> f64 {
    let n = inst.graph.node_count();
    let mut worst: f64 = 0.0;
    for target in &inst.targets {
        let TargetPosition::Static(t) = target.position else {
            unreachable!("static targets only")
        };
        // q[x]: probability of standing on t within the remaining steps, starting at x.
        let mut q = vec![0.0; n];
        for _ in 0..target.deadline {
            let mut next = vec![0.0; n];
            for (i, &x) in support.iter().enumerate() {
                next[x] = rows[i]
                    .iter()
                    .map(|&(y, p)| p * if y == t { 1.0 } else { q[y] })
                    .sum();
            }
            q = next;
        }
        for &h in support {
            worst = worst.max(target.value * (1.0 - q[h]));
        }
    }
    worst
}

/// Connected vertex subsets of a small graph, by bitmask.
fn connected_subsets(g: &Graph) -> Vec<Vec<NodeId>> {
    let n = g.node_count();
    (1u32..(1 << n))
        .filter_map(|mask| {
            let set: Vec<NodeId> = (0..n).filter(|&v| mask & (1 << v) != 0).collect();
            let mut seen = vec![set[0]];
            let mut i = 0;
            while i < seen.len() {
                for &w in g.neighbors(seen[i]) {
                    if mask & (1 << w) != 0 && !seen.contains(&w) {
                        seen.push(w);
                    }
                }
                i += 1;
            }
            (seen.len() == set.len()).then_some(set)
        })
        .collect()
}

/// All ways to split `m` units over `r` slots.
fn compositions(m: usize, r: usize) -> Vec<Vec<usize>> {
    if r == 1 {
        return vec![vec![m]];
    }
    (0..=m)
        .flat_map(|first| {
            compositions(m - first, r - 1)
                .into_iter()
                .map(move |mut rest| {
                    rest.insert(0, first);
                    rest
                })
        })
        .collect()
}

/// The best loss over every policy whose probabilities are multiples of `1/m`, on every
/// connected support.
fn grid_minimum(inst: &Instance, m: usize) -> f64 {
    let g = &inst.graph;
    let mut best = f64::INFINITY;
    for support in connected_subsets(g) {
        // Each row's successors: itself and its neighbours inside the support.
        let succ: Vec<Vec<NodeId>> = support
            .iter()
            .map(|&v| {
                let mut s: Vec<NodeId> = g
                    .neighbors(v)
                    .iter()
                    .copied()
                    .filter(|w| support.contains(w))
                    .collect();
                s.push(v);
                s
            })
            .collect();
        let choices: Vec<Vec<Vec<usize>>> = succ.iter().map(|s| compositions(m, s.len())).collect();
        let mut digits = vec![0usize; support.len()];
        loop {
            let rows: Vec<Vec<(NodeId, f64)>> = (0..support.len())
                .map(|i| {
                    succ[i]
                        .iter()
                        .zip(&choices[i][digits[i]])
                        .map(|(&w, &k)| (w, k as f64 / m as f64))
                        .collect()
                })
                .collect();
            best = best.min(brute_loss(inst, &support, &rows));
            let mut i = 0;
            while i < digits.len() {
                digits[i] += 1;
                if digits[i] < choices[i].len() {
                    break;
                }
                digits[i] = 0;
                i += 1;
            }
            if i == digits.len() {
                break;
            }
        }
    }
    best
}

fn policy_rows(policy: &Policy) -> Vec<Vec<(NodeId, f64)>> {
    policy
        .support()
        .iter()
        .map(|&v| policy.moves(v).unwrap().to_vec())
        .collect()
}

#[test]
fn exact_solutions_match_a_brute_force_grid() {
    for (name, inst, m) in small_instances() {
        let start = Instant::now();
        let solution = patrol::solve(&inst).unwrap();
        let solve_time = start.elapsed();
        let grid = grid_minimum(&inst, m);
        eprintln!(
            "{name:>34}: value {:.6} (lower bound {:.6}, exact {}), grid 1/{m}: {grid:.6}; {} boxes, {} + {} LPs (max {}x{}), {solve_time:.2?}",
            solution.value,
            solution.lower_bound,
            solution.exact,
            solution.stats.nodes,
            solution.stats.lp.solves,
            solution.stats.bnb_lp.solves,
            solution
                .stats
                .bnb_lp
                .max_variables
                .max(solution.stats.lp.max_variables),
            solution
                .stats
                .bnb_lp
                .max_constraints
                .max(solution.stats.lp.max_constraints),
        );
        assert!(solution.exact, "{name}: not certified");
        // The reported value is the policy's true value (independent evaluation).
        let own = brute_loss(
            &inst,
            solution.policies[0].support(),
            &policy_rows(&solution.policies[0]),
        );
        assert!(
            (own - solution.value).abs() < 1e-9,
            "{name}: {own} vs {}",
            solution.value
        );
        // Never worse than any grid policy ...
        assert!(
            solution.value <= grid + 1e-9,
            "{name}: grid beats the optimum"
        );
        // ... and the grid comes within its resolution: rounding the optimum to the grid moves
        // each row by less than r/(2m) in total variation, each capture probability by at most
        // deadline times that.
        let r = (0..inst.graph.node_count())
            .map(|v| inst.graph.neighbors(v).len() + 1)
            .max()
            .unwrap();
        let slack = inst
            .targets
            .iter()
            .map(|t| t.value * f64::from(t.deadline) * r as f64 / (2.0 * m as f64))
            .fold(0.0, f64::max);
        assert!(
            grid - solution.value <= slack + 1e-9,
            "{name}: grid too far"
        );
        assert!(solution.value >= solution.lower_bound - 1e-12);
    }
}

#[test]
fn rational_optima_are_hit_exactly_by_a_fine_enough_grid() {
    // Optima with probabilities in {0, 1/3, 1/2, 1}: the grid contains them.
    for (name, inst, m) in small_instances().into_iter().take(3) {
        let solution = patrol::solve(&inst).unwrap();
        let grid = grid_minimum(&inst, m);
        assert!(
            (grid - solution.value).abs() < 1e-5,
            "{name}: {grid} vs {}",
            solution.value
        );
    }
    let solution = patrol::solve(&small_instances()[0].1).unwrap();
    assert!((solution.value - 0.5).abs() < 1e-5);
    assert!((solution.capture_probability - 0.5).abs() < 1e-5);
}

#[test]
fn a_single_static_target_is_always_caught() {
    for g in [
        graph::path(4).unwrap(),
        graph::grid(3, 3).unwrap(),
        graph::petersen(),
    ] {
        for deadline in [1, 3] {
            let inst = instance(g.clone(), &[(2, 5.0, deadline)]);
            let solution = patrol::solve(&inst).unwrap();
            assert!(solution.exact);
            assert_eq!(solution.value, 0.0);
            assert_eq!(solution.capture_probability, 1.0);
            assert!(solution.policies[0].support().contains(&2));
        }
    }
}

#[test]
fn monte_carlo_agrees_with_the_computed_values() {
    let options = MonteCarloOptions {
        trials: 20_000,
        seed: 42,
        confidence: 0.99,
    };
    for (name, inst, _) in small_instances() {
        let solution = patrol::solve(&inst).unwrap();
        // The optimum, and a non-optimal policy: the uniform random walk on the whole graph.
        let g = &inst.graph;
        let walk = Policy::new(
            g,
            (0..g.node_count())
                .map(|v| {
                    let succ: Vec<NodeId> = g.neighbors(v).iter().copied().chain([v]).collect();
                    let p = 1.0 / succ.len() as f64;
                    (v, succ.into_iter().map(|w| (w, p)).collect())
                })
                .collect(),
        )
        .unwrap();
        for policy in [&solution.policies[0], &walk] {
            let exact = policy.attacks(&inst).unwrap();
            let report = monte_carlo(&inst, policy, &options).unwrap();
            assert_eq!(report.attacks.len(), exact.len());
            for (estimate, truth) in report.attacks.iter().zip(&exact) {
                assert_eq!((estimate.target, estimate.from), (truth.target, truth.from));
                let (lo, hi) = estimate.interval;
                assert!(
                    lo <= truth.capture_probability && truth.capture_probability <= hi,
                    "{name}: {} not in [{lo}, {hi}]",
                    truth.capture_probability
                );
                // Tight enough to mean something.
                assert!(hi - lo < 0.05);
            }
            let value = policy.value(&inst).unwrap();
            let (lo, hi) = report.value_interval;
            assert!(
                lo <= value && value <= hi,
                "{name}: value {value} not in [{lo}, {hi}]"
            );
        }
    }
}

#[test]
fn toml_instances_solve_like_built_ones() {
    let text = r#"
        # Two ends of a path of three.
        [graph]
        edges = [[0, 1], [1, 2]]

        [[target]]
        name = "west"
        node = 0
        value = 1
        deadline = 2

        [[target]]
        name = "east"
        node = 2
        value = 1.0
        deadline = 2

        [[patroller]]
        name = "ugv"
    "#;
    let parsed = Instance::from_toml_str(text).unwrap();
    let built = instance(graph::path(3).unwrap(), &[(0, 1.0, 2), (2, 1.0, 2)]);
    assert_eq!(parsed.graph, built.graph);
    let a = patrol::solve(&parsed).unwrap();
    let b = patrol::solve(&built).unwrap();
    assert_eq!(a.value, b.value);
    assert_eq!(a.policies, b.policies);
}

#[test]
fn instance_files_can_point_at_edge_lists() {
    let dir = std::env::temp_dir().join(format!("vitro-patrol-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cycle.toml");
    let edges = format!("{GRAPHS}/cycle5.edges");
    std::fs::write(
        &file,
        format!(
            "[graph]\nfile = {edges:?}\n[[target]]\nnode = 0\nvalue = 1\ndeadline = 2\n[[target]]\nnode = 2\nvalue = 1\ndeadline = 3\n[[patroller]]\n"
        ),
    )
    .unwrap();
    let loaded = Instance::load(&file).unwrap();
    assert_eq!(loaded.graph, graph::cycle(5).unwrap());
    let missing = dir.join("missing.toml");
    std::fs::write(&missing, "[graph]\nfile = \"nope.edges\"\n").unwrap();
    match Instance::load(&missing) {
        Err(PatrolError::Parse {
            line: 2, column: 8, ..
        }) => {}
        other => panic!("expected an error at 2:8, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn policies_are_validated() {
    let g = graph::path(3).unwrap();
    // Jumps over a vertex.
    assert!(Policy::new(&g, vec![(0, vec![(2, 1.0)]), (2, vec![(2, 1.0)])]).is_err());
    // Leaves its support.
    assert!(Policy::new(&g, vec![(0, vec![(1, 1.0)])]).is_err());
    // Does not sum to one.
    assert!(Policy::new(&g, vec![(1, vec![(1, 0.5)])]).is_err());
    let stay = Policy::stay(1);
    assert_eq!(stay.next(1, 0.7), Some(1));
    assert_eq!(stay.recurrent_classes(), vec![vec![1]]);
}

#[test]
fn a_budget_cut_search_reports_an_honest_bound() {
    // Four corners of a 3x3 grid: 218 connected supports, too many boxes for a budget of 50.
    let inst = instance(
        graph::grid(3, 3).unwrap(),
        &[(0, 1.0, 4), (2, 1.0, 4), (6, 1.0, 4), (8, 1.0, 4)],
    );
    let options = SolveOptions {
        max_nodes: 50,
        local_searches: 2,
        local_iterations: 30,
        ..SolveOptions::default()
    };
    let solution = patrol::solve_with(&inst, &options).unwrap();
    assert!(!solution.exact);
    assert!(solution.lower_bound < solution.value - options.tolerance);
    // The value is still the returned policy's true value, and beats the uniform random walk.
    assert_eq!(solution.value, solution.policies[0].value(&inst).unwrap());
    let walk = Policy::new(
        &inst.graph,
        (0..9)
            .map(|v| {
                let succ: Vec<NodeId> =
                    inst.graph.neighbors(v).iter().copied().chain([v]).collect();
                let p = 1.0 / succ.len() as f64;
                (v, succ.into_iter().map(|w| (w, p)).collect())
            })
            .collect(),
    )
    .unwrap();
    assert!(solution.value < walk.value(&inst).unwrap());
}

#[test]
fn inconsistent_instances_are_rejected() {
    let g = graph::path(3).unwrap();
    let target = |node, value, deadline| Target {
        name: "t".into(),
        position: TargetPosition::Static(node),
        value,
        deadline,
    };
    let one = || vec![Patroller { name: "p".into() }];
    for (targets, patrollers) in [
        (vec![target(5, 1.0, 2)], one()),
        (vec![target(0, 0.0, 2)], one()),
        (vec![target(0, f64::NAN, 2)], one()),
        (vec![target(0, 1.0, 0)], one()),
        (vec![], one()),
        (vec![target(0, 1.0, 2)], vec![]),
    ] {
        assert!(matches!(
            Instance::new(g.clone(), targets, patrollers),
            Err(PatrolError::InvalidInstance(_))
        ));
    }
    let jumpy = Target {
        position: TargetPosition::Schedule(vec![0, 2]),
        ..target(0, 1.0, 2)
    };
    assert!(Instance::new(g, vec![jumpy], one()).is_err());
}
