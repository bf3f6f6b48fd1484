//! Frames and scenes: the plain data of a recording.
//!
//! World coordinates are metres, `x` east, `y` north, `z` up (the simulator's world frame);
//! [`Geo`] turns them into latitude and longitude. Times are simulated nanoseconds.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Allegiance as the viewer draws it (MIL-STD-2525 affiliations).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Own forces (blue).
    Friendly,
    /// Adversaries (red).
    Hostile,
    /// Civilians, bystanders (green).
    Neutral,
    /// Not identified (yellow).
    Unknown,
}

/// One entity at one instant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EntityState {
    /// Entity id (stable over the run).
    pub id: u32,
    /// Entity name (unique).
    pub name: String,
    /// Entity type: `"truck"`, `"car"`, `"ugv"`, `"trooper"`, `"vip"`, `"hvt"`, `"ctol"`,
    /// `"vtol"`, ...
    pub kind: String,
    /// Allegiance.
    pub side: Side,
    /// Fidelity level: `"discrete"`, `"interpolated"`, `"physical"`, `"directed"`,
    /// `"kinematic"`, `"dynamic"`.
    pub level: String,
    /// Position of the base (feet, wheels, aircraft centre), world metres.
    pub pos: [f64; 3],
    /// Heading, radians counter-clockwise from east.
    pub heading: f64,
    /// Speed over ground, m/s.
    pub speed: f64,
    /// Condition: `"active"`, `"down"`, `"captured"`, `"aboard"`, `"extracted"`, ...
    pub status: String,
}

/// A sensor detection: `observer` sees `target` this instant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Detection {
    /// Who sees.
    pub observer: u32,
    /// Who is seen.
    pub target: u32,
    /// The observer's eye, world metres.
    pub from: [f64; 3],
    /// The target's centre, world metres.
    pub to: [f64; 3],
    /// The side the observer believes the target is on.
    pub seen_as: Side,
}

/// A message sent through the simulated network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MessageEvent {
    /// When it was sent, simulated nanoseconds.
    pub t_ns: u64,
    /// Sender.
    pub from: u32,
    /// Receiver (`None`: broadcast or a group).
    pub to: Option<u32>,
    /// What it is about (the message variant, e.g. `"contact"`, `"bid"`).
    pub kind: String,
    /// Whether it was delivered (`false`: lost or bounced).
    pub delivered: bool,
}

/// An agent's current intention and plan, as the agent states it.
///
/// Only `id` and `text` are needed; the other fields are optional views of the agent's mind
/// (empty when the agent has nothing to show), so build one with `..Default::default()`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Intention {
    /// The agent.
    pub id: u32,
    /// One line: what it is doing and why (e.g. `"escort VIP to extraction"`).
    pub text: String,
    /// The steps of its current plan, if it has one (e.g. PDDL actions, formation names).
    pub plan: Vec<String>,
    /// The path it means to follow, world metres (may be empty).
    pub path: Vec<[f64; 3]>,
    /// The plan as first made, when `plan` is a repair of it (empty if never repaired).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub original_plan: Vec<String>,
    /// The path of the original plan, when `path` is a repair of it (may be empty).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub original_path: Vec<[f64; 3]>,
    /// A policy over places as weights (e.g. a patroller's visit probabilities), world metres;
    /// any non-negative scale, the viewer draws it relative to the largest weight.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub heat: Vec<([f64; 3], f64)>,
    /// Where the agent believes its quarry is (e.g. a pursuer's belief about the evader), as
    /// weighted places, world metres; any non-negative scale.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub belief: Vec<([f64; 3], f64)>,
}

/// What one sensor covers this instant: a sector around its entity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorFootprint {
    /// The entity carrying the sensor (the sector is centred on its position).
    pub id: u32,
    /// What it is (e.g. `"camera"`, `"proximity"`).
    pub kind: String,
    /// Range, metres.
    pub range: f64,
    /// Direction of the sector's axis, radians counter-clockwise from east.
    pub heading: f64,
    /// Full opening angle, radians (2π or more: all around).
    pub fov: f64,
}

/// Everything that changes, at one sampled instant.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// Simulated time, nanoseconds.
    pub t_ns: u64,
    /// Events fired so far.
    pub events: u64,
    /// Every entity with a body, by id.
    pub entities: Vec<EntityState>,
    /// Detections this instant.
    pub detections: Vec<Detection>,
    /// Messages sent since the previous frame.
    pub messages: Vec<MessageEvent>,
    /// Intentions of the agents that state one.
    pub intentions: Vec<Intention>,
    /// Sensor coverage this instant (optional: empty when not recorded).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<SensorFootprint>,
    /// Mission metrics so far (name → value).
    pub metrics: BTreeMap<String, f64>,
    /// A one-line account of what happened since the previous frame, if anything did
    /// (e.g. `"VIP picked up"`).
    pub log: Vec<String>,
}

