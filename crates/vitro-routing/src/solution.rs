//! A solution, its check, and the cheapest-insertion step every solver shares.

use crate::Instance;
use serde::{Deserialize, Serialize};

/// What a solver did to find its solution.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stats {
    /// Large-neighbourhood iterations run (ruin, recreate, local search).
    pub iterations: u64,
    /// Times the best solution improved.
    pub improvements: u64,
    /// Auction rounds (one task awarded per round).
    pub rounds: u64,
    /// Messages an auction would send: the calls for bids and the awards (one a vehicle each),
    /// and the bids.
    pub messages: u64,
}

/// Routes for the fleet, their total length, and the customers no vehicle could serve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// One list of customer indices per vehicle used, in visiting order (the depot is implied at
    /// both ends).
    pub routes: Vec<Vec<usize>>,
    /// Total length of the routes.
    pub cost: f64,
    /// Customers left out: their demand exceeds a vehicle's capacity, their window cannot be met,
    /// or the fleet is full.
    pub unassigned: Vec<usize>,
    /// How the solution was found.
    pub stats: Stats,
}

/// Why a solution is not a feasible one of its instance.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Violation {
    /// A customer is served twice, not at all, or is not a customer.
    #[error("customer {0} is served {1} times")]
    Coverage(usize, usize),
    /// A route carries more than a vehicle's capacity.
    #[error("route {route} carries {load}, capacity {capacity}")]
    Capacity {
        /// Route index.
        route: usize,
        /// Its load.
        load: u64,
        /// The capacity.
        capacity: u64,
    },
    /// A route arrives after a due time.
    #[error("route {0} is late at a customer or back at the depot")]
    Late(usize),
    /// More routes than vehicles.
    #[error("{routes} routes for {vehicles} vehicles")]
    Fleet {
        /// Routes used.
        routes: usize,
        /// Vehicles available.
        vehicles: usize,
    },
    /// The stated cost is not the routes' length.
    #[error("stated cost {stated}, routes' length {actual}")]
    Cost {
        /// `Solution::cost`.
        stated: f64,
        /// The recomputed length.
        actual: f64,
    },
}

impl Solution {
    /// A solution over these routes, its cost computed.
    #[must_use]
    pub fn new(
        inst: &Instance,
        routes: Vec<Vec<usize>>,
        unassigned: Vec<usize>,
        stats: Stats,
    ) -> Solution {
        let routes: Vec<Vec<usize>> = routes.into_iter().filter(|r| !r.is_empty()).collect();
        let cost = inst.cost(&routes);
        Solution {
            routes,
            cost,
            unassigned,
            stats,
        }
    }

    /// Checks that every customer is served once, by routes within capacity, on time, by no
    /// more vehicles than the fleet has, at the stated cost.
    ///
    /// # Errors
    /// The first [`Violation`] found.
    pub fn check(&self, inst: &Instance) -> Result<(), Violation> {
        let mut served = vec![0usize; inst.nodes.len()];
        for &c in self.routes.iter().flatten() {
            if c == 0 || c >= served.len() {
                return Err(Violation::Coverage(c, 1));
            }
            served[c] += 1;
        }
        if let Some(c) = (1..served.len()).find(|&c| served[c] != 1) {
            return Err(Violation::Coverage(c, served[c]));
        }
        for (k, r) in self.routes.iter().enumerate() {
            let load = inst.route_load(r);
            if load > inst.capacity {
                return Err(Violation::Capacity {
                    route: k,
                    load,
                    capacity: inst.capacity,
                });
            }
            if !inst.route_on_time(r) {
                return Err(Violation::Late(k));
            }
        }
        if let Some(v) = inst.vehicles.filter(|&v| self.routes.len() > v) {
            return Err(Violation::Fleet {
                routes: self.routes.len(),
                vehicles: v,
            });
        }
        let actual = inst.cost(&self.routes);
        if (actual - self.cost).abs() > 1e-6 * actual.max(1.0) {
            return Err(Violation::Cost {
                stated: self.cost,
                actual,
            });
        }
        Ok(())
    }

    /// The relative gap to a reference cost, in percent: `100 (cost − reference) / reference`.
    #[must_use]
    pub fn gap_percent(&self, reference: f64) -> f64 {
        100.0 * (self.cost - reference) / reference
    }
}

/// The cheapest feasible place to insert customer `c` into `route` (whose load is `load`):
/// `(added length, position)`, the first position on ties; `None` if none is feasible.
pub(crate) fn best_insertion(
    inst: &Instance,
    route: &[usize],
    load: u64,
    c: usize,
    buf: &mut Vec<usize>,
) -> Option<(f64, usize)> {
    if load + inst.nodes[c].demand > inst.capacity {
        return None;
    }
    let mut best: Option<(f64, usize)> = None;
    for pos in 0..=route.len() {
        let prev = if pos == 0 { 0 } else { route[pos - 1] };
        let next = route.get(pos).copied().unwrap_or(0);
        let delta = inst.dist(prev, c) + inst.dist(c, next) - inst.dist(prev, next);
        if best.is_some_and(|(b, _)| delta >= b) {
            continue;
        }
        if inst.has_time_windows() {
            buf.clear();
            buf.extend_from_slice(&route[..pos]);
            buf.push(c);
            buf.extend_from_slice(&route[pos..]);
            if !inst.route_on_time(buf) {
                continue;
            }
        }
        best = Some((delta, pos));
    }
    best
}

/// Whether a customer can be served at all: alone on a vehicle, within capacity and on time.
pub(crate) fn servable(inst: &Instance, c: usize) -> bool {
    inst.route_feasible(&[c])
}
