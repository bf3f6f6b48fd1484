//! A summary of a map file, for the command line (`vitro map info FILE`).

use crate::map::{GeoBox, MapConfig, MapError, StreetGraph, TownMap};
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::Path;

/// Size of a street graph.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct GraphInfo {
    /// Junctions.
    pub nodes: usize,
    /// Street segments between junctions (each once, whatever its directions).
    pub edges: usize,
    /// Directed edges (a two-way segment counts twice, a one-way once).
    pub directed_edges: usize,
    /// OSM ways in the network.
    pub ways: usize,
    /// Total street length, metres.
    pub length_m: f64,
    /// The same network with every OSM node kept (no junction simplification): nodes.
    pub osm_nodes: usize,
    /// ... and undirected node-to-node links, as other street-network tools count them.
    pub osm_edges: usize,
}

impl GraphInfo {
    /// Sizes of `g`.
    pub fn of(g: &StreetGraph) -> Self {
        let key = |p: [f64; 2]| (p[0].to_bits(), p[1].to_bits());
        let mut nodes = BTreeSet::new();
        let mut links = BTreeSet::new();
        for s in &g.segments {
            for w in s.points.windows(2) {
                let (a, b) = (key(w[0]), key(w[1]));
                nodes.insert(a);
                nodes.insert(b);
                links.insert((a.min(b), a.max(b)));
            }
        }
        GraphInfo {
            nodes: g.node_count(),
            edges: g.segments.len(),
            directed_edges: g.graph.edge_count(),
            ways: g.ways,
            length_m: g.total_length(),
            osm_nodes: nodes.len(),
            osm_edges: links.len(),
        }
    }
}

/// What `vitro map info` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MapInfo {
    /// Nodes in the file.
    pub nodes: usize,
    /// Ways in the file.
    pub ways: usize,
    /// Relations in the file.
    pub relations: usize,
    /// Ways and relations tagged `building`.
    pub buildings: usize,
    /// Ways tagged `highway`.
    pub highway_ways: usize,
    /// Buildings with a usable footprint.
    pub building_polygons: usize,
    /// Water areas.
    pub water_areas: usize,
    /// Bridges.
    pub bridges: usize,
    /// Street graph for vehicles.
    pub drive_graph: GraphInfo,
    /// Street graph for troops.
    pub walk_graph: GraphInfo,
    /// Bounds of all nodes, degrees.
    pub bbox: GeoBox,
    /// Size of the bounds in local metres, `[width, height]`.
    pub size_m: [f64; 2],
}

impl MapInfo {
    /// The summary of a loaded map.
    pub fn of(m: &TownMap) -> Self {
        MapInfo {
            nodes: m.counts.nodes,
            ways: m.counts.ways,
            relations: m.counts.relations,
            buildings: m.counts.buildings,
            highway_ways: m.counts.highway_ways,
            building_polygons: m.buildings.len(),
            water_areas: m.water.len(),
            bridges: m.bridges.len(),
            drive_graph: GraphInfo::of(&m.drive),
            walk_graph: GraphInfo::of(&m.walk),
            bbox: m.bbox,
            size_m: [m.extent[2] - m.extent[0], m.extent[3] - m.extent[1]],
        }
    }
}

/// Loads `path` (any `.osm.pbf`) and summarises it.
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/maps/kotka.osm.pbf");
/// let info = vitro_site::info::map_info(path).unwrap();
/// let json = serde_json::to_value(&info).unwrap();
/// assert_eq!(json["relations"], 5);
/// assert!(json["walk_graph"]["nodes"].as_u64().unwrap() > 0);
/// ```
pub fn map_info(path: impl AsRef<Path>) -> Result<MapInfo, MapError> {
    Ok(MapInfo::of(&TownMap::load(path, &MapConfig::default())?))
}
