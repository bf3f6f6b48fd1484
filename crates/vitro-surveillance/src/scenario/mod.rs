//! The surveillance scenario file: plain serde types, one per TOML table.
//!
//! The tables every mission shares come from `vitro_tactical::scenario` (`[end]`, `[site]`,
//! `[fidelity]`, `[[entity]]`, `[channel]`, `[record]`, and the camera's
//! [`VisionSpec`]); the mission's own are the ground control station, the search area and
//! its sectors, the areas tasked later, UAV losses, the team's radio discipline, tracking,
//! the contract net's deadlines and the red units' movement. Every table but `[end]`,
//! `[site]`, `[station]` and the entities has defaults; unknown keys are errors.
//!
//! ```
//! use vitro_surveillance::scenario::SurveillanceFile;
//!
//! let text = r#"
//! kind = "surveillance"
//! name = "tiny"
//! seed = 7
//! end = { time_s = 600 }
//! site = { map = "town.osm.pbf", terrain = "valley.asc" }
//! station = { start = [0, 0] }
//!
//! [[entity]]
//! name = "uav"
//! type = "vidar"
//! side = "blue"
//! count = 3
//! altitude_m = 120
//!
//! [[entity]]
//! name = "red"
//! type = "trooper"
//! side = "red"
//! count = 4
//! "#;
//! let file: SurveillanceFile = toml::from_str(text).unwrap();
//! assert_eq!(file.entities[0].count, 3);
//! assert_eq!(file.search.sector_m, 400.0);
//! assert_eq!(file.tracking.misses_to_lose, 3);
//! assert!(file.losses.is_empty());
//! ```

mod check;
mod parse;

pub use check::{Validated, validate_text};
pub use parse::TOP_LEVEL_KEYS;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use vitro::time::UtcTime;
use vitro_tactical::scenario::{
    ChannelSpec, EndSpec, EntitySpec, FidelitySpec, RecordSpec, START_PATTERN, SiteSpec, VisionSpec,
};

/// A whole scenario file of the surveillance mission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = schema_rules)]
pub struct SurveillanceFile {
    /// The kind of scenario, `"surveillance"`: the tools pick the mission by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("const" = "surveillance"))]
    pub kind: Option<String>,
    /// A short name for reports.
    #[schemars(regex(pattern = r"\S"))]
    pub name: String,
    /// Master seed of every random stream of the run.
    pub seed: u64,
    /// When simulated time 0 is on the calendar, RFC 3339 (`"2024-06-01T06:00:00Z"`;
    /// default 2024-06-01T06:00:00Z): the recording, KML tracks and the viewer's clock
    /// show it, the simulation never reads it (no trace changes with it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<String>", extend("pattern" = START_PATTERN, "format" = "date-time"))]
    pub start: Option<UtcTime>,
    /// When the run stops.
    pub end: EndSpec,
    /// The town and its terrain.
    pub site: SiteSpec,
    /// Fidelity level of each entity type.
    #[serde(default)]
    pub fidelity: FidelitySpec,
    /// The ground control station: the contract net's manager.
    pub station: StationSpec,
    /// The entities, one `[[entity]]` table per group: blue UAVs (procerus, vidar,
    /// skeldar) and red units (trooper, car, truck, ugv).
    #[serde(rename = "entity")]
    pub entities: Vec<EntitySpec>,
    /// The area searched from the start, and how it is cut into sectors.
    #[serde(default)]
    pub search: SearchSpec,
    /// Areas tasked later, one `[[area]]` table each.
    #[serde(default, rename = "area", skip_serializing_if = "Vec::is_empty")]
    pub areas: Vec<AreaSpec>,
    /// UAVs lost at set times, one `[[loss]]` table each.
    #[serde(default, rename = "loss", skip_serializing_if = "Vec::is_empty")]
    pub losses: Vec<LossSpec>,
    /// Random UAV failures.
    #[serde(default)]
    pub failures: FailureSpec,
    /// The team's radio discipline and flying.
    #[serde(default)]
    pub team: TeamSpec,
    /// The UAVs' camera.
    #[serde(default)]
    pub sensors: SensorSpec,
    /// Locks of the tracking sensor.
    #[serde(default)]
    pub tracking: TrackingSpec,
    /// How the sectors are shared out, and the deadlines.
    #[serde(default)]
    pub allocation: AllocationSpec,
    /// How the red units move.
    #[serde(default)]
    pub red: RedSpec,
    /// The simulated radio channel.
    #[serde(default)]
    pub channel: ChannelSpec,
    /// Sampling of the recording.
    #[serde(default)]
    pub record: RecordSpec,
}

