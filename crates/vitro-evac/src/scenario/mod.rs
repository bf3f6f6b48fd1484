//! The evacuation mission's scenario file: plain serde types, one per TOML table.
//!
//! A scenario names the town and its terrain ([`SiteSpec`]), the three places of the mission
//! ([`Places`]), the entities by type, side and start ([`EntitySpec`]), the fidelity level of
//! each entity type ([`FidelitySpec`]) and the settings of the mission, the sensors, the radio
//! channel and the algorithms. Every table but `[site]`, `[places]`, `[end]` and the
//! entities has defaults, and unknown keys are errors.
//!
//! ```
//! use vitro_evac::scenario::ScenarioFile;
//! use vitro_tactical::scenario::EntityType;
//! use vitro_tactical::entity::Level;
//!
//! let text = r#"
//! name = "tiny"
//! seed = 7
//! end = { time_s = 600 }
//! site = { map = "town.osm.pbf", terrain = "valley.asc" }
//! places = { start = [0, 0], safehouse = [500, 0], extraction = [0, 500] }
//! fidelity = { level = "interpolated", truck = "physical" }
//!
//! [[entity]]
//! name = "truck"
//! type = "truck"
//! side = "blue"
//! "#;
//! let file: ScenarioFile = toml::from_str(text).unwrap();
//! assert_eq!(file.entities[0].count, 1);
//! assert_eq!(file.fidelity.level_of(EntityType::Truck), Level::Physical);
//! assert_eq!(file.fidelity.level_of(EntityType::Vip), Level::Directed);
//! assert_eq!(file.mission.pickup_s, 30.0);
//! ```

mod check;
mod env;
mod load;
mod loaded;

pub use env::{EnvSpec, RewardSpec};
pub use load::{TOP_LEVEL_KEYS, Validated};
pub use loaded::Loaded;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use vitro::time::UtcTime;
use vitro_tactical::scenario::{
    ChannelSpec, EndSpec, EntitySpec, FidelitySpec, RecordSpec, START_PATTERN, SiteSpec, TieOrder,
    VisionSpec, require_kind,
};

/// A whole scenario file of the evacuation mission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = require_kind)]
pub struct ScenarioFile {
    /// The kind of scenario, `"evacuation"`: the tools pick the mission by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("const" = "evacuation"))]
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
    /// The order of events due at the same time: `"fifo"` (default: first scheduled, first
    /// fired) or `"shuffled"` (a seeded random order, to check an outcome is not an artefact
    /// of the order agents were added or woke).
    #[serde(default)]
    pub tie_order: TieOrder,
    /// When the run stops.
    pub end: EndSpec,
    /// The town and its terrain.
    pub site: SiteSpec,
    /// Fidelity level of each entity type.
    #[serde(default)]
    pub fidelity: FidelitySpec,
    /// Start, safehouse and extraction points.
    pub places: Places,
    /// The entities, one `[[entity]]` table per group.
    #[serde(rename = "entity")]
    pub entities: Vec<EntitySpec>,
    /// Mission parameters.
    #[serde(default)]
    pub mission: MissionSpec,
    /// Friend-or-foe vision of ground units and aircraft.
    #[serde(default)]
    pub sensors: SensorsSpec,
    /// The simulated radio channel.
    #[serde(default)]
    pub channel: ChannelSpec,
    /// Randomized patrolling of the convoy (Stackelberg game).
    #[serde(default)]
    pub patrol: PatrolSpec,
    /// Pursuit of the high-value target.
    #[serde(default)]
    pub pursuit: PursuitSpec,
    /// Plan repair of the VTOL support team.
    #[serde(default)]
    pub repair: RepairSpec,
    /// Rule-programmed troop formations.
    #[serde(default)]
    pub formation: FormationSpec,
    /// Sampling of the recording.
    #[serde(default)]
    pub record: RecordSpec,
    /// Settings of the learning environment (the mission never reads them).
    #[serde(default, skip_serializing_if = "is_default")]
    pub env: EnvSpec,
}

fn is_default(env: &EnvSpec) -> bool {
    *env == EnvSpec::default()
}

