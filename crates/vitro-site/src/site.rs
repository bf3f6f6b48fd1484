//! The site: a town set on a terrain at an offset, with its line-of-sight scene.
//!
//! World coordinates are the terrain's local metres (`x` east, `y` north from the grid's
//! lower-left corner, `z` up). A town point `p` (map metres) sits at `p + offset` in the world.
//!
//! - "Ground" is the ground mesh ([`Terrain::surface_height`]), the surface that line of sight
//!   and physics see, not the smoother bilinear [`Terrain::height`].
//! - Buildings stand on the ground: their base is the lowest ground height under their
//!   footprint's vertices (so no wall floats above a slope), their roof is base + height.
//! - Streets follow the ground, sampled at least every half cell.
//! - Bridge decks run straight between the ground at the bridge's two ends, never below the
//!   ground under them.

use crate::geo::{P2, polyline_length};
use crate::los::{Deck, LosError, LosScene, Prism};
use crate::map::{ForbiddenZones, Mode, TownMap, ZoneConfig};
use crate::terrain::Terrain;
use serde::{Deserialize, Serialize};
use vitro::env::NodeId;

/// How the town is set on the terrain.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SiteConfig {
    /// World position of the town's origin (the centre of its bounding box); `None` centres
    /// the town on the terrain.
    pub offset: Option<[f64; 2]>,
    /// Forbidden-zone buffers.
    pub zones: ZoneConfig,
}

/// Why a site could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SiteError {
    /// The town does not fit on the terrain at this offset.
    #[error("the town at offset {offset:?} leaves the terrain (ground defined over {ground:?})")]
    OffTerrain {
        /// The offset used.
        offset: [f64; 2],
        /// Where the ground is defined.
        ground: [f64; 4],
    },
    /// The line-of-sight scene failed.
    #[error(transparent)]
    Los(#[from] LosError),
}

/// A building standing on the ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlacedBuilding {
    /// Index into [`TownMap::buildings`].
    pub index: usize,
    /// Footprint in world metres.
    pub footprint: crate::geo::Polygon,
    /// Height of the base (lowest ground under a footprint vertex), metres.
    pub base: f64,
    /// Height of the roof, metres.
    pub roof: f64,
}

/// A bridge deck in world metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlacedBridge {
    /// Index into [`TownMap::bridges`].
    pub index: usize,
    /// Centre line with deck height, world metres.
    pub deck: Vec<[f64; 3]>,
    /// Deck width, metres.
    pub width: f64,
}

/// A town on a terrain: the static world of a tactical simulation.
#[derive(Debug)]
pub struct Site {
    /// The map (town coordinates).
    pub map: TownMap,
    /// The ground.
    pub terrain: Terrain,
    /// World position of the town's origin.
    pub offset: [f64; 2],
    /// Buildings on the ground.
    pub buildings: Vec<PlacedBuilding>,
    /// Bridge decks.
    pub bridges: Vec<PlacedBridge>,
    /// Forbidden zones (town coordinates; use [`Site::is_forbidden`] for world points).
    pub zones: ForbiddenZones,
    /// Line of sight against ground, buildings and bridges.
    pub los: LosScene,
    zone_config: ZoneConfig,
    /// World points on the ground of every street node, drive then walk graph (cached:
    /// poses of entities at nodes are read on every look).
    street_points: [Vec<[f64; 3]>; 2],
}