/// World coordinates to latitude and longitude: a local equirectangular projection.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Geo {
    /// Latitude of the town origin, degrees.
    pub lat0: f64,
    /// Longitude of the town origin, degrees.
    pub lon0: f64,
    /// Metres per degree of latitude at the origin.
    pub m_per_deg_lat: f64,
    /// Metres per degree of longitude at the origin.
    pub m_per_deg_lon: f64,
    /// World position of the town origin, metres.
    pub offset: [f64; 2],
    /// Height of world `z = 0` above mean sea level, metres.
    pub z0: f64,
}

impl Geo {
    /// `[lat, lon, altitude above sea level]` of a world point.
    ///
    /// ```
    /// use vitro_record::Geo;
    /// let g = Geo { lat0: 60.0, lon0: 27.0, m_per_deg_lat: 111_000.0, m_per_deg_lon: 55_500.0,
    ///               offset: [100.0, 0.0], z0: 5.0 };
    /// assert_eq!(g.to_wgs84([100.0, 111.0, 1.0]), [60.001, 27.0, 6.0]);
    /// ```
    pub fn to_wgs84(&self, p: [f64; 3]) -> [f64; 3] {
        [
            self.lat0 + (p[1] - self.offset[1]) / self.m_per_deg_lat,
            self.lon0 + (p[0] - self.offset[0]) / self.m_per_deg_lon,
            p[2] + self.z0,
        ]
    }
}

impl Scene {
    /// An empty scene named `name` on flat ground over `extent` (`[x0, y0, x1, y1]`, metres),
    /// simulated time 0 at `start_unix_ms` on the calendar, for a world on no map: the
    /// geo-reference is an arbitrary one (at latitude and longitude 0), for tools that want
    /// one. A mission adds its own layers.
    ///
    /// ```
    /// let mut scene = vitro_record::Scene::flat("walk".into(), 0, [-100.0, -10.0, 100.0, 10.0]);
    /// scene.streets.push(vec![[-100.0, 0.0, 0.0], [100.0, 0.0, 0.0]]);
    /// assert_eq!(scene.terrain.z, [0.0; 4]);
    /// ```
    pub fn flat(name: String, start_unix_ms: i64, extent: [f64; 4]) -> Scene {
        Scene {
            name,
            start_unix_ms,
            geo: Geo {
                lat0: 0.0,
                lon0: 0.0,
                m_per_deg_lat: 110_574.0,
                m_per_deg_lon: 111_320.0,
                offset: [0.0, 0.0],
                z0: 0.0,
            },
            extent,
            streets: Vec::new(),
            paths: Vec::new(),
            buildings: Vec::new(),
            bridges: Vec::new(),
            forbidden: Vec::new(),
            places: BTreeMap::new(),
            terrain: Heightmap {
                nx: 2,
                ny: 2,
                origin: [extent[0], extent[1]],
                cell: (extent[2] - extent[0]).max(extent[3] - extent[1]),
                z: vec![0.0; 4],
            },
        }
    }
}

/// A building: footprint on the ground and height.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Building {
    /// Outer ring, world metres (not closed: the last point differs from the first).
    pub footprint: Vec<[f64; 2]>,
    /// Ground height under the building, world metres.
    pub base: f64,
    /// Height above its base, metres.
    pub height: f64,
}

/// A regular grid of ground heights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Heightmap {
    /// Columns (x).
    pub nx: usize,
    /// Rows (y).
    pub ny: usize,
    /// World position of sample (0, 0), metres.
    pub origin: [f64; 2],
    /// Spacing between samples, metres.
    pub cell: f64,
    /// Heights, row-major from `origin` (row `j` at `y = origin[1] + j·cell`), world metres.
    pub z: Vec<f32>,
}

/// The static world a run plays in: what a viewer draws once.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Scenario name.
    pub name: String,
    /// When simulated time 0 is on the calendar (the scenario's `start`), milliseconds
    /// since 1970-01-01T00:00:00Z, UTC. Absent from older recordings, read as 0.
    #[serde(default)]
    pub start_unix_ms: i64,
    /// Geo-reference of the world frame.
    pub geo: Geo,
    /// World extent `[min_x, min_y, max_x, max_y]` of the town, metres.
    pub extent: [f64; 4],
    /// Street centre lines (drivable), world metres.
    pub streets: Vec<Vec<[f64; 3]>>,
    /// Footpaths, world metres.
    pub paths: Vec<Vec<[f64; 3]>>,
    /// Buildings.
    pub buildings: Vec<Building>,
    /// Bridge decks, world metres.
    pub bridges: Vec<Vec<[f64; 3]>>,
    /// Forbidden zones: outer rings, world metres.
    pub forbidden: Vec<Vec<[f64; 2]>>,
    /// Named places of the mission (e.g. `"safehouse"`, `"extraction"`), world metres.
    pub places: BTreeMap<String, [f64; 3]>,
    /// The ground.
    pub terrain: Heightmap,
}
