//! Patrolling moving targets (convoys on periodic schedules): stationary against
//! time-dependent policies, an independent brute force over discretised policies, Monte-Carlo
//! agreement, and teams of patrollers.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vitro_algo::graph::{self, Graph, NodeId};
use vitro_algo::patrol::{
    self, Instance, MonteCarloOptions, Patroller, Policy, SolveOptions, Target, TargetPosition,
    monte_carlo,
};

fn target(position: TargetPosition, value: f64, deadline: u32) -> Target {
    Target {
        name: "t".into(),
        position,
        value,
        deadline,
    }
}

fn instance(g: Graph, targets: Vec<Target>, patrollers: usize) -> Instance {
    let patrollers = (0..patrollers)
        .map(|i| Patroller {
            name: format!("p{i}"),
        })
        .collect();
    Instance::new(g, targets, patrollers).unwrap()
}

fn time_dependent() -> SolveOptions {
    SolveOptions {
        time_dependent: true,
        ..SolveOptions::default()
    }
}

/// A random closed walk of `len` steps (staying allowed) on `g`, from a random vertex.
fn random_schedule(g: &Graph, len: usize, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
    loop {
        let mut walk = vec![rng.random_range(0..g.node_count())];
        for _ in 1..len {
            let &at = walk.last().unwrap();
            let mut options: Vec<NodeId> = g.neighbors(at).to_vec();
            options.push(at);
            walk.push(options[rng.random_range(0..options.len())]);
        }
        let (first, last) = (walk[0], walk[len - 1]);
        if first == last || g.has_edge(first, last) {
            return walk;
        }
    }
}

/// Random small instances: a graph of 3 or 4 vertices, a convoy and maybe a static target.
fn random_instances(count: usize) -> Vec<Instance> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let graphs = [
        graph::path(3).unwrap(),
        graph::cycle(3).unwrap(),
        graph::path(4).unwrap(),
        graph::tree(3, 1).unwrap(),
    ];
    (0..count)
        .map(|i| {
            let g = graphs[i % graphs.len()].clone();
            let period = rng.random_range(2..=3);
            let mut targets = vec![target(
                TargetPosition::Schedule(random_schedule(&g, period, &mut rng)),
                1.0 + f64::from(rng.random_range(0..2u8)),
                rng.random_range(1..=2),
            )];
            if rng.random_bool(0.5) {
                targets.push(target(
                    TargetPosition::Static(rng.random_range(0..g.node_count())),
                    1.0,
                    rng.random_range(1..=3),
                ));
            }
            instance(g, targets, 1)
        })
        .collect()
}

/// Independent evaluation: the worst `value · (1 − P)` over targets, phases and support
/// starts, for a policy given as a row function `(vertex, phase) -> [(next, p)]`.
fn brute_loss(
    inst: &Instance,
    support: &[NodeId],
    period: usize,
    rows: &dyn Fn(NodeId, usize) -> Vec<(NodeId, f64)>,
) -> f64 {
    let n = inst.graph.node_count();
    let mut worst: f64 = 0.0;
    for t in &inst.targets {
        let pos = |step: usize| t.position.at(step).unwrap();
        for phase in 0..period {
            // q[x]: probability of catching the target within the remaining steps from x,
            // computed backwards from the attack's last step.
            let d = t.deadline as usize;
            let mut q = vec![0.0; n];
            for s in (1..=d).rev() {
                let mut next = vec![0.0; n];
                for &x in support {
                    next[x] = rows(x, phase + s - 1)
                        .iter()
                        .map(|&(y, p)| p * if y == pos(phase + s) { 1.0 } else { q[y] })
                        .sum();
                }
                q = next;
            }
            for &h in support {
                worst = worst.max(t.value * (1.0 - q[h]));
            }
        }
    }
    worst
}

fn policy_loss(inst: &Instance, policy: &Policy) -> f64 {
    let period = inst.period().unwrap();
    brute_loss(inst, policy.support(), period, &|v, phase| {
        policy.moves_at(v, phase).unwrap().to_vec()
    })
}

