//! The evacuation mission's scenario file: plain serde types, one per TOML table.
//!
//! A scenario names the town and its terrain ([`SiteSpec`]), the three places of the mission
//! ([`Places`]), the entities by type, side and start ([`EntitySpec`]), the fidelity level of
//! each entity type ([`FidelitySpec`]) and the settings of the mission, the sensors, the radio
//! channel and the algorithms. Every table but `[site]`, `[places]`, `[end]` and the
//! entities has defaults, and unknown keys are errors.
//!
//! ```
//! use vitro_tactical::scenario::{ScenarioFile, EntityType};
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
pub mod checker;
mod env;
mod kind;
mod load;
mod loaded;
mod span;
pub mod tables;

pub use checker::{ALTITUDE_M, MAX_COUNT, MAX_END_S};
pub use env::{EnvSpec, RewardSpec};
pub use load::{TOP_LEVEL_KEYS, Validated};
pub use loaded::Loaded;
pub use span::{Diagnostic, Diagnostics, MAX_PROBLEMS, SourceMap};

use crate::entity::Level;
use crate::sensor::FriendFoeVision;
use crate::world::Side;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use vitro::time::UtcTime;

/// Makes `kind` a required key of a scenario file's schema: the mission's own parser takes
/// a file without it, the tools (which pick the mission by it) do not.
pub fn require_kind(schema: &mut schemars::Schema) {
    if let Some(required) = schema.get_mut("required").and_then(|r| r.as_array_mut()) {
        required.insert(0, "kind".into());
    }
}

/// The form of a scenario's `start` in the JSON Schema (the checker also checks the
/// calendar: month, day, leap years).
pub const START_PATTERN: &str = r"^[0-9]{4}-[0-9]{2}-[0-9]{2}[Tt][0-9]{2}:[0-9]{2}:[0-9]{2}(\.[0-9]{1,9})?([Zz]|[+-][0-9]{2}:[0-9]{2})$";

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

/// The order of events due at the same time.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum TieOrder {
    /// First scheduled, first fired.
    #[default]
    Fifo,
    /// A seeded random order ([`vitro::sim::Simulation::shuffle_ties`]).
    Shuffled,
}

/// The end condition.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EndSpec {
    /// Simulated seconds after which the run stops, in (0, 1e6].
    #[schemars(range(max = 1e6), extend("exclusiveMinimum" = 0.0))]
    pub time_s: f64,
}

/// The town and its terrain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SiteSpec {
    /// OpenStreetMap extract (.osm.pbf), relative to the scenario file's directory.
    pub map: PathBuf,
    /// Elevation model (ESRI ASCII grid or GeoTIFF), relative to the scenario file's directory.
    pub terrain: PathBuf,
    /// Shift of the town on the terrain, metres `[east, north]` (none: centred).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset: Option<[f64; 2]>,
}

/// A fidelity preset for every entity type at once.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// Every entity at its discrete level.
    #[default]
    Discrete,
    /// Ground vehicles interpolated, troopers directed, the fixed-wing UAV kinematic,
    /// helicopters discrete.
    Interpolated,
    /// Ground vehicles as rigid bodies, troopers directed, the fixed-wing UAV kinematic,
    /// helicopters with rotor dynamics.
    Physical,
}

impl Preset {
    /// Every preset, from the most abstract to the most concrete.
    pub const ALL: [Preset; 3] = [Preset::Discrete, Preset::Interpolated, Preset::Physical];
    /// Their names, as a scenario file and `--fidelity` write them, in the same order.
    pub const NAMES: [&'static str; 3] = ["discrete", "interpolated", "physical"];

    /// The preset's name.
    pub fn name(self) -> &'static str {
        Preset::NAMES[self as usize]
    }

