//! Large neighbourhood search: ruin part of the solution, recreate it by regret insertion, then
//! run the local search; keep the best solution seen.
//!
//! - P. Shaw, "Using constraint programming and local search methods to solve vehicle routing
//!   problems", CP 1998 (removal of related customers, then re-insertion);
//! - S. Ropke and D. Pisinger, "An adaptive large neighborhood search heuristic for the pickup
//!   and delivery problem with time windows", *Transportation Science* 40(4), 455–472, 2006
//!   (random and Shaw removal, regret-2 insertion, the removal-size range);
//! - G. Dueck, "New optimization heuristics: the great deluge algorithm and the record-to-record
//!   travel", *J. Comput. Phys.* 104, 86–92, 1993 (the acceptance rule: a new current solution
//!   is kept while it is within 1% of the record).
//!
//! Unlike Ropke & Pisinger's adaptive version, the two removals are drawn with equal
//! probability and the acceptance needs no exponentials, so the search gives the same bits on
//! every machine.

use crate::Instance;
use crate::moves::improve;
use crate::solution::{Solution, Stats, best_insertion};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Record-to-record deviation: a candidate becomes the current solution if its cost is below
/// the best cost times `1 + DEVIATION`.
const DEVIATION: f64 = 0.01;
/// Shaw removal's randomisation exponent (Ropke & Pisinger's `p`).
const SHAW_P: u32 = 6;

/// Runs `budget` ruin-and-recreate iterations from `start` (the savings solution, usually).
#[must_use]
pub(crate) fn lns(inst: &Instance, start: Solution, budget: u64, seed: u64) -> Solution {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let unassigned = start.unassigned.clone();
    let mut current = start.routes;
    improve(inst, &mut current);
    let mut current_key = key(inst, &current);
    let mut best = current.clone();
    let mut best_key = current_key;
    let mut stats = Stats::default();
    let served: usize = current.iter().map(Vec::len).sum();
    if served == 0 {
        return Solution::new(inst, best, unassigned, stats);
    }
    let q_min = served.min(4);
    let q_max = served.min((served * 3 / 10).max(q_min).max(1));
    for _ in 0..budget {
        stats.iterations += 1;
        let q = rng.random_range(q_min..=q_max);
        let mut routes = current.clone();
        let removed = if rng.random_bool(0.5) {
            random_removal(&mut routes, q, &mut rng)
        } else {
            shaw_removal(inst, &mut routes, q, &mut rng)
        };
        routes.retain(|r| !r.is_empty());
        if !regret_insertion(inst, &mut routes, removed) {
            continue;
        }
        improve(inst, &mut routes);
        let k = key(inst, &routes);
        if less(k, best_key) {
            best = routes.clone();
            best_key = k;
            stats.improvements += 1;
        }
        if less(k, current_key) || (k.0 <= best_key.0 && k.1 < best_key.1 * (1.0 + DEVIATION)) {
            current = routes;
            current_key = k;
        }
    }
    Solution::new(inst, best, unassigned, stats)
}

/// Vehicles over the fleet, then length.
fn key(inst: &Instance, routes: &[Vec<usize>]) -> (usize, f64) {
    let over = inst.vehicles.map_or(0, |v| routes.len().saturating_sub(v));
    (over, inst.cost(routes))
}

fn less(a: (usize, f64), b: (usize, f64)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1 - 1e-9)
}

fn take(routes: &mut [Vec<usize>], c: usize) {
    for r in routes.iter_mut() {
        r.retain(|&x| x != c);
    }
}

fn random_removal(routes: &mut [Vec<usize>], q: usize, rng: &mut ChaCha8Rng) -> Vec<usize> {
    let mut all: Vec<usize> = routes.iter().flatten().copied().collect();
    let mut removed = Vec::with_capacity(q);
    for _ in 0..q.min(all.len()) {
        let c = all.swap_remove(rng.random_range(0..all.len()));
        removed.push(c);
    }
    for &c in &removed {
        take(routes, c);
    }
    removed
}

