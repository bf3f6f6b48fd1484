//! The streets a body may use: each street graph without the segments that pass through a
//! forbidden zone, so that a route planned on the abstract graph never enters one (the
//! property the cross-level check then re-checks on every concrete level), and its largest
//! strongly connected part (where any node reaches any other).

use super::stretch::{Stretch, Stretches};
use serde::{Deserialize, Serialize};
use vitro::env::{GraphStorage, NodeId};
use vitro_algo::scc::largest_component;
use vitro_site::geo::{P2, dist};
use vitro_site::map::{Mode, StreetEdge, StreetNode};
use vitro_site::site::Site;

/// Spacing used to test streets against forbidden zones, metres.
const ZONE_PROBE: f64 = 0.5;

/// Why no route could be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error, Serialize, Deserialize)]
pub enum RouteError {
    /// A node is not in the graph.
    #[error("node {0:?} is not in the street graph")]
    NoNode(NodeId),
    /// The goal cannot be reached on free streets.
    #[error("no free route from node {from:?} to node {to:?}")]
    NoPath {
        /// Start.
        from: NodeId,
        /// Goal.
        to: NodeId,
    },
}

/// One mode's street graph with the segments through forbidden zones left out.
#[derive(Clone, Debug)]
pub struct FreeGraph {
    /// Which streets.
    pub mode: Mode,
    /// Same nodes as the site's street graph; only edges over free segments.
    pub graph: GraphStorage<StreetNode, StreetEdge>,
    /// Per segment of the street graph: true if some point of it is forbidden.
    pub blocked: Vec<bool>,
    /// Per node: true if it is in the largest strongly connected part of the free graph
    /// (every such node reaches every other).
    pub main: Vec<bool>,
    /// Per segment and direction: its stretch of track, once a trip needed it.
    stretches: Stretches,
}

impl FreeGraph {
    fn new(site: &Site, mode: Mode) -> Self {
        let sg = site.map.streets(mode);
        let blocked: Vec<bool> = sg
            .segments
            .iter()
            .map(|s| {
                s.points.windows(2).any(|w| {
                    let n = (dist(w[0], w[1]) / ZONE_PROBE).ceil().max(1.0) as usize;
                    site.zones.forbidden_along(w[0], w[1], n)
                })
            })
            .collect();
        let mut graph = GraphStorage::default();
        for n in 0..sg.graph.node_count() as u32 {
            if let Some(data) = sg.graph.node(NodeId(n)) {
                graph.add_node(data.clone());
            }
        }
        for n in 0..sg.graph.node_count() as u32 {
            for (to, len, e) in sg.graph.neighbors(NodeId(n)) {
                if !blocked[e.segment as usize] {
                    graph.add_edge(NodeId(n), to, len, *e);
                }
            }
        }
        let main = largest_scc(&graph);
        FreeGraph {
            mode,
            graph,
            blocked,
            main,
            stretches: Stretches::new(sg.segments.len()),
        }
    }

    /// The stretch of track on `segment` in direction `forward` ([`Stretch`]), worked out the
    /// first time it is asked for; `site` must be the one these roads were made for.
    pub fn stretch(&self, site: &Site, segment: usize, forward: bool) -> Option<&Stretch> {
        self.stretches.get(site, self.mode, segment, forward)
    }

    /// Number of free directed edges leaving `n`.
    pub fn degree(&self, n: NodeId) -> usize {
        self.graph.neighbors(n).count()
    }

    /// The node of the main (largest strongly connected) part nearest to the town point `p`
    /// (ties to the lower id): any two such nodes are joined by free routes both ways.
    pub fn nearest_connected(&self, p: P2) -> Option<NodeId> {
        (0..self.graph.node_count() as u32)
            .map(NodeId)
            .filter(|&n| self.main[n.0 as usize])
            .filter_map(|n| self.graph.node(n).map(|s| (n, dist(p, s.pos))))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .map(|(n, _)| n)
    }

    /// Shortest free path from `from` to `to`.
    pub fn path(&self, from: NodeId, to: NodeId) -> Result<Vec<NodeId>, RouteError> {
        for n in [from, to] {
            if self.graph.node(n).is_none() {
                return Err(RouteError::NoNode(n));
            }
        }
        self.graph
            .shortest_path(from, to)
            .map(|(_, p)| p)
            .ok_or(RouteError::NoPath { from, to })
    }
}

/// Membership of the largest strongly connected component (ties to the component with the
/// lowest node id).
fn largest_scc<N, E>(g: &GraphStorage<N, E>) -> Vec<bool> {
    let arcs = (0..g.node_count() as u32).flat_map(|u| {
        g.neighbors(NodeId(u))
            .map(move |(v, _, _)| (u as usize, v.0 as usize))
    });
    largest_component(g.node_count(), arcs)
}

/// The free street graphs of a site, built once and shared by every run on it.
#[derive(Clone, Debug)]
pub struct Roads {
    /// For vehicles.
    pub drive: FreeGraph,
    /// For troops.
    pub walk: FreeGraph,
}

impl Roads {
    /// Tests every street segment of `site` against its forbidden zones.
    pub fn new(site: &Site) -> Self {
        Roads {
            drive: FreeGraph::new(site, Mode::Drive),
            walk: FreeGraph::new(site, Mode::Walk),
        }
    }
    /// The free graph of `mode`.
    pub fn of(&self, mode: Mode) -> &FreeGraph {
        match mode {
            Mode::Drive => &self.drive,
            Mode::Walk => &self.walk,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn largest_scc_needs_both_ways() {
        // 0 <-> 1 <-> 2, 2 -> 3 (3 reaches nothing), 4 <-> 5.
        let mut g: GraphStorage<(), ()> = GraphStorage::default();
        let n: Vec<NodeId> = (0..6).map(|_| g.add_node(())).collect();
        g.add_undirected_edge(n[0], n[1], 1.0, ());
        g.add_undirected_edge(n[1], n[2], 1.0, ());
        g.add_edge(n[2], n[3], 1.0, ());
        g.add_undirected_edge(n[4], n[5], 1.0, ());
        assert_eq!(largest_scc(&g), [true, true, true, false, false, false]);
    }
}
