//! The tables every tactical mission's scenario file shares, with their parser and checker.
//!
//! A scenario file of any mission on the tactical arena names its town and terrain
//! ([`SiteSpec`]), when it ends ([`EndSpec`]), its entities by type, side and start
//! ([`EntitySpec`]), the fidelity level of each entity type ([`FidelitySpec`]), the simulated
//! radio ([`ChannelSpec`]) and the recording's sampling ([`RecordSpec`]). A mission adds its
//! own tables beside these: [`tables`] reads the whole file into the mission's type and
//! reports every problem at its file, line and column, and [`checker`] checks the shared
//! tables and offers the checks a mission's own tables need. The evacuation's scenario
//! (`vitro_evac::scenario`) and the surveillance's (`vitro_surveillance::scenario`) are
//! built this way.
//!
//! ```
//! use vitro_tactical::entity::Level;
//! use vitro_tactical::scenario::{EntitySpec, EntityType, FidelitySpec};
//!
//! let fidelity: FidelitySpec = toml::from_str(r#"level = "interpolated"
//! truck = "physical""#).unwrap();
//! assert_eq!(fidelity.level_of(EntityType::Truck), Level::Physical);
//! assert_eq!(fidelity.level_of(EntityType::Car), Level::Interpolated);
//! let group: EntitySpec = toml::from_str(r#"name = "truck"
//! type = "truck"
//! side = "blue""#).unwrap();
//! assert_eq!(group.count, 1);
//! ```

pub mod checker;
mod kind;
mod span;
pub mod tables;

pub use checker::{ALTITUDE_M, MAX_COUNT, MAX_END_S};
pub use span::{Diagnostic, Diagnostics, MAX_PROBLEMS, SourceMap};

use crate::entity::Level;
use crate::sensor::FriendFoeVision;
use crate::world::Side;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

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
    /// Every entity type at the preset `level` (a `--fidelity` option): the per-type
    /// overrides and the calibration of the file are dropped.
    ///
    /// ```
    /// use vitro_tactical::entity::Level;
    /// use vitro_tactical::scenario::{EntityType, FidelitySpec, Preset};
    /// let mut f: FidelitySpec = toml::from_str("truck = \"physical\"").unwrap();
    /// f.set_preset(Preset::Interpolated);
    /// assert_eq!(f.level_of(EntityType::Truck), Level::Interpolated);
    /// ```
    pub fn set_preset(&mut self, level: Preset) {
        *self = FidelitySpec {
            level,
            ..FidelitySpec::default()
        };
    }

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

impl ChannelSpec {
    /// The link between any two radios: the table's delay, jitter, loss and range, and no
    /// bandwidth limit (`sim.network_mut().set_default_link(file.channel.link())`).
    ///
    /// ```
    /// use vitro_tactical::scenario::ChannelSpec;
    /// let link = ChannelSpec::default().link();
    /// assert_eq!(link.delay.as_secs_f64(), 0.02);
    /// assert_eq!(link.range_m, Some(3000.0));
    /// ```
    pub fn link(&self) -> vitro::comm::LinkParams {
        let ms = |x: f64| vitro::time::SimDuration::from_secs_f64(x / 1e3);
        vitro::comm::LinkParams {
            delay: ms(self.delay_ms),
            jitter: ms(self.jitter_ms),
            loss: self.loss,
            range_m: Some(self.range_m),
            bandwidth_bps: None,
        }
    }
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
