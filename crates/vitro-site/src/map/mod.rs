//! A town from any OpenStreetMap `.osm.pbf` file: street graphs, buildings, bridges, water.
//!
//! Coordinates are local metres (`x` east, `y` north) around the centre of the bounding box
//! of all nodes in the file, through a [`LocalProjection`]. Nothing about a particular file is
//! assumed: no ids, counts or bounds.
//!
//! ```
//! use vitro_site::map::{MapConfig, TownMap};
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/maps/kotka.osm.pbf");
//! let town = TownMap::load(path, &MapConfig::default()).unwrap();
//! assert_eq!(town.counts.highway_ways, 343);
//! assert!(town.walk.node_count() > town.drive.node_count());
//! ```

mod error;
mod features;
mod osm;
mod streets;
mod zones;

pub use error::MapError;
pub use features::{Bridge, Building, HeightRules, WaterArea};
pub use streets::{Mode, Segment, StreetEdge, StreetGraph, StreetNode};
pub use zones::{ForbiddenZones, ZoneConfig};

use crate::geo::{LocalProjection, P2};
use osm::RawOsm;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// Loading options.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MapConfig {
    /// How building heights are found.
    pub heights: HeightRules,
}

/// Element counts as stored in the file.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ElementCounts {
    /// Nodes (plain and dense).
    pub nodes: usize,
    /// Ways.
    pub ways: usize,
    /// Relations.
    pub relations: usize,
    /// Ways and relations carrying a `building` tag.
    pub buildings: usize,
    /// Ways carrying a `highway` tag.
    pub highway_ways: usize,
}

/// A geographic bounding box in degrees.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GeoBox {
    /// Southern edge.
    pub min_lat: f64,
    /// Western edge.
    pub min_lon: f64,
    /// Northern edge.
    pub max_lat: f64,
    /// Eastern edge.
    pub max_lon: f64,
}

/// A town: everything the tactical world needs from a map.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TownMap {
    /// Geographic bounds of all nodes.
    pub bbox: GeoBox,
    /// Degrees to local metres (centred on `bbox`).
    pub projection: LocalProjection,
    /// Local extent `[min_x, min_y, max_x, max_y]` of all nodes, metres.
    pub extent: [f64; 4],
    /// Counts of elements in the file.
    pub counts: ElementCounts,
    /// Buildings with a valid footprint.
    pub buildings: Vec<Building>,
    /// Water areas.
    pub water: Vec<WaterArea>,
    /// Bridges.
    pub bridges: Vec<Bridge>,
    /// Street graph for vehicles.
    pub drive: StreetGraph,
    /// Street graph for troops.
    pub walk: StreetGraph,
}

