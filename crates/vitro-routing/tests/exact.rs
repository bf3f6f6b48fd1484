//! The solvers against an exact optimum on small instances generated from a seed.
//!
//! The exact reference: every feasible route (each subset of customers in every order, the
//! cheapest feasible order kept), then a dynamic programme over subsets that partitions the
//! customers into routes at least total length. Exact for 6–8 customers, any windows.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vitro_routing::{Instance, Metric, Node, Options, Solver, solve};

/// A random instance: `n` customers on a 100 × 100 square, demands 1–9, capacity 15; with
/// `windows`, each customer has a window of width 40–120 around a reachable time and a service
/// time of 5, and the depot closes at 400.
fn generate(seed: u64, n: usize, windows: bool) -> Instance {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut nodes = vec![Node::untimed(50.0, 50.0, 0)];
    if windows {
        nodes[0].due = 400.0;
    }
    for _ in 0..n {
        let x = f64::from(rng.random_range(0..=100u32));
        let y = f64::from(rng.random_range(0..=100u32));
        let mut node = Node::untimed(x, y, rng.random_range(1..=9));
        if windows {
            let far = ((x - 50.0) * (x - 50.0) + (y - 50.0) * (y - 50.0)).sqrt();
            let centre = far + f64::from(rng.random_range(0..=200u32));
            let half = f64::from(rng.random_range(20..=60u32));
            node.ready = (centre - half).max(0.0);
            node.due = centre + half;
            node.service = 5.0;
        }
        nodes.push(node);
    }
    Instance::new(format!("gen-{seed}"), nodes, 15, None, Metric::Euclidean)
}

/// The optimal total length (all customers served; unlimited fleet).
fn exact(inst: &Instance) -> f64 {
    let n = inst.customers();
    let full = (1usize << n) - 1;
    // Cheapest feasible route over each subset, by trying every order.
    let mut route = vec![f64::INFINITY; full + 1];
    let mut order = Vec::new();
    fn permute(
        inst: &Instance,
        mask: usize,
        n: usize,
        order: &mut Vec<usize>,
        route: &mut [f64],
        used: usize,
    ) {
        if used != 0 && inst.route_feasible(order) {
            let c = inst.route_cost(order);
            if c < route[used] {
                route[used] = c;
            }
        }
        for k in 0..n {
            if mask & (1 << k) == 0 && used & (1 << k) == 0 {
                order.push(k + 1);
                // Prune: a prefix already late or over capacity cannot become feasible.
                if inst.route_load(order) <= inst.capacity && prefix_on_time(inst, order) {
                    permute(inst, mask, n, order, route, used | (1 << k));
                }
                order.pop();
            }
        }
    }
    permute(inst, 0, n, &mut order, &mut route, 0);
    let mut best = vec![f64::INFINITY; full + 1];
    best[0] = 0.0;
    for mask in 1..=full {
        let low = mask & mask.wrapping_neg();
        let mut sub = mask;
        while sub > 0 {
            if sub & low != 0 && route[sub].is_finite() {
                let c = route[sub] + best[mask ^ sub];
                if c < best[mask] {
                    best[mask] = c;
                }
            }
            sub = (sub - 1) & mask;
        }
    }
    best[full]
}

/// Whether the customers so far are each reached by their due time.
fn prefix_on_time(inst: &Instance, order: &[usize]) -> bool {
    let mut t = inst.nodes[0].ready;
    let mut prev = 0;
    for &c in order {
        let node = &inst.nodes[c];
        t += inst.dist(prev, c);
        if t > node.due + 1e-9 {
            return false;
        }
        t = t.max(node.ready) + node.service;
        prev = c;
    }
    true
}

/// Instances whose every customer can be served (the generator's windows may exclude some).
fn servable(inst: &Instance) -> bool {
    (1..inst.nodes.len()).all(|c| inst.route_feasible(&[c]))
}

struct Tally {
    cases: usize,
    optimal: usize,
    worst_gap: f64,
    gaps: f64,
}

fn compare(windows: bool, solver: Solver, seeds: std::ops::Range<u64>) -> Tally {
    let mut t = Tally {
        cases: 0,
        optimal: 0,
        worst_gap: 0.0,
        gaps: 0.0,
    };
    for seed in seeds {
        let n = 6 + (seed % 3) as usize;
        let inst = generate(seed, n, windows);
        if !servable(&inst) {
            continue;
        }
        let opt = exact(&inst);
        let sol = solve(&inst, &Options { solver, seed });
        sol.check(&inst)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert!(sol.unassigned.is_empty(), "seed {seed}");
        let gap = sol.gap_percent(opt);
        assert!(
            gap > -1e-6,
            "seed {seed}: below the optimum {opt}: {}",
            sol.cost
        );
        t.cases += 1;
        t.optimal += usize::from(gap < 1e-6);
        t.worst_gap = t.worst_gap.max(gap);
        t.gaps += gap;
    }
    eprintln!(
        "{solver:?}, windows {windows}: {} instances, {} optimal, mean gap {:.3}%, worst {:.3}%",
        t.cases,
        t.optimal,
        t.gaps / t.cases as f64,
        t.worst_gap
    );
    t
}

/// 40 CVRP instances of 6–8 customers: the local search (200 iterations) finds the optimum on
/// at least 38 and is never more than 2% above it.
#[test]
fn local_search_is_within_two_percent_of_the_optimum_on_cvrp() {
    let t = compare(false, Solver::LocalSearch { budget: 200 }, 0..40);
    assert_eq!(t.cases, 40);
    assert!(t.optimal >= 38, "{} of {} optimal", t.optimal, t.cases);
    assert!(t.worst_gap <= 2.0, "worst gap {:.3}%", t.worst_gap);
}

/// 40 CVRPTW instances (seeds 100–139, the servable ones; all 40 are): at least 95% optimal,
/// none more than 2% above.
#[test]
fn local_search_is_within_two_percent_of_the_optimum_with_time_windows() {
    let t = compare(true, Solver::LocalSearch { budget: 200 }, 100..140);
    assert!(t.cases >= 20, "only {} servable instances", t.cases);
    assert!(
        t.optimal * 100 >= t.cases * 95,
        "{} of {} optimal",
        t.optimal,
        t.cases
    );
    assert!(t.worst_gap <= 2.0, "worst gap {:.3}%", t.worst_gap);
}

/// The constructions are feasible and not far off: savings within 20%, the auction within 60%
/// (the auction is myopic: each round awards one customer to its cheapest insertion).
#[test]
fn savings_and_auction_are_feasible_and_near() {
    for windows in [false, true] {
        let s = compare(windows, Solver::Savings, 0..40);
        assert!(s.worst_gap <= 20.0, "savings worst gap {:.2}%", s.worst_gap);
        let a = compare(windows, Solver::Auction, 0..40);
        assert!(a.worst_gap <= 60.0, "auction worst gap {:.2}%", a.worst_gap);
    }
}

#[test]
fn the_same_seed_gives_the_same_solution() {
    let inst = generate(7, 8, true);
    let options = Options {
        solver: Solver::LocalSearch { budget: 100 },
        seed: 3,
    };
    let a = solve(&inst, &options);
    let b = solve(&inst, &options);
    assert_eq!(a, b);
    assert_eq!(a.cost.to_bits(), b.cost.to_bits());
}