#[test]
fn time_dependent_policies_catch_at_least_as_often_as_stationary_ones() {
    let mut certified = 0;
    for (i, inst) in random_instances(12).iter().enumerate() {
        let stationary = patrol::solve(inst).unwrap();
        let timed = patrol::solve_with(inst, &time_dependent()).unwrap();
        eprintln!(
            "instance {i}: stationary {:.6} (exact {}), time-dependent {:.6} (exact {})",
            stationary.value, stationary.exact, timed.value, timed.exact
        );
        // In attacker-gain terms time-dependent ≤ stationary; in capture terms the reverse.
        assert!(timed.value <= stationary.value + 1e-9, "instance {i}");
        assert!(
            timed.capture_probability + 1e-9 >= stationary.capture_probability || {
                // With unequal values the worst capture probability need not order; the value does.
                inst.targets.iter().any(|t| t.value != 1.0)
            }
        );
        // Reported values are the policies' true values (independent evaluation).
        for s in [&stationary, &timed] {
            let own = policy_loss(inst, &s.policies[0]);
            assert!(
                (own - s.value).abs() < 1e-9,
                "instance {i}: {own} vs {}",
                s.value
            );
            assert!(s.value >= s.lower_bound - 1e-12);
        }
        certified += usize::from(stationary.exact && timed.exact);
        assert_eq!(timed.policies[0].phases(), inst.period().unwrap());
    }
    // Most of these tiny instances certify within the default box budget.
    assert!(certified >= 9, "{certified} certified");
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

/// The best loss over every policy (stationary if `phases == 1`, else one row per phase) with
/// probabilities on the `1/m` grid, on every connected support of a graph of at most 5
/// vertices.
fn grid_minimum(inst: &Instance, m: usize, phases: usize) -> f64 {
    let g = &inst.graph;
    let n = g.node_count();
    let period = inst.period().unwrap();
    let mut best = f64::INFINITY;
    for mask in 1u32..(1 << n) {
        let support: Vec<NodeId> = (0..n).filter(|&v| mask & (1 << v) != 0).collect();
        let within = |w: &NodeId| mask & (1 << w) != 0;
        // Connected?
        let mut seen = vec![support[0]];
        let mut k = 0;
        while k < seen.len() {
            for w in g.neighbors(seen[k]).iter().filter(|w| within(w)) {
                if !seen.contains(w) {
                    seen.push(*w);
                }
            }
            k += 1;
        }
        if seen.len() != support.len() {
            continue;
        }
        let succ: Vec<Vec<NodeId>> = support
            .iter()
            .map(|&v| {
                g.neighbors(v)
                    .iter()
                    .copied()
                    .filter(within)
                    .chain([v])
                    .collect()
            })
            .collect();
        let rows = support.len() * phases;
        let choices: Vec<Vec<Vec<usize>>> = (0..rows)
            .map(|r| compositions(m, succ[r % support.len()].len()))
            .collect();
        let mut digits = vec![0usize; rows];
        loop {
            let row_of = |v: NodeId, phase: usize| {
                let i = support.binary_search(&v).unwrap();
                let r = (phase % phases) * support.len() + i;
                succ[i]
                    .iter()
                    .zip(&choices[r][digits[r]])
                    .map(|(&w, &c)| (w, c as f64 / m as f64))
                    .collect()
            };
            best = best.min(brute_loss(inst, &support, period, &row_of));
            let mut i = 0;
            while i < rows {
                digits[i] += 1;
                if digits[i] < choices[i].len() {
                    break;
                }
                digits[i] = 0;
                i += 1;
            }
            if i == rows {
                break;
            }
        }
    }
    best
}

#[test]
fn computed_values_match_a_brute_force_grid() {
    // A convoy shuttling along a path of three, and a static post at the far end.
    let shuttle = instance(
        graph::path(3).unwrap(),
        vec![
            target(TargetPosition::Schedule(vec![0, 1]), 1.0, 2),
            target(TargetPosition::Static(2), 1.0, 2),
        ],
        1,
    );
    // A convoy circling a 4-cycle.
    let circling = instance(
        graph::cycle(4).unwrap(),
        vec![
            target(TargetPosition::Schedule(vec![0, 1, 2, 3]), 1.0, 2),
            target(TargetPosition::Static(2), 2.0, 3),
        ],
        1,
    );
    for (name, inst, m_stationary, m_timed) in
        [("shuttle", &shuttle, 6, 2), ("circling", &circling, 3, 0)]
    {
        let r = 1
            + (0..inst.graph.node_count())
                .map(|v| inst.graph.neighbors(v).len())
                .max()
                .unwrap();
        for (phases, m) in [(1, m_stationary), (inst.period().unwrap(), m_timed)] {
            if m == 0 {
                continue;
            }
            let options = SolveOptions {
                time_dependent: phases > 1,
                ..SolveOptions::default()
            };
            let solution = patrol::solve_with(inst, &options).unwrap();
            let grid = grid_minimum(inst, m, phases);
            eprintln!(
                "{name}, {phases} phase(s): value {:.6} (exact {}), grid 1/{m}: {grid:.6}",
                solution.value, solution.exact
            );
            assert!(solution.value <= grid + 1e-9, "{name}: the grid beats it");
            let slack = inst
                .targets
                .iter()
                .map(|t| t.value * f64::from(t.deadline) * r as f64 / (2.0 * m as f64))
                .fold(0.0, f64::max);
            assert!(
                grid - solution.value <= slack + 1e-9,
                "{name}: grid too far"
            );
            if solution.exact {
                assert!(solution.value - solution.lower_bound <= 1e-5);
            }
        }
    }
}

#[test]
fn monte_carlo_agrees_with_moving_target_values() {
    let options = MonteCarloOptions {
        trials: 20_000,
        seed: 3,
        confidence: 0.99,
    };
    for inst in random_instances(4) {
        for solve_options in [SolveOptions::default(), time_dependent()] {
            let solution = patrol::solve_with(&inst, &solve_options).unwrap();
            let policy = &solution.policies[0];
            let exact = policy.attacks(&inst).unwrap();
            let report = monte_carlo(&inst, policy, &options).unwrap();
            assert_eq!(report.attacks.len(), exact.len());
            for (estimate, truth) in report.attacks.iter().zip(&exact) {
                assert_eq!(
                    (estimate.target, estimate.phase, estimate.from),
                    (truth.target, truth.phase, truth.from)
                );
                let (lo, hi) = estimate.interval;
                assert!(lo <= truth.capture_probability && truth.capture_probability <= hi);
                assert!(hi - lo < 0.06);
            }
            let (lo, hi) = report.value_interval;
            assert!(lo <= solution.value && solution.value <= hi);
        }
    }
}

#[test]
fn a_convoy_on_a_deterministic_loop_is_escorted() {
    // On a cycle the convoy's next vertex is a function of its vertex: riding along is a
    // stationary policy, but the attacker may also strike when the patroller is off the convoy.
    // With deadline ≥ the cycle length the patroller catches everything by circling too.
    let inst = instance(
        graph::cycle(3).unwrap(),
        vec![target(TargetPosition::Schedule(vec![0, 1, 2]), 1.0, 3)],
        1,
    );
    let solution = patrol::solve(&inst).unwrap();
    assert!(solution.exact);
    assert!(solution.value < 1e-9, "{}", solution.value);
    // A single static target is always caught, with moving ones next to it or not.
    let post = instance(
        graph::path(4).unwrap(),
        vec![target(TargetPosition::Static(1), 3.0, 1)],
        1,
    );
    let solution = patrol::solve_with(&post, &time_dependent()).unwrap();
    assert_eq!(solution.capture_probability, 1.0);
}

#[test]
fn teams_split_far_apart_targets() {
    // A post and a convoy shuttling 4-3-4-3 far from it, attacks of one step: one patroller
    // guards only one of them, two guard both, if the convoy's guard can follow the phase.
    let targets = || {
        vec![
            target(TargetPosition::Static(0), 1.0, 1),
            target(TargetPosition::Schedule(vec![4, 3]), 1.0, 1),
        ]
    };
    let alone = patrol::solve(&instance(graph::path(5).unwrap(), targets(), 1)).unwrap();
    assert!((alone.value - 1.0).abs() < 1e-9);
    let inst = instance(graph::path(5).unwrap(), targets(), 2);
    // Stationary: the convoy's guard must stay on 3 at one phase and leave it at the other.
    let stationary = patrol::solve(&inst).unwrap();
    assert!(
        (stationary.value - 0.5).abs() < 1e-6,
        "{}",
        stationary.value
    );
    let team = patrol::solve_with(&inst, &time_dependent()).unwrap();
    assert!(team.value < 1e-9, "{}", team.value);
    assert_eq!(team.policies.len(), 2);
    assert_eq!(
        patrol::team_value(&inst, &team.policies).unwrap(),
        team.value
    );
    // Threats name every target and phase.
    assert_eq!(team.threats.len(), 2 * inst.period().unwrap());
}