/// Start, safehouse and extraction, town metres (x east, y north from the town origin).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Places {
    /// Where the team sets out.
    pub start: [f64; 2],
    /// Where the truck stops for the VIP; the VIP itself waits where its `vip` entity
    /// starts, and the escort fetches it on foot from here.
    pub safehouse: [f64; 2],
    /// Where the VIP is taken.
    pub extraction: [f64; 2],
}

/// Mission parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MissionSpec {
    /// Time to get the VIP on board at the safehouse, seconds.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub pickup_s: f64,
    /// When the HVT appears, seconds after the start.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub hvt_appear_s: f64,
    /// How many troopers split off to pursue the HVT.
    #[schemars(range(max = 20_000))]
    pub hvt_pursuers: u32,
    /// A pursuer within this distance of the HVT captures it, metres.
    #[schemars(range(max = 1e4), extend("exclusiveMinimum" = 0.0))]
    pub capture_range_m: f64,
    /// Red attacks a blue unit it sees within this distance, metres.
    #[schemars(range(max = 1e4), extend("exclusiveMinimum" = 0.0))]
    pub attack_range_m: f64,
    /// Time a red attacker aims before it fires, seconds.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub attack_aim_s: f64,
    /// Probability that an attack hits, in [0, 1].
    #[schemars(range(min = 0.0, max = 1.0))]
    pub hit_probability: f64,
    /// A team member within this distance of a friendly watcher is covered, metres.
    #[schemars(range(max = 1e4), extend("exclusiveMinimum" = 0.0))]
    pub cover_radius_m: f64,
}

impl Default for MissionSpec {
    fn default() -> Self {
        MissionSpec {
            pickup_s: 30.0,
            hvt_appear_s: 600.0,
            hvt_pursuers: 2,
            capture_range_m: 15.0,
            attack_range_m: 150.0,
            attack_aim_s: 15.0,
            hit_probability: 0.3,
            cover_radius_m: 200.0,
        }
    }
}

/// The sensors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SensorsSpec {
    /// Time between two looks of each sensor, seconds.
    #[schemars(range(max = 3600.0), extend("exclusiveMinimum" = 0.0))]
    pub period_s: f64,
    /// Time between two position reports of each blue unit over the radio (blue-force
    /// tracking: its own GPS fix), seconds; 0 sends none.
    #[schemars(range(min = 0.0, max = 3600.0))]
    pub report_period_s: f64,
    /// A position report or an own sighting older than this is no longer used to estimate
    /// where a unit is, seconds.
    #[schemars(range(max = 1e6), extend("exclusiveMinimum" = 0.0))]
    pub stale_s: f64,
    /// Vision of ground units.
    pub ground: VisionSpec,
    /// Vision of aircraft.
    pub air: VisionSpec,
}

impl Default for SensorsSpec {
    fn default() -> Self {
        SensorsSpec {
            period_s: 1.0,
            report_period_s: 5.0,
            stale_s: 60.0,
            ground: VisionSpec {
                range_m: 300.0,
                fov_deg: 120.0,
                p0: 0.95,
                falloff: 1.0,
                misidentification: 0.05,
            },
            air: VisionSpec {
                range_m: 600.0,
                fov_deg: 360.0,
                p0: 0.9,
                falloff: 1.0,
                misidentification: 0.1,
            },
        }
    }
}

/// Randomized patrolling of the convoy: the Skeldars' patrolling game (a Stackelberg game
/// solved when the mission is built; see `evac::agents::patrol`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PatrolSpec {
    /// Duration of one patrol step, seconds: a Skeldar flies to its next checkpoint each step.
    #[schemars(range(max = 1e6), extend("exclusiveMinimum" = 0.0))]
    pub step_s: f64,
    /// Steps an attacker needs to complete an attack (a Skeldar over the target at one of
    /// them catches it).
    #[schemars(range(min = 1, max = 100))]
    pub attack_steps: u32,
    /// Steps the game looks ahead: besides the convoy, the patrol guards the route where the
    /// convoy will be this many steps later (0: the convoy only, which a Skeldar guards by
    /// riding along, without randomness).
    #[schemars(range(max = 100))]
    pub horizon: u32,
    /// LP iterations of each local search of the patrol solver (more: closer to the
    /// optimum, a slower mission setup).
    #[schemars(range(min = 1, max = 1000))]
    pub iterations: u32,
    /// Red troopers that play the game's attacker (the first ones): briefed with the
    /// patrol's policies and the convoy's timetable, each watches the Skeldars and the
    /// truck and strikes the convoy or the route ahead once, at the start the game's
    /// attacker picks (0: none; scored in the report, the convoy is not hurt).
    #[schemars(range(max = 100))]
    pub attackers: u32,
    /// How far the game's attacker sees the Skeldars and the truck, metres (horizontally;
    /// line of sight not checked).
    #[schemars(range(max = 1e6), extend("exclusiveMinimum" = 0.0))]
    pub watch_range_m: f64,
}

