//! Sequential single-item auctions: the distributed allocation, simulated round by round.
//!
//! S. Koenig, C. Tovey, M. Lagoudakis, V. Markakis, D. Kempe, P. Keskinocak, A. Kleywegt,
//! A. Meyerson and S. Jain, "The power of sequential single-item auctions for agent
//! coordination", AAAI 2006. Each round the auctioneer calls for bids on the unallocated
//! customers; every vehicle bids its smallest marginal cost (the cheapest feasible insertion of
//! one customer into the route it already holds); the smallest bid wins that customer.

use crate::Instance;
use crate::solution::{Solution, Stats, best_insertion, servable};

/// Runs the auction among `vehicles` equal vehicles (the instance's fleet, or one per customer
/// when unlimited) until every customer is awarded or no vehicle can bid.
///
/// Messages are counted as a radio would carry them: per round one call for bids and one award
/// to each vehicle, and one bid from each vehicle that has a feasible bid. Ties go to the lower
/// vehicle, then the lower customer. Vehicles beyond one per customer never win (an empty
/// vehicle with a lower number makes the same bid), so only that many bid in the computation;
/// the others' messages are still counted.
#[must_use]
pub fn auction(inst: &Instance) -> Solution {
    let fleet = inst.vehicles.unwrap_or(inst.customers()).max(1);
    let bidders = fleet.min(inst.customers().max(1));
    let idle = (fleet - bidders) as u64; // vehicles that bid as an empty one does
    let mut routes: Vec<Vec<usize>> = vec![Vec::new(); bidders];
    let mut loads = vec![0u64; bidders];
    let mut open: Vec<usize> = (1..inst.nodes.len())
        .filter(|&c| servable(inst, c))
        .collect();
    let mut unassigned: Vec<usize> = (1..inst.nodes.len())
        .filter(|&c| !servable(inst, c))
        .collect();
    let mut stats = Stats::default();
    let mut buf = Vec::new();
    while !open.is_empty() {
        stats.rounds += 1;
        stats.messages = stats.messages.saturating_add(fleet as u64); // the call for bids
        let mut winner: Option<(f64, usize, usize, usize)> = None; // cost, vehicle, customer, pos
        let mut empty_bids = false;
        for v in 0..bidders {
            let mut bid: Option<(f64, usize, usize)> = None;
            for &c in &open {
                if let Some((cost, pos)) = best_insertion(inst, &routes[v], loads[v], c, &mut buf)
                    && bid.is_none_or(|(b, _, _)| cost < b)
                {
                    bid = Some((cost, c, pos));
                }
            }
            if let Some((cost, c, pos)) = bid {
                stats.messages = stats.messages.saturating_add(1);
                empty_bids |= routes[v].is_empty();
                if winner.is_none_or(|(w, _, _, _)| cost < w) {
                    winner = Some((cost, v, c, pos));
                }
            }
        }
        if empty_bids {
            stats.messages = stats.messages.saturating_add(idle);
        }
        let Some((_, v, c, pos)) = winner else {
            unassigned.append(&mut open);
            break;
        };
        stats.messages = stats.messages.saturating_add(fleet as u64); // the award
        routes[v].insert(pos, c);
        loads[v] += inst.nodes[c].demand;
        open.retain(|&x| x != c);
    }
    unassigned.sort_unstable();
    Solution::new(inst, routes, unassigned, stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Metric, Node};

    #[test]
    fn two_vehicles_take_the_two_clusters() {
        let nodes = vec![
            Node::untimed(0.0, 0.0, 0),
            Node::untimed(10.0, 0.0, 1),
            Node::untimed(11.0, 0.0, 1),
            Node::untimed(-10.0, 0.0, 1),
            Node::untimed(-11.0, 0.0, 1),
        ];
        let inst = Instance::new("two", nodes, 2, Some(2), Metric::Euclidean);
        let s = auction(&inst);
        s.check(&inst).unwrap();
        assert_eq!(s.cost, 44.0);
        assert_eq!(s.stats.rounds, 4);
        // Each round: 2 calls, 2 awards, and one bid per vehicle with room.
        assert!(s.stats.messages >= 4 * 4 + 4 && s.stats.messages <= 4 * 6);
    }

    #[test]
    fn a_fleet_larger_than_the_customers_bids_as_one_per_customer() {
        let nodes = vec![
            Node::untimed(0.0, 0.0, 0),
            Node::untimed(10.0, 0.0, 1),
            Node::untimed(11.0, 0.0, 1),
            Node::untimed(-10.0, 0.0, 1),
        ];
        let per_customer = Instance::new("n", nodes.clone(), 2, None, Metric::Euclidean);
        let more = Instance::new("n", nodes.clone(), 2, Some(3 + 4), Metric::Euclidean);
        let (a, b) = (auction(&per_customer), auction(&more));
        assert_eq!((a.routes.clone(), a.cost), (b.routes.clone(), b.cost));
        assert_eq!(a.stats.rounds, b.stats.rounds);
        // Four more vehicles: each round one more call, award and (empty: it can bid) bid each.
        assert_eq!(b.stats.messages, a.stats.messages + 4 * 3 * a.stats.rounds);
        // A fleet no computer could simulate one by one: the same routes, counts saturated.
        let huge = Instance::new("n", nodes, 2, Some(usize::MAX), Metric::Euclidean);
        let c = auction(&huge);
        assert_eq!((c.routes, c.cost), (a.routes, a.cost));
        assert_eq!(c.stats.messages, u64::MAX);
    }
}
