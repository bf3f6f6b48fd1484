//! Street graphs: junctions as nodes, street segments between them as edges.
//!
//! A node is a junction: an OSM node used by two or more ways of the network (or twice by one
//! way), or the end of a way. An edge is the run of a way between two consecutive junctions;
//! its length is the sum of its segment lengths in local metres.

use super::osm::{RawOsm, Tags};
use crate::geo::{LocalProjection, P2, polyline_length};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use vitro::env::{GraphStorage, NodeId};

/// Who travels on a street graph.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// Vehicles: drivable highway classes, one-way rules respected.
    Drive,
    /// Troops on foot: walkable classes, every street both ways.
    Walk,
}

impl Mode {
    /// True if a way with these tags belongs to this mode's network.
    ///
    /// Drive: `motorway`, `trunk`, `primary`, `secondary`, `tertiary` (and their `_link`s),
    /// `unclassified`, `residential`, `living_street`, `service`, `road`; minus `area=yes`,
    /// `access`/`motor_vehicle`/`motorcar` `no`/`private`, and service roads tagged
    /// `parking`, `parking_aisle`, `private` or `emergency_access` (driveways stay: a truck
    /// may have to reach a house).
    ///
    /// Walk: every `highway` except motorways, `cycleway` (unless `foot` is `yes`,
    /// `designated` or `permissive`), `bus_guideway`, `raceway`, `platform`, `construction`,
    /// `proposed`, `abandoned`, `razed`; minus `area=yes`, `foot=no`, and `access=private`
    /// or `no` (unless `foot` allows it). These follow the usual rules of street-network
    /// tools, so graph sizes are comparable with theirs.
    pub(crate) fn admits(self, tags: &Tags) -> bool {
        let Some(hw) = tags.get("highway") else {
            return false;
        };
        if tags.get("area") == Some("yes") {
            return false;
        }
        let foot_ok = matches!(tags.get("foot"), Some("yes" | "designated" | "permissive"));
        let no = |k: &str| matches!(tags.get(k), Some("no" | "private"));
        match self {
            Mode::Drive => {
                let class = hw.strip_suffix("_link").unwrap_or(hw);
                matches!(
                    class,
                    "motorway"
                        | "trunk"
                        | "primary"
                        | "secondary"
                        | "tertiary"
                        | "unclassified"
                        | "residential"
                        | "living_street"
                        | "service"
                        | "road"
                ) && !no("access")
                    && !no("motor_vehicle")
                    && !no("motorcar")
                    && !matches!(
                        tags.get("service"),
                        Some("parking" | "parking_aisle" | "private" | "emergency_access")
                    )
            }
            Mode::Walk => {
                let banned = matches!(
                    hw,
                    "motorway"
                        | "motorway_link"
                        | "bus_guideway"
                        | "raceway"
                        | "platform"
                        | "construction"
                        | "proposed"
                        | "abandoned"
                        | "razed"
                        | "no"
                ) || (hw == "cycleway" && !foot_ok);
                !banned && tags.get("foot") != Some("no") && (!no("access") || foot_ok)
            }
        }
    }
}

/// Travel directions allowed on a way, for vehicles.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Direction {
    Both,
    Forward,
    Backward,
}

/// One-way rules: `oneway=yes|true|1` forward, `-1|reverse` backward, `no` both ways;
/// roundabouts (`junction=roundabout|circular`) and motorways are one-way forward unless
/// tagged `oneway=no`.
fn direction(tags: &Tags) -> Direction {
    match tags.get("oneway") {
        Some("yes" | "true" | "1") => Direction::Forward,
        Some("-1" | "reverse") => Direction::Backward,
        Some("no" | "false" | "0") => Direction::Both,
        _ => {
            let implied = matches!(tags.get("junction"), Some("roundabout" | "circular"))
                || matches!(tags.get("highway"), Some("motorway" | "motorway_link"));
            if implied {
                Direction::Forward
            } else {
                Direction::Both
            }
        }
    }
}

/// A junction of the street graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StreetNode {
    /// OSM node id.
    pub osm_id: i64,
    /// Position, local metres.
    pub pos: P2,
}

/// Graph edge data: which segment, walked which way.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StreetEdge {
    /// Index into [`StreetGraph::segments`].
    pub segment: u32,
    /// True if travelled in the direction of the segment's points.
    pub forward: bool,
}

/// A street segment: the run of one way between two consecutive junctions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// OSM way id.
    pub way: i64,
    /// The `highway` class.
    pub class: String,
    /// True if the way is a bridge.
    pub bridge: bool,
    /// Junction at the first point.
    pub from: NodeId,
    /// Junction at the last point.
    pub to: NodeId,
    /// Geometry, local metres, from `from` to `to`.
    pub points: Vec<P2>,
    /// Length, metres (sum of segment lengths).
    pub length: f64,
}

/// A street graph for one [`Mode`]: a directed [`GraphStorage`] whose edges point at
/// [`Segment`]s (a two-way street gives two directed edges over one segment).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StreetGraph {
    /// Who travels here.
    pub mode: Mode,
    /// Junctions and directed edges; edge lengths in metres.
    pub graph: GraphStorage<StreetNode, StreetEdge>,
    /// The street segments (undirected geometry).
    pub segments: Vec<Segment>,
    /// Number of OSM ways in the network.
    pub ways: usize,
}