impl TownMap {
    /// Loads a map from an `.osm.pbf` file.
    pub fn load(path: impl AsRef<Path>, config: &MapConfig) -> Result<Self, MapError> {
        let path = path.as_ref();
        let file = std::fs::File::open(path).map_err(|source| MapError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::build(RawOsm::read(std::io::BufReader::new(file))?, config)
    }

    /// Loads a map from `.osm.pbf` bytes.
    pub fn from_bytes(bytes: &[u8], config: &MapConfig) -> Result<Self, MapError> {
        Self::build(RawOsm::read(bytes)?, config)
    }

    fn build(raw: RawOsm, config: &MapConfig) -> Result<Self, MapError> {
        let [min_lat, min_lon, max_lat, max_lon] = raw.bounds.ok_or(MapError::Empty)?;
        let projection = LocalProjection::new((min_lat + max_lat) / 2.0, (min_lon + max_lon) / 2.0);
        let [x0, y0] = projection.project(min_lat, min_lon);
        let [x1, y1] = projection.project(max_lat, max_lon);

        let counts = ElementCounts {
            nodes: raw.node_count,
            ways: raw.ways.len(),
            relations: raw.relations.len(),
            buildings: raw.ways.iter().filter(|w| w.tags.has("building")).count()
                + raw
                    .relations
                    .iter()
                    .filter(|r| r.tags.has("building"))
                    .count(),
            highway_ways: raw.ways.iter().filter(|w| w.tags.has("highway")).count(),
        };

        let mut buildings = Vec::new();
        let mut water = Vec::new();
        let mut bridges = Vec::new();
        for w in &raw.ways {
            let tags = &w.tags;
            if tags.is_set("building") {
                if let Some(footprint) = features::way_polygon(&raw, w, &projection) {
                    buildings.push(Building {
                        osm_id: w.id,
                        footprint,
                        height: features::building_height(tags, &config.heights),
                    });
                }
            } else if features::is_water(tags)
                && let Some(area) = features::way_polygon(&raw, w, &projection)
            {
                water.push(WaterArea { osm_id: w.id, area });
            }
            if tags.is_set("bridge") && (tags.has("highway") || tags.has("railway")) {
                let line: Vec<P2> = w
                    .refs
                    .iter()
                    .filter_map(|&r| raw.coord(r).map(|[la, lo]| projection.project(la, lo)))
                    .collect();
                if line.len() >= 2 {
                    bridges.push(Bridge {
                        osm_id: w.id,
                        line,
                        width: features::bridge_width(tags),
                        layer: tags
                            .get("layer")
                            .and_then(|l| l.trim().parse().ok())
                            .unwrap_or(1),
                    });
                }
            }
        }
        let ways_by_id: BTreeMap<i64, usize> = raw
            .ways
            .iter()
            .enumerate()
            .map(|(i, w)| (w.id, i))
            .collect();
        for r in &raw.relations {
            let tags = &r.tags;
            if !matches!(tags.get("type"), Some("multipolygon" | "building")) {
                continue;
            }
            let polys = || features::relation_polygons(&raw, &ways_by_id, r, &projection);
            if tags.is_set("building") {
                let height = features::building_height(tags, &config.heights);
                buildings.extend(polys().into_iter().map(|footprint| Building {
                    osm_id: -r.id,
                    footprint,
                    height,
                }));
            } else if features::is_water(tags) {
                water.extend(polys().into_iter().map(|area| WaterArea {
                    osm_id: -r.id,
                    area,
                }));
            }
        }

        Ok(TownMap {
            bbox: GeoBox {
                min_lat,
                min_lon,
                max_lat,
                max_lon,
            },
            projection,
            extent: [x0, y0, x1, y1],
            counts,
            buildings,
            water,
            bridges,
            drive: StreetGraph::build(&raw, &projection, Mode::Drive),
            walk: StreetGraph::build(&raw, &projection, Mode::Walk),
        })
    }

    /// A map holding only `buildings` (local metres), with no streets, bridges or water: for
    /// hand-made scenes. Its projection is centred on (0°, 0°).
    pub fn from_buildings(buildings: Vec<Building>) -> Self {
        let mut extent = [0.0f64; 4];
        for (i, b) in buildings.iter().enumerate() {
            let bb = b.footprint.bbox();
            if i == 0 {
                extent = bb;
            }
            extent = [
                extent[0].min(bb[0]),
                extent[1].min(bb[1]),
                extent[2].max(bb[2]),
                extent[3].max(bb[3]),
            ];
        }
        let projection = LocalProjection::new(0.0, 0.0);
        let [min_lat, min_lon] = projection.unproject([extent[0], extent[1]]);
        let [max_lat, max_lon] = projection.unproject([extent[2], extent[3]]);
        let raw = RawOsm::default();
        TownMap {
            bbox: GeoBox {
                min_lat,
                min_lon,
                max_lat,
                max_lon,
            },
            projection,
            extent,
            counts: ElementCounts::default(),
            buildings,
            water: Vec::new(),
            bridges: Vec::new(),
            drive: StreetGraph::build(&raw, &projection, Mode::Drive),
            walk: StreetGraph::build(&raw, &projection, Mode::Walk),
        }
    }

    /// The street graph of `mode`.
    pub fn streets(&self, mode: Mode) -> &StreetGraph {
        match mode {
            Mode::Drive => &self.drive,
            Mode::Walk => &self.walk,
        }
    }
}