/// The surveillance mission's rules on top of the shared tables' schemas: `kind` is
/// required, and every entity is a blue UAV or a red ground unit.
fn schema_rules(schema: &mut schemars::Schema) {
    vitro_tactical::scenario::require_kind(schema);
    let roles = schemars::json_schema!({
        "anyOf": [
            {
                "properties": {
                    "side": { "const": "blue" },
                    "type": { "enum": ["procerus", "vidar", "skeldar"] }
                }
            },
            {
                "properties": {
                    "side": { "const": "red" },
                    "type": { "enum": ["trooper", "car", "truck", "ugv"] }
                }
            }
        ]
    });
    if let Some(items) = schema
        .get_mut("properties")
        .and_then(|p| p.get_mut("entity"))
        .and_then(|e| e.get_mut("items"))
    {
        let entity = items.take();
        *items = schemars::json_schema!({ "allOf": [entity, roles] }).into();
    }
}

/// The ground control station: a command vehicle parked at a junction, whose operator
/// shares the sectors out by contract net.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StationSpec {
    /// Where it is parked, town metres `[x, y]` (the nearest junction).
    pub start: [f64; 2],
}

/// The search area and its sectors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SearchSpec {
    /// The area, town metres `[x_min, y_min, x_max, y_max]` (none: the whole town).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub area: Option<[f64; 4]>,
    /// Largest side of a sector, metres: each area is cut into the fewest equal columns
    /// and rows no wider than this.
    #[schemars(range(min = 50.0, max = 10_000.0))]
    pub sector_m: f64,
    /// Distance between the parallel tracks a UAV flies over a sector, metres.
    #[schemars(range(min = 10.0, max = 10_000.0))]
    pub spacing_m: f64,
}

impl Default for SearchSpec {
    fn default() -> Self {
        SearchSpec {
            area: None,
            sector_m: 400.0,
            spacing_m: 200.0,
        }
    }
}

/// An area tasked to the station during the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AreaSpec {
    /// When the tasking reaches the station, seconds after the start.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub appear_s: f64,
    /// The area, town metres `[x_min, y_min, x_max, y_max]`, cut into sectors like the
    /// search area.
    pub area: [f64; 4],
}

/// A UAV lost at a set time (shot down, crashed): it stops flying, sensing and talking.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LossSpec {
    /// The UAV's name (`name` of its entity, or `name-i` in a group).
    pub uav: String,
    /// When, seconds after the start.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub at_s: f64,
}

/// Random UAV failures.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FailureSpec {
    /// Failures per UAV per hour of flight (exponential times drawn from the seed; 0:
    /// none).
    #[schemars(range(min = 0.0, max = 1000.0))]
    pub rate_per_h: f64,
}

/// The team's radio discipline and flying.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TeamSpec {
    /// Period of each UAV's status report (position, sectors, tracks) to the team and the
    /// station, seconds.
    #[schemars(range(max = 3600.0), extend("exclusiveMinimum" = 0.0))]
    pub heartbeat_s: f64,
    /// The station presumes a UAV lost when it has heard nothing from it this long, and
    /// shares its sectors out again, seconds.
    #[schemars(range(max = 36_000.0), extend("exclusiveMinimum" = 0.0))]
    pub lost_after_s: f64,
    /// Period of the sighting reports of a UAV that holds locks, seconds.
    #[schemars(range(max = 3600.0), extend("exclusiveMinimum" = 0.0))]
    pub report_s: f64,
    /// A teammate's report of a track is taken as current this long, seconds.
    #[schemars(range(max = 36_000.0), extend("exclusiveMinimum" = 0.0))]
    pub report_fresh_s: f64,
    /// Radius of the orbit a fixed-wing UAV flies around a tracked target, metres
    /// (helicopters hover over it).
    #[schemars(range(min = 20.0, max = 5000.0))]
    pub orbit_m: f64,
    /// How long a UAV that lost its track searches around the target's predicted position
    /// before it goes back to its sectors, seconds.
    #[schemars(range(min = 0.0, max = 36_000.0))]
    pub reacquire_s: f64,
    /// A searching UAV goes to look for a target a teammate reported within this
    /// distance, if nobody follows it, metres (0: never).
    #[schemars(range(min = 0.0, max = 1e5))]
    pub cue_m: f64,
}

impl Default for TeamSpec {
    fn default() -> Self {
        TeamSpec {
            heartbeat_s: 5.0,
            lost_after_s: 30.0,
            report_s: 5.0,
            report_fresh_s: 15.0,
            orbit_m: 150.0,
            reacquire_s: 60.0,
            cue_m: 600.0,
        }
    }
}

/// The UAVs' camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SensorSpec {
    /// Time between two looks, seconds.
    #[schemars(range(max = 600.0), extend("exclusiveMinimum" = 0.0))]
    pub period_s: f64,
    /// Friend-or-foe vision of the UAVs.
    pub camera: VisionSpec,
}

