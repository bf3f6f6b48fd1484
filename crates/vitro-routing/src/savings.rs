//! Clarke & Wright's savings construction (parallel version), with capacity and time windows.
//!
//! G. Clarke and J. W. Wright, "Scheduling of vehicles from a central depot to a number of
//! delivery points", *Operations Research* 12(4), 568–581, 1964.

use crate::Instance;
use crate::solution::{Solution, Stats, servable};

/// Every customer starts on its own route; pairs `(i, j)` are taken by decreasing saving
/// `d(0,i) + d(0,j) − d(i,j)` (ties by index) and their routes joined end to start when the
/// joined route is feasible. Without time windows a route may also be reversed to join.
#[must_use]
pub fn savings(inst: &Instance) -> Solution {
    let n = inst.nodes.len();
    let mut unassigned = Vec::new();
    let mut routes: Vec<Vec<usize>> = Vec::new();
    let mut route_of = vec![usize::MAX; n];
    for (c, slot) in route_of.iter_mut().enumerate().skip(1) {
        if servable(inst, c) {
            *slot = routes.len();
            routes.push(vec![c]);
        } else {
            unassigned.push(c);
        }
    }
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for i in 1..n {
        for j in 1..n {
            if i != j && route_of[i] != usize::MAX && route_of[j] != usize::MAX {
                let s = inst.dist(0, i) + inst.dist(0, j) - inst.dist(i, j);
                if s > 0.0 {
                    pairs.push((s, i, j));
                }
            }
        }
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let reversible = !inst.has_time_windows();
    for &(_, i, j) in &pairs {
        let (ri, rj) = (route_of[i], route_of[j]);
        if ri == rj {
            continue;
        }
        let (a, b) = (&routes[ri], &routes[rj]);
        if inst.route_load(a) + inst.route_load(b) > inst.capacity {
            continue;
        }
        let i_last = a.last() == Some(&i);
        let i_first = a.first() == Some(&i);
        let j_first = b.first() == Some(&j);
        let j_last = b.last() == Some(&j);
        let mut joined: Option<Vec<usize>> = None;
        if i_last && j_first {
            joined = Some(a.iter().chain(b.iter()).copied().collect());
        } else if reversible && i_first && j_first {
            joined = Some(a.iter().rev().chain(b.iter()).copied().collect());
        } else if reversible && i_last && j_last {
            joined = Some(a.iter().chain(b.iter().rev()).copied().collect());
        } else if reversible && i_first && j_last {
            joined = Some(b.iter().chain(a.iter()).copied().collect());
        }
        let Some(route) = joined else { continue };
        if !inst.route_on_time(&route) {
            continue;
        }
        for &c in &route {
            route_of[c] = ri;
        }
        routes[ri] = route;
        routes[rj].clear();
    }
    Solution::new(inst, routes, unassigned, Stats::default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Metric, Node};

    #[test]
    fn two_customers_on_a_line_share_one_route() {
        let nodes = vec![
            Node::untimed(0.0, 0.0, 0),
            Node::untimed(10.0, 0.0, 1),
            Node::untimed(20.0, 0.0, 1),
        ];
        let inst = Instance::new("line", nodes, 5, None, Metric::Euclidean);
        let s = savings(&inst);
        assert_eq!(s.routes.len(), 1);
        assert_eq!(s.cost, 40.0);
        s.check(&inst).unwrap();
    }

    #[test]
    fn capacity_keeps_routes_apart() {
        let nodes = vec![
            Node::untimed(0.0, 0.0, 0),
            Node::untimed(10.0, 0.0, 3),
            Node::untimed(20.0, 0.0, 3),
            Node::untimed(0.0, 10.0, 9),
        ];
        let inst = Instance::new("cap", nodes, 5, None, Metric::Euclidean);
        let s = savings(&inst);
        assert_eq!(s.routes.len(), 2);
        assert_eq!(s.unassigned, vec![3]);
    }
}
