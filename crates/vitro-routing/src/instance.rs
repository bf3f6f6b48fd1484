//! The problem: a depot, customers with demands and time windows, a fleet of equal vehicles.

use serde::{Deserialize, Serialize};

/// Slack allowed when comparing an arrival time with a due time (sums of square roots).
pub(crate) const TIME_EPS: f64 = 1e-9;

/// How the distance between two points is computed from their coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[non_exhaustive]
pub enum Metric {
    /// Euclidean distance rounded to the nearest integer, `nint(sqrt(dx² + dy²))`: TSPLIB's
    /// `EUC_2D`, the convention CVRPLIB's best-known values are computed with.
    RoundedEuclidean,
    /// Euclidean distance, not rounded: the usual convention for Solomon's instances.
    Euclidean,
}

impl Metric {
    /// The distance between `(ax, ay)` and `(bx, by)`.
    #[must_use]
    pub fn distance(self, ax: f64, ay: f64, bx: f64, by: f64) -> f64 {
        let (dx, dy) = (ax - bx, ay - by);
        let d = (dx * dx + dy * dy).sqrt();
        match self {
            Metric::RoundedEuclidean => (d + 0.5).floor(),
            Metric::Euclidean => d,
        }
    }
}

/// One place to visit: the depot (index 0 of [`Instance::nodes`]) or a customer.
///
/// Times follow Solomon: a vehicle may not arrive after `due`; arriving before `ready` it waits;
/// serving takes `service`. Travel time equals distance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// x coordinate.
    pub x: f64,
    /// y coordinate.
    pub y: f64,
    /// Demand (load units); 0 for the depot.
    pub demand: u64,
    /// Ready time: the earliest start of service (for the depot: the earliest departure).
    pub ready: f64,
    /// Due time: the latest arrival (for the depot: the latest return).
    pub due: f64,
    /// Service duration.
    pub service: f64,
}

impl Node {
    /// A node without a time window (ready 0, due infinite, no service time).
    #[must_use]
    pub fn untimed(x: f64, y: f64, demand: u64) -> Node {
        Node {
            x,
            y,
            demand,
            ready: 0.0,
            due: f64::INFINITY,
            service: 0.0,
        }
    }
}

/// A capacitated vehicle routing problem, with time windows when the nodes have them.
///
/// Node 0 is the depot; customers are nodes `1..nodes.len()`. A route is the list of customer
/// indices one vehicle serves, in order, leaving from and returning to the depot. Build it with
/// [`Instance::new`] (which computes the distances); changing `nodes` afterwards is not seen by
/// the distance matrix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Instance {
    /// The instance's name (from the file, or the caller's).
    pub name: String,
    /// The depot (index 0) and the customers.
    pub nodes: Vec<Node>,
    /// Capacity of each vehicle.
    pub capacity: u64,
    /// The fleet size, if limited.
    pub vehicles: Option<usize>,
    /// How distances are computed.
    pub metric: Metric,
    /// A best-known solution cost, if the file states one.
    pub best_known: Option<f64>,
    dist: Vec<f64>,
    timed: bool,
}

impl Instance {
    /// An instance over `nodes` (node 0 is the depot); the distance matrix is computed here.
    #[must_use]
    pub fn new(
        name: impl Into<String>,
        nodes: Vec<Node>,
        capacity: u64,
        vehicles: Option<usize>,
        metric: Metric,
    ) -> Instance {
        let n = nodes.len();
        let mut dist = vec![0.0; n * n];
        for (i, a) in nodes.iter().enumerate() {
            for (j, b) in nodes.iter().enumerate() {
                dist[i * n + j] = metric.distance(a.x, a.y, b.x, b.y);
            }
        }
        let timed = nodes
            .iter()
            .any(|n| n.ready > 0.0 || n.due.is_finite() || n.service > 0.0);
        Instance {
            name: name.into(),
            nodes,
            capacity,
            vehicles,
            metric,
            best_known: None,
            dist,
            timed,
        }
    }

    /// The number of customers (nodes other than the depot).
    #[must_use]
    pub fn customers(&self) -> usize {
        self.nodes.len().saturating_sub(1)
    }

    /// The distance (and travel time) from node `a` to node `b`.
    #[must_use]
    pub fn dist(&self, a: usize, b: usize) -> f64 {
        self.dist[a * self.nodes.len() + b]
    }

    /// Whether any customer has a time window or a service time.
    #[must_use]
    pub fn has_time_windows(&self) -> bool {
        self.timed
    }

    /// The length of one route (depot → customers → depot); 0 for an empty route.
    #[must_use]
    pub fn route_cost(&self, route: &[usize]) -> f64 {
        let mut cost = 0.0;
        let mut prev = 0;
        for &c in route {
            cost += self.dist(prev, c);
            prev = c;
        }
        if !route.is_empty() {
            cost += self.dist(prev, 0);
        }
        cost
    }

    /// The total load of a route.
    #[must_use]
    pub fn route_load(&self, route: &[usize]) -> u64 {
        route.iter().map(|&c| self.nodes[c].demand).sum()
    }

    /// Whether one route respects the capacity and every time window (the vehicle leaves the
    /// depot at its ready time, waits when early, and must be back by the depot's due time).
    #[must_use]
    pub fn route_feasible(&self, route: &[usize]) -> bool {
        self.route_load(route) <= self.capacity && self.route_on_time(route)
    }

    /// Whether one route respects every time window (capacity not checked).
    #[must_use]
    pub fn route_on_time(&self, route: &[usize]) -> bool {
        if !self.timed {
            return true;
        }
        let depot = &self.nodes[0];
        let mut t = depot.ready;
        let mut prev = 0;
        for &c in route {
            let node = &self.nodes[c];
            t += self.dist(prev, c);
            if t > node.due + TIME_EPS {
                return false;
            }
            t = t.max(node.ready) + node.service;
            prev = c;
        }
        route.is_empty() || t + self.dist(prev, 0) <= depot.due + TIME_EPS
    }

    /// The total length of a set of routes.
    #[must_use]
    pub fn cost(&self, routes: &[Vec<usize>]) -> f64 {
        routes.iter().map(|r| self.route_cost(r)).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounded_euclidean_is_tsplib_nint() {
        assert_eq!(Metric::RoundedEuclidean.distance(0.0, 0.0, 1.0, 1.0), 1.0);
        assert_eq!(Metric::RoundedEuclidean.distance(0.0, 0.0, 1.5, 1.5), 2.0);
        assert_eq!(Metric::RoundedEuclidean.distance(0.0, 0.0, 3.0, 4.0), 5.0);
        assert!((Metric::Euclidean.distance(0.0, 0.0, 1.0, 1.0) - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_late_arrival_is_infeasible_and_an_early_one_waits() {
        let mut a = Node::untimed(10.0, 0.0, 1);
        a.ready = 50.0;
        a.due = 60.0;
        a.service = 5.0;
        let mut b = Node::untimed(20.0, 0.0, 1);
        b.due = 64.0;
        let depot = Node {
            x: 0.0,
            y: 0.0,
            demand: 0,
            ready: 0.0,
            due: 100.0,
            service: 0.0,
        };
        let inst = Instance::new("t", vec![depot, a, b], 10, None, Metric::Euclidean);
        // Arrive at 1 at 10, wait to 50, leave 55, reach 2 at 65 > 64.
        assert!(!inst.route_on_time(&[1, 2]));
        assert!(inst.route_on_time(&[2, 1]));
        assert_eq!(inst.route_cost(&[1, 2]), 40.0);
    }
}