impl Default for PatrolSpec {
    fn default() -> Self {
        PatrolSpec {
            step_s: 20.0,
            attack_steps: 3,
            horizon: 2,
            iterations: 5,
            attackers: 1,
            watch_range_m: 2000.0,
        }
    }
}

/// The game-tree search that pursues the HVT.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum PursuitAlgorithm {
    /// Information-set Monte Carlo tree search.
    #[default]
    Mcts,
    /// Iterative-deepening minimax.
    Minimax,
}

/// Which family of search the hunt lead plays (the HVT always evades with the
/// determinized one: the game searches assume an evader that sees the pursuers).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum PursuitLead {
    /// Information-set search over sampled determinizations with a scripted ε-greedy
    /// evader inside (`vitro_algo::pursuit`'s `Mcts` / `Minimax`).
    #[default]
    Determinized,
    /// The game searches: MO-ISMCTS or worst-case minimax over the team's information
    /// sets, the evader's decisions in the tree (`vitro_algo::pursuit::game`).
    Game,
}

/// Pursuit of the HVT.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PursuitSpec {
    /// The search.
    pub algorithm: PursuitAlgorithm,
    /// The hunt lead's family of search.
    pub lead: PursuitLead,
    /// Iterations per decision.
    #[schemars(range(min = 1, max = 10_000_000))]
    pub budget: u32,
    /// Simulated thinking time charged per iteration, microseconds.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub think_us_per_iteration: f64,
    /// Turns (walk-graph moves) each MCTS simulation plays out (minimax deepens iteratively
    /// within its budget instead).
    #[schemars(range(min = 1, max = 1000))]
    pub horizon: u32,
}

impl Default for PursuitSpec {
    fn default() -> Self {
        PursuitSpec {
            algorithm: PursuitAlgorithm::Mcts,
            lead: PursuitLead::Determinized,
            budget: 500,
            think_us_per_iteration: 20.0,
            horizon: 30,
        }
    }
}

/// How the VTOL team's plan is repaired.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RepairStrategy {
    /// Plan again from scratch.
    Replan,
    /// Plan back to the broken plan's state, then follow it.
    BackOnTrack,
    /// Plan only to the broken action's goal.
    Lazy,
    /// Lazy repair, widened step by step.
    #[default]
    RepeatedLazy,
}

/// Plan repair of the VTOL support team.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct RepairSpec {
    /// The strategy.
    pub strategy: RepairStrategy,
    /// Deepest repair tried before replanning (none: no limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 1))]
    pub max_depth: Option<u32>,
    /// Probability that a Vidar's look at a checkpoint fails (glare, smoke, a gust), and
    /// that a Vidar other than the lead is recalled during the mission.
    #[schemars(range(min = 0.0, max = 1.0))]
    pub failure_rate: f64,
}

/// Troop formations.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FormationSpec {
    /// Rule file, relative to the scenario file's directory (none: the built-in rules).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<PathBuf>,
    /// Spacing between troopers, metres.
    #[schemars(range(max = 100.0), extend("exclusiveMinimum" = 0.0))]
    pub spacing_m: f64,
}

impl Default for FormationSpec {
    fn default() -> Self {
        FormationSpec {
            program: None,
            spacing_m: 5.0,
        }
    }
}

/// The JSON Schema of scenario files (draft 7, for editors): what
/// `scenarios/scenario.schema.json` holds, pretty-printed.
///
/// ```
/// let schema = vitro_evac::scenario::json_schema();
/// assert_eq!(schema.get("title").and_then(|t| t.as_str()), Some("ScenarioFile"));
/// ```
pub fn json_schema() -> schemars::Schema {
    let generator = schemars::generate::SchemaSettings::draft07().into_generator();
    generator.into_root_schema_for::<ScenarioFile>()
}