impl StreetGraph {
    /// Builds the graph of `mode` from the ways of the file, in file order.
    pub(crate) fn build(raw: &RawOsm, proj: &LocalProjection, mode: Mode) -> Self {
        // Runs of consecutive nodes with known coordinates: a way cut by the extract's edge
        // becomes several runs.
        let mut runs: Vec<(usize, Vec<i64>)> = Vec::new();
        let mut ways = 0;
        for (wi, w) in raw.ways.iter().enumerate() {
            if !mode.admits(&w.tags) {
                continue;
            }
            ways += 1;
            let mut run = Vec::new();
            for &r in &w.refs {
                if raw.coord(r).is_some() {
                    run.push(r);
                } else if run.len() > 1 {
                    runs.push((wi, std::mem::take(&mut run)));
                } else {
                    run.clear();
                }
            }
            if run.len() > 1 {
                runs.push((wi, run));
            }
        }
        // Uses per node (lookup only, never iterated), and the junction set.
        let mut uses: HashMap<i64, u32> = HashMap::new();
        for (_, run) in &runs {
            for &r in run {
                *uses.entry(r).or_insert(0) += 1;
            }
        }
        let is_junction = |r: i64, end: bool| end || uses.get(&r).is_some_and(|&u| u > 1);

        let mut graph = GraphStorage::default();
        let mut ids: BTreeMap<i64, NodeId> = BTreeMap::new();
        let mut segments = Vec::new();
        let mut node_of = |graph: &mut GraphStorage<StreetNode, StreetEdge>, r: i64, p: P2| {
            *ids.entry(r)
                .or_insert_with(|| graph.add_node(StreetNode { osm_id: r, pos: p }))
        };
        let project = |r: i64| {
            raw.coord(r)
                .map(|[la, lo]| proj.project(la, lo))
                .unwrap_or_default()
        };
        for (wi, run) in &runs {
            let way = &raw.ways[*wi];
            let dir = match mode {
                Mode::Drive => direction(&way.tags),
                Mode::Walk => Direction::Both,
            };
            let class = way.tags.get("highway").unwrap_or_default().to_owned();
            let bridge = way.tags.is_set("bridge");
            let mut start = 0;
            for i in 1..run.len() {
                if !is_junction(run[i], i + 1 == run.len()) {
                    continue;
                }
                let points: Vec<P2> = run[start..=i].iter().map(|&r| project(r)).collect();
                let from = node_of(&mut graph, run[start], points[0]);
                let to = node_of(&mut graph, run[i], points[points.len() - 1]);
                let length = polyline_length(&points);
                let seg = segments.len() as u32;
                if dir != Direction::Backward {
                    graph.add_edge(
                        from,
                        to,
                        length,
                        StreetEdge {
                            segment: seg,
                            forward: true,
                        },
                    );
                }
                if dir != Direction::Forward {
                    graph.add_edge(
                        to,
                        from,
                        length,
                        StreetEdge {
                            segment: seg,
                            forward: false,
                        },
                    );
                }
                segments.push(Segment {
                    way: way.id,
                    class: class.clone(),
                    bridge,
                    from,
                    to,
                    points,
                    length,
                });
                start = i;
            }
        }
        StreetGraph {
            mode,
            graph,
            segments,
            ways,
        }
    }

    /// Number of junctions.
    pub fn node_count(&self) -> usize {
        self.graph.node_count()
    }
    /// Position of junction `n`.
    pub fn pos(&self, n: NodeId) -> Option<P2> {
        self.graph.node(n).map(|s| s.pos)
    }
    /// Total street length, metres (each segment once).
    pub fn total_length(&self) -> f64 {
        self.segments.iter().map(|s| s.length).sum()
    }
    /// The junction nearest to `p` (linear scan; ties to the lower id).
    pub fn nearest_node(&self, p: P2) -> Option<NodeId> {
        (0..self.graph.node_count() as u32)
            .map(NodeId)
            .filter_map(|n| self.pos(n).map(|q| (n, crate::geo::dist(p, q))))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .map(|(n, _)| n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tags(kv: &[(&str, &str)]) -> Tags {
        let mut t = Tags::default();
        for (k, v) in kv {
            t.push(k, v);
        }
        t
    }

    #[test]
    fn one_way_rules() {
        assert_eq!(direction(&tags(&[("oneway", "yes")])), Direction::Forward);
        assert_eq!(direction(&tags(&[("oneway", "1")])), Direction::Forward);
        assert_eq!(direction(&tags(&[("oneway", "true")])), Direction::Forward);
        assert_eq!(direction(&tags(&[("oneway", "-1")])), Direction::Backward);
        assert_eq!(
            direction(&tags(&[("junction", "roundabout")])),
            Direction::Forward
        );
        assert_eq!(
            direction(&tags(&[("junction", "roundabout"), ("oneway", "no")])),
            Direction::Both
        );
        assert_eq!(
            direction(&tags(&[("highway", "residential")])),
            Direction::Both
        );
    }

    #[test]
    fn classes_per_mode() {
        let res = tags(&[("highway", "residential")]);
        let cyc = tags(&[("highway", "cycleway")]);
        let shared = tags(&[("highway", "cycleway"), ("foot", "designated")]);
        let aisle = tags(&[("highway", "service"), ("service", "parking_aisle")]);
        assert!(Mode::Drive.admits(&res) && Mode::Walk.admits(&res));
        assert!(!Mode::Drive.admits(&cyc) && !Mode::Walk.admits(&cyc));
        assert!(Mode::Walk.admits(&shared));
        assert!(!Mode::Drive.admits(&aisle) && Mode::Walk.admits(&aisle));
        assert!(!Mode::Walk.admits(&tags(&[("building", "yes")])));
    }
}