impl Site {
    /// Sets `map` on `terrain`. Fails if any part of the town's extent is off the ground.
    pub fn new(map: TownMap, terrain: Terrain, config: &SiteConfig) -> Result<Self, SiteError> {
        let ground = terrain.extent();
        let offset = config
            .offset
            .unwrap_or([(ground[0] + ground[2]) / 2.0, (ground[1] + ground[3]) / 2.0]);
        let e = map.extent;
        let fits = e[0] + offset[0] >= ground[0]
            && e[1] + offset[1] >= ground[1]
            && e[2] + offset[0] <= ground[2]
            && e[3] + offset[1] <= ground[3];
        if !fits {
            return Err(SiteError::OffTerrain { offset, ground });
        }
        let shift = |p: P2| [p[0] + offset[0], p[1] + offset[1]];
        let ground_at = |p: P2| terrain.surface_height(p[0], p[1]).unwrap_or(0.0);

        let buildings: Vec<PlacedBuilding> = map
            .buildings
            .iter()
            .enumerate()
            .map(|(index, b)| {
                let fp = &b.footprint;
                let footprint = crate::geo::Polygon {
                    outer: fp.outer.iter().map(|&p| shift(p)).collect(),
                    holes: fp
                        .holes
                        .iter()
                        .map(|h| h.iter().map(|&p| shift(p)).collect())
                        .collect(),
                };
                let base = footprint
                    .outer
                    .iter()
                    .map(|&p| ground_at(p))
                    .fold(f64::INFINITY, f64::min);
                PlacedBuilding {
                    index,
                    footprint,
                    base,
                    roof: base + b.height,
                }
            })
            .collect();
        let bridges: Vec<PlacedBridge> = map
            .bridges
            .iter()
            .enumerate()
            .map(|(index, b)| {
                let line: Vec<P2> = b.line.iter().map(|&p| shift(p)).collect();
                PlacedBridge {
                    index,
                    deck: ramp(&line, &ground_at),
                    width: b.width,
                }
            })
            .collect();
        let prisms: Vec<Prism<'_>> = buildings
            .iter()
            .map(|b| Prism {
                footprint: &b.footprint,
                base: b.base,
                top: b.roof,
            })
            .collect();
        let decks: Vec<Deck<'_>> = bridges
            .iter()
            .map(|b| Deck {
                line: &b.deck,
                width: b.width,
            })
            .collect();
        let los = LosScene::new(&terrain, &prisms, &decks)?;
        let zones = ForbiddenZones::new(&map, &config.zones);
        let points = |g: &crate::map::StreetGraph| -> Vec<[f64; 3]> {
            (0..g.graph.node_count() as u32)
                .map(|n| {
                    let p = g.pos(NodeId(n)).map_or([0.0, 0.0], shift);
                    [p[0], p[1], ground_at(p)]
                })
                .collect()
        };
        let street_points = [
            points(map.streets(Mode::Drive)),
            points(map.streets(Mode::Walk)),
        ];
        Ok(Site {
            map,
            terrain,
            offset,
            buildings,
            bridges,
            zones,
            los,
            zone_config: config.zones,
            street_points,
        })
    }

    /// The buffers the forbidden zones were built with.
    pub fn zones_config(&self) -> ZoneConfig {
        self.zone_config
    }
    /// The world point on the ground of node `n` of `mode`'s street graph
    /// ([`Site::on_ground`] of its position, precomputed); `None` for an unknown node.
    pub fn street_point(&self, mode: Mode, n: NodeId) -> Option<[f64; 3]> {
        let i = match mode {
            Mode::Drive => 0,
            Mode::Walk => 1,
        };
        self.street_points[i].get(n.0 as usize).copied()
    }
    /// Town coordinates to world (x, y).
    pub fn to_world(&self, town: P2) -> P2 {
        [town[0] + self.offset[0], town[1] + self.offset[1]]
    }
    /// World (x, y) to town coordinates.
    pub fn to_town(&self, world: P2) -> P2 {
        [world[0] - self.offset[0], world[1] - self.offset[1]]
    }
    /// Ground height at world (x, y) on the ground mesh (the surface line of sight and
    /// physics use); `None` off the terrain.
    pub fn ground(&self, world: P2) -> Option<f64> {
        self.terrain.surface_height(world[0], world[1])
    }
    /// The world point on the ground under a town point (height 0 off the terrain).
    pub fn on_ground(&self, town: P2) -> [f64; 3] {
        let [x, y] = self.to_world(town);
        [x, y, self.ground([x, y]).unwrap_or(0.0)]
    }
    /// True if world (x, y) is in a forbidden zone.
    pub fn is_forbidden(&self, world: P2) -> bool {
        self.zones.is_forbidden(self.to_town(world))
    }
    /// The free world point nearest to world (x, y).
    pub fn nearest_free(&self, world: P2) -> P2 {
        self.to_world(self.zones.nearest_free(self.to_town(world)))
    }