/// Removes customers related to a random seed customer: close in space and, with time windows,
/// in ready time.
fn shaw_removal(
    inst: &Instance,
    routes: &mut [Vec<usize>],
    q: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<usize> {
    let all: Vec<usize> = routes.iter().flatten().copied().collect();
    let max_d = all
        .iter()
        .flat_map(|&a| all.iter().map(move |&b| (a, b)))
        .map(|(a, b)| inst.dist(a, b))
        .fold(1e-9, f64::max);
    let horizon = inst.nodes[0].due;
    let related = |a: usize, b: usize| {
        let mut r = inst.dist(a, b) / max_d;
        if inst.has_time_windows() && horizon.is_finite() && horizon > 0.0 {
            r += (inst.nodes[a].ready - inst.nodes[b].ready).abs() / horizon;
        }
        r
    };
    let mut removed = vec![all[rng.random_range(0..all.len())]];
    let mut left: Vec<usize> = all.iter().copied().filter(|&c| c != removed[0]).collect();
    while removed.len() < q && !left.is_empty() {
        let r = removed[rng.random_range(0..removed.len())];
        left.sort_by(|&a, &b| related(r, a).total_cmp(&related(r, b)).then(a.cmp(&b)));
        let y: f64 = rng.random();
        let idx = (pow(y, SHAW_P) * left.len() as f64) as usize;
        removed.push(left.remove(idx.min(left.len() - 1)));
    }
    for &c in &removed {
        take(routes, c);
    }
    removed
}

/// `y^p` by multiplication (the same bits everywhere).
fn pow(y: f64, p: u32) -> f64 {
    (0..p).fold(1.0, |acc, _| acc * y)
}

/// Regret-2 insertion: repeatedly inserts the customer whose best place is most better than
/// its second best (a customer with one option first), at its best place. A new route is an
/// option while the fleet has a free vehicle. False if some customer fits nowhere.
fn regret_insertion(inst: &Instance, routes: &mut Vec<Vec<usize>>, mut todo: Vec<usize>) -> bool {
    let mut buf = Vec::new();
    todo.sort_unstable();
    while !todo.is_empty() {
        let can_open = inst.vehicles.is_none_or(|v| routes.len() < v);
        let loads: Vec<u64> = routes.iter().map(|r| inst.route_load(r)).collect();
        // (regret, -best cost) maximised; then the lowest index (todo is sorted).
        let mut choice: Option<(usize, f64, f64, usize, usize)> = None;
        for (k, &c) in todo.iter().enumerate() {
            let mut first: Option<(f64, usize, usize)> = None;
            let mut second = f64::INFINITY;
            for (ri, r) in routes.iter().enumerate() {
                if let Some((cost, pos)) = best_insertion(inst, r, loads[ri], c, &mut buf) {
                    match first {
                        Some((b, _, _)) if cost >= b => second = second.min(cost),
                        _ => {
                            if let Some((b, _, _)) = first {
                                second = second.min(b);
                            }
                            first = Some((cost, ri, pos));
                        }
                    }
                }
            }
            if can_open && inst.route_feasible(&[c]) {
                let cost = 2.0 * inst.dist(0, c);
                match first {
                    Some((b, _, _)) if cost >= b => second = second.min(cost),
                    _ => {
                        if let Some((b, _, _)) = first {
                            second = second.min(b);
                        }
                        first = Some((cost, routes.len(), 0));
                    }
                }
            }
            let Some((cost, ri, pos)) = first else {
                return false;
            };
            let regret = second - cost;
            let better = match choice {
                None => true,
                Some((_, r, bc, _, _)) => regret > r || (regret == r && cost < bc),
            };
            if better {
                choice = Some((k, regret, cost, ri, pos));
            }
        }
        let Some((k, _, _, ri, pos)) = choice else {
            return false;
        };
        let c = todo.remove(k);
        if ri == routes.len() {
            routes.push(vec![c]);
        } else {
            routes[ri].insert(pos, c);
        }
    }
    true
}