    /// The preset named `name`, if any (a tool's `--fidelity`: [`None`] is no override).
    ///
    /// ```
    /// use vitro_tactical::scenario::Preset;
    /// assert_eq!(Preset::named(Some("physical")).unwrap(), Some(Preset::Physical));
    /// assert_eq!(Preset::named(None).unwrap(), None);
    /// let e = Preset::named(Some("high")).unwrap_err();
    /// assert_eq!(e.to_string(), "--fidelity high: expected one of discrete, interpolated, physical");
    /// ```
    ///
    /// # Errors
    /// [`UnknownPreset`] if `name` names no preset.
    pub fn named(name: Option<&str>) -> Result<Option<Preset>, UnknownPreset> {
        let Some(name) = name else { return Ok(None) };
        (Preset::ALL.into_iter())
            .find(|p| p.name() == name)
            .map(Some)
            .ok_or_else(|| UnknownPreset(name.to_owned()))
    }
}

/// A fidelity preset name that names none of [`Preset::NAMES`] (bad input).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("--fidelity {0}: expected one of {names}", names = Preset::NAMES.join(", "))]
pub struct UnknownPreset(pub String);

/// The fidelity level of each entity type: a preset, then an override per type.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FidelitySpec {
    /// The preset.
    pub level: Preset,
    /// Cargo truck: discrete, interpolated or physical.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "interpolated", "physical"]))]
    pub truck: Option<Level>,
    /// Civilian car: discrete, interpolated or physical.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "interpolated", "physical"]))]
    pub car: Option<Level>,
    /// MDARS UGV: discrete, interpolated or physical.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "interpolated", "physical"]))]
    pub ugv: Option<Level>,
    /// Troopers, the VIP and the HVT: discrete or directed.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "directed"]))]
    pub trooper: Option<Level>,
    /// Procerus fixed-wing UAV: discrete or kinematic.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "kinematic"]))]
    pub procerus: Option<Level>,
    /// Vidar helicopter UAV: discrete or dynamic.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "dynamic"]))]
    pub vidar: Option<Level>,
    /// Skeldar helicopter UAV: discrete or dynamic.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = ["discrete", "dynamic"]))]
    pub skeldar: Option<Level>,
    /// A calibration file made by `vitro calibrate` for this scenario's map, terrain and
    /// type set, relative to the scenario file's directory: the abstract levels (discrete,
    /// interpolated) then follow its fitted trip times. None: the plans as they are.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub calibration: Option<PathBuf>,
}

impl FidelitySpec {
    /// The level of entity type `t`: its override if given, else the preset's level.
    pub fn level_of(&self, t: EntityType) -> Level {
        self.override_of(t)
            .unwrap_or_else(|| t.preset_level(self.level))
    }

    /// The override given for `t`'s fidelity key, if any.
    pub fn override_of(&self, t: EntityType) -> Option<Level> {
        match t {
            EntityType::Truck => self.truck,
            EntityType::Car => self.car,
            EntityType::Ugv => self.ugv,
            EntityType::Trooper | EntityType::Vip | EntityType::Hvt => self.trooper,
            EntityType::Procerus => self.procerus,
            EntityType::Vidar => self.vidar,
            EntityType::Skeldar => self.skeldar,
        }
    }
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

/// The type of an entity.
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum EntityType {
    /// Cargo truck.
    Truck,
    /// Civilian car.
    Car,
    /// MDARS unmanned ground vehicle.
    Ugv,
    /// Trooper.
    Trooper,
    /// The very important person to evacuate (a trooper).
    Vip,
    /// The high-value target (a trooper).
    Hvt,
    /// Procerus fixed-wing UAV.
    Procerus,
    /// Vidar helicopter UAV.
    Vidar,
    /// Skeldar helicopter UAV.
    Skeldar,
}

/// Allegiance of an entity in the file.
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum SideSpec {
    /// Own forces.
    Blue,
    /// Adversaries.
    Red,
    /// Civilians.
    Neutral,
}

impl SideSpec {
    /// The world's side.
    pub fn side(self) -> Side {
        match self {
            SideSpec::Blue => Side::Blue,
            SideSpec::Red => Side::Red,
            SideSpec::Neutral => Side::Neutral,
        }
    }
}

impl From<SideSpec> for Side {
    fn from(s: SideSpec) -> Side {
        s.side()
    }
}

fn one() -> u32 {
    1
}

/// A group of entities of one type and side.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
// Aircraft (and only they) have an altitude.
#[schemars(extend(
    "if" = { "properties": { "type": { "enum": ["procerus", "vidar", "skeldar"] } } },
    "then" = { "required": ["altitude_m"] },
    "else" = { "not": { "required": ["altitude_m"] } }
))]
pub struct EntitySpec {
    /// Unique name; a group of `count > 1` is named `name-1`, `name-2`, ...
    #[schemars(regex(pattern = r"\S"))]
    pub name: String,
    /// Entity type.
    #[serde(rename = "type")]
    pub kind: EntityType,
    /// Allegiance.
    pub side: SideSpec,
    /// How many, 1 to 20000.
    #[serde(default = "one")]
    #[schemars(range(min = 1, max = 20_000))]
    pub count: u32,
    /// Start, town metres `[x, y]`; none: placed by the mission.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<[f64; 2]>,
    /// Flight altitude above the ground, metres, 20 to 3000 (aircraft only).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 20.0, max = 3000.0))]
    pub altitude_m: Option<f64>,
}