    /// The 3D path of street segment `segment` of the `mode` graph: on the ground, resampled
    /// at least every half terrain cell, or on the bridge deck for a street on a bridge.
    pub fn segment_path(&self, mode: Mode, segment: usize) -> Option<Vec<[f64; 3]>> {
        let seg = self.map.streets(mode).segments.get(segment)?;
        let step = self.terrain.grid().cellsize / 2.0;
        let mut pts: Vec<P2> = Vec::new();
        for w in seg.points.windows(2) {
            let (a, b) = (self.to_world(w[0]), self.to_world(w[1]));
            let n = (crate::geo::dist(a, b) / step).ceil().max(1.0) as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                pts.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
        if let Some(&last) = seg.points.last() {
            pts.push(self.to_world(last));
        }
        let ground_at = |p: P2| self.ground(p).unwrap_or(0.0);
        let deck = seg
            .bridge
            .then(|| {
                self.bridges
                    .iter()
                    .find(|b| self.map.bridges[b.index].osm_id == seg.way)
            })
            .flatten();
        Some(match deck {
            // On the bridge's own deck, the one line of sight sees.
            Some(b) => pts
                .iter()
                .map(|&p| [p[0], p[1], deck_height(&b.deck, p).max(ground_at(p))])
                .collect(),
            None if seg.bridge => ramp(&pts, &ground_at),
            None => pts.iter().map(|&p| [p[0], p[1], ground_at(p)]).collect(),
        })
    }

    /// Length of a street segment following the ground (or bridge deck), metres.
    pub fn segment_length_3d(&self, mode: Mode, segment: usize) -> Option<f64> {
        let path = self.segment_path(mode, segment)?;
        Some(
            path.windows(2)
                .map(|w| {
                    let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
                    libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
                })
                .sum(),
        )
    }
}

/// Height of a deck polyline at the point of it nearest to `p` (interpolated along the
/// nearest piece).
fn deck_height(deck: &[[f64; 3]], p: P2) -> f64 {
    let mut best = (f64::INFINITY, deck.first().map_or(0.0, |q| q[2]));
    for w in deck.windows(2) {
        let (a, b) = ([w[0][0], w[0][1]], [w[1][0], w[1][1]]);
        let q = crate::geo::closest_on_segment(p, a, b);
        let d = crate::geo::dist(p, q);
        if d < best.0 {
            let l = crate::geo::dist(a, b);
            let t = if l > 0.0 {
                crate::geo::dist(a, q) / l
            } else {
                0.0
            };
            best = (d, w[0][2] + t * (w[1][2] - w[0][2]));
        }
    }
    best.1
}

/// Heights along a line: a straight ramp between the ground at both ends, lifted to the
/// ground wherever the ground is higher.
fn ramp(line: &[P2], ground: &impl Fn(P2) -> f64) -> Vec<[f64; 3]> {
    let (Some(&first), Some(&last)) = (line.first(), line.last()) else {
        return Vec::new();
    };
    let total = polyline_length(line);
    let (z0, z1) = (ground(first), ground(last));
    let mut s = 0.0;
    let mut prev = first;
    line.iter()
        .map(|&p| {
            s += crate::geo::dist(prev, p);
            prev = p;
            let t = if total > 0.0 { s / total } else { 0.0 };
            [p[0], p[1], (z0 + t * (z1 - z0)).max(ground(p))]
        })
        .collect()
}