impl Default for SensorSpec {
    fn default() -> Self {
        SensorSpec {
            period_s: 1.0,
            camera: VisionSpec {
                range_m: 350.0,
                fov_deg: 360.0,
                p0: 0.9,
                falloff: 1.0,
                misidentification: 0.05,
            },
        }
    }
}

/// Locks of the tracking sensor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TrackingSpec {
    /// Missed looks in a row that lose a lock (1: the first miss).
    #[schemars(range(min = 1, max = 10_000))]
    pub misses_to_lose: u32,
    /// Looks in a row that must take a new target for red before it is locked, and that
    /// must take a locked one for another side before the lock is dropped (identification
    /// errors then rarely make a lock).
    #[schemars(range(min = 1, max = 1000))]
    pub confirm_looks: u32,
    /// Most locks a UAV holds at once.
    #[schemars(range(min = 1, max = 100))]
    pub max_locks: u32,
}

impl Default for TrackingSpec {
    fn default() -> Self {
        TrackingSpec {
            misses_to_lose: 3,
            confirm_looks: 3,
            max_locks: 4,
        }
    }
}

/// How the station shares the sectors out among the UAVs.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum AllocationMethod {
    /// One call for proposals per sector (`vitro::protocol::contract_net`): each UAV bids
    /// the seconds until it would have searched the sector, the lowest bid wins.
    #[default]
    ContractNet,
    /// The station solves the waiting sectors as a capacitated vehicle routing problem
    /// (`vitro_routing`'s large neighbourhood search, from the station's position, one tour
    /// per UAV it believes flying) and sends each UAV its tour; the search is charged in
    /// simulated time.
    Central,
    /// Sequential single-item auctions over the radio: each round the station announces
    /// every waiting sector, each UAV bids for the one it adds most cheaply, the lowest bid
    /// wins (announced with the next round).
    Auction,
}

/// How the sectors are shared out: the method, the contract net's deadlines (also the
/// auction's and the central plan's) and the central search's budget.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct AllocationSpec {
    /// `contract-net` (default), `central` or `auction`.
    pub method: AllocationMethod,
    /// The central search's iterations (ruin-and-recreate steps of the large neighbourhood
    /// search).
    #[schemars(range(min = 1, max = 1_000_000))]
    pub budget: u64,
    /// Simulated time the central search takes per iteration, milliseconds: the station's
    /// tours are sent once the search is over.
    #[schemars(range(min = 0.0, max = 10_000.0))]
    pub iteration_ms: f64,
    /// How long after a call for proposals (or an auction round) the station decides, at the
    /// latest, seconds.
    #[schemars(range(max = 3600.0), extend("exclusiveMinimum" = 0.0))]
    pub proposal_deadline_s: f64,
    /// How long the winner has to confirm it holds the sector, seconds (for the auction and
    /// the central plan: a UAV's status report claiming it, within this plus a heartbeat).
    #[schemars(range(max = 3600.0), extend("exclusiveMinimum" = 0.0))]
    pub report_deadline_s: f64,
    /// How long a UAV's proposal binds without an answer, seconds (longer than the
    /// proposal deadline plus the channel's delays).
    #[schemars(range(max = 36_000.0), extend("exclusiveMinimum" = 0.0))]
    pub proposal_expiry_s: f64,
    /// A sector whose call failed is called again after this long, seconds.
    #[schemars(range(max = 36_000.0), extend("exclusiveMinimum" = 0.0))]
    pub retry_s: f64,
}

impl Default for AllocationSpec {
    fn default() -> Self {
        AllocationSpec {
            method: AllocationMethod::ContractNet,
            budget: 500,
            iteration_ms: 0.5,
            proposal_deadline_s: 2.0,
            report_deadline_s: 5.0,
            proposal_expiry_s: 4.0,
            retry_s: 10.0,
        }
    }
}

/// How the red units move: from a junction to another drawn at random, a pause, again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct RedSpec {
    /// Distance to the next destination, metres `[min, max]` (straight line).
    #[schemars(inner(range(min = 0.0)))]
    pub leg_m: [f64; 2],
    /// Pause at each destination, seconds `[min, max]`.
    #[schemars(inner(range(min = 0.0)))]
    pub dwell_s: [f64; 2],
}

impl Default for RedSpec {
    fn default() -> Self {
        RedSpec {
            leg_m: [150.0, 600.0],
            dwell_s: [30.0, 180.0],
        }
    }
}

/// The JSON Schema of surveillance scenario files (draft 7, for editors): what
/// `scenarios/surveillance.schema.json` holds, pretty-printed.
///
/// ```
/// let schema = vitro_surveillance::scenario::json_schema();
/// assert_eq!(schema.get("title").and_then(|t| t.as_str()), Some("SurveillanceFile"));
/// ```
pub fn json_schema() -> schemars::Schema {
    let generator = schemars::generate::SchemaSettings::draft07().into_generator();
    generator.into_root_schema_for::<SurveillanceFile>()
}