impl EntitySpec {
    /// The names of the group's entities: `name` alone, or `name-1` ... `name-N` for a
    /// group of `count = N > 1`.
    pub fn names(&self) -> Vec<String> {
        if self.count == 1 {
            vec![self.name.clone()]
        } else {
            (1..=self.count)
                .map(|i| format!("{}-{i}", self.name))
                .collect()
        }
    }
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

/// Friend-or-foe vision settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VisionSpec {
    /// Range, metres.
    #[schemars(range(max = 1e5), extend("exclusiveMinimum" = 0.0))]
    pub range_m: f64,
    /// Field of view, degrees, in (0, 360].
    #[schemars(range(max = 360.0), extend("exclusiveMinimum" = 0.0))]
    pub fov_deg: f64,
    /// Detection probability at distance 0, in [0, 1].
    #[schemars(range(min = 0.0, max = 1.0))]
    pub p0: f64,
    /// Fall-off exponent of the detection probability with distance, ≥ 0.
    #[schemars(range(min = 0.0, max = 100.0))]
    pub falloff: f64,
    /// Probability of reporting the wrong side, in [0, 1].
    #[schemars(range(min = 0.0, max = 1.0))]
    pub misidentification: f64,
}

impl VisionSpec {
    /// The sensor model.
    pub fn vision(&self) -> FriendFoeVision {
        FriendFoeVision {
            range: self.range_m,
            half_fov: (self.fov_deg / 2.0).to_radians(),
            p0: self.p0,
            k: self.falloff,
            misidentification: self.misidentification,
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

/// The simulated radio channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ChannelSpec {
    /// Mean delivery delay, milliseconds.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub delay_ms: f64,
    /// Delay jitter, milliseconds.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub jitter_ms: f64,
    /// Probability that a message is lost, in [0, 1].
    #[schemars(range(min = 0.0, max = 1.0))]
    pub loss: f64,
    /// Radio range, metres.
    #[schemars(range(max = 1e6), extend("exclusiveMinimum" = 0.0))]
    pub range_m: f64,
}

impl Default for ChannelSpec {
    fn default() -> Self {
        ChannelSpec {
            delay_ms: 20.0,
            jitter_ms: 30.0,
            loss: 0.05,
            range_m: 3000.0,
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

/// Recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct RecordSpec {
    /// Time between two recorded frames, seconds.
    #[schemars(range(max = 3600.0), extend("exclusiveMinimum" = 0.0))]
    pub sample_s: f64,
}

impl Default for RecordSpec {
    fn default() -> Self {
        RecordSpec { sample_s: 1.0 }
    }
}

/// The JSON Schema of scenario files (draft 7, for editors): what
/// `scenarios/scenario.schema.json` holds, pretty-printed.
///
/// ```
/// let schema = vitro_tactical::scenario::json_schema();
/// assert_eq!(schema.get("title").and_then(|t| t.as_str()), Some("ScenarioFile"));
/// ```
pub fn json_schema() -> schemars::Schema {
    let generator = schemars::generate::SchemaSettings::draft07().into_generator();
    generator.into_root_schema_for::<ScenarioFile>()
}
