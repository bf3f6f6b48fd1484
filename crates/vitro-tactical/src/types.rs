//! Entity type parameters from public specifications: `data/types.toml`.
//!
//! The file ships inside the crate ([`TypeBook::builtin`], nothing is read at run time);
//! [`TypeBook::from_toml`] reads a user's own file of the same shape. Every table names its
//! `source` and says in `notes` which figures are estimates.
//!
//! ```
//! use vitro_tactical::types::{GroundKind, TypeBook};
//! let book = TypeBook::builtin();
//! let truck = book.ground(GroundKind::CargoTruck);
//! assert!(truck.mass > book.ground(GroundKind::Car).mass);
//! assert!(truck.source.contains("FMTV"));
//! ```

use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// Standard gravity, m/s².
pub const G: f64 = 9.80665;
/// Sea-level air density (ISA), kg/m³.
pub const RHO_AIR: f64 = 1.225;
/// Share of a ground vehicle's weight its driven tyres can turn into tractive force on a
/// paved road (an estimate: all four wheels driven, tyre-road friction about 0.7 and up).
pub const TRACTION: f64 = 0.7;

/// Why a type file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum TypesError {
    /// The TOML does not parse or does not match the schema.
    #[error("types file: {0}")]
    Toml(#[from] toml::de::Error),
    /// A value is out of its range.
    #[error("types file: {table}.{key} = {value} is out of range ({why})")]
    Range {
        /// The table, e.g. `ground.car`.
        table: String,
        /// The key.
        key: &'static str,
        /// The value found.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
}

/// A ground vehicle type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum GroundKind {
    /// Passenger car.
    Car,
    /// Cargo truck.
    CargoTruck,
    /// MDARS unmanned ground vehicle.
    Mdars,
}

impl GroundKind {
    /// All kinds, in a fixed order.
    pub const ALL: [GroundKind; 3] = [GroundKind::Car, GroundKind::CargoTruck, GroundKind::Mdars];
    /// Short name (the key in the types file).
    pub fn key(self) -> &'static str {
        match self {
            GroundKind::Car => "car",
            GroundKind::CargoTruck => "cargo_truck",
            GroundKind::Mdars => "mdars",
        }
    }
}

/// A trooper type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum TroopKind {
    /// Own trooper.
    Blue,
    /// Adversary.
    Red,
    /// The person to evacuate.
    Vip,
}

impl TroopKind {
    /// All kinds, in a fixed order.
    pub const ALL: [TroopKind; 3] = [TroopKind::Blue, TroopKind::Red, TroopKind::Vip];
    /// Short name (the key in the types file).
    pub fn key(self) -> &'static str {
        match self {
            TroopKind::Blue => "blue",
            TroopKind::Red => "red",
            TroopKind::Vip => "vip",
        }
    }
}

/// A fixed-wing UAV type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum CtolKind {
    /// Procerus Unicorn-class flying wing.
    Procerus,
}

impl CtolKind {
    /// Short name (the key in the types file).
    pub fn key(self) -> &'static str {
        "procerus"
    }
}

/// A helicopter UAV type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum VtolKind {
    /// Vidar-class light helicopter.
    Vidar,
    /// Saab Skeldar V-200.
    Skeldar,
}

impl VtolKind {
    /// All kinds, in a fixed order.
    pub const ALL: [VtolKind; 2] = [VtolKind::Vidar, VtolKind::Skeldar];
    /// Short name (the key in the types file).
    pub fn key(self) -> &'static str {
        match self {
            VtolKind::Vidar => "vidar",
            VtolKind::Skeldar => "skeldar",
        }
    }
}

/// Street speed limits by OSM `highway` class, km/h.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedLimits {
    /// Where the figures come from.
    pub source: String,
    /// Which figures are assumptions.
    pub notes: String,
    /// Any class not listed.
    pub default_kmh: f64,
    /// `motorway`.
    pub motorway_kmh: f64,
    /// `motorway_link`.
    pub motorway_link_kmh: f64,
    /// `trunk` (and `trunk_link`).
    pub trunk_kmh: f64,
    /// `living_street`.
    pub living_street_kmh: f64,
    /// `service`.
    pub service_kmh: f64,
    /// `unclassified`.
    pub unclassified_kmh: f64,
}

impl SpeedLimits {
    /// The limit on a street of OSM class `class`, m/s.
    pub fn for_class(&self, class: &str) -> f64 {
        let kmh = match class {
            "motorway" => self.motorway_kmh,
            "motorway_link" => self.motorway_link_kmh,
            "trunk" | "trunk_link" => self.trunk_kmh,
            "living_street" => self.living_street_kmh,
            "service" => self.service_kmh,
            "unclassified" => self.unclassified_kmh,
            _ => self.default_kmh,
        };
        kmh / 3.6
    }
}

/// Parameters of a ground vehicle type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundType {
    /// What it is.
    pub name: String,
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Mass, kg.
    pub mass: f64,
    /// Engine power, kW.
    pub power_kw: f64,
    /// Top speed, km/h.
    pub max_speed_kmh: f64,
    /// Largest acceleration (traction/gearing limit at low speed), m/s².
    pub max_accel: f64,
    /// Braking deceleration used in driving, m/s².
    pub max_decel: f64,
    /// Largest lateral acceleration the planner allows in corners, m/s².
    pub max_lateral_accel: f64,
    /// Radius of the tightest circle it can drive, m.
    pub turning_radius: f64,
    /// Body length, m.
    pub length: f64,
    /// Body width, m.
    pub width: f64,
    /// Body height, m.
    pub height: f64,
    /// Distance between axles, m.
    pub wheelbase: f64,
    /// Wheel radius, m.
    pub wheel_radius: f64,
    /// Drag coefficient × frontal area, m².
    pub drag_area: f64,
    /// Rolling resistance coefficient.
    pub rolling_resistance: f64,
}

impl GroundType {
    /// Top speed, m/s.
    pub fn max_speed(&self) -> f64 {
        self.max_speed_kmh / 3.6
    }

    /// Engine power, W.
    pub fn power(&self) -> f64 {
        self.power_kw * 1000.0
    }

    /// The largest tractive force at speed `v`, N: the tyres' grip when slow
    /// ([`TRACTION`] × weight), the engine's power `P / v` when fast.
    pub fn drive_limit(&self, v: f64) -> f64 {
        (TRACTION * self.mass * G).min(self.power() / v.abs().max(0.5))
    }

    /// The largest acceleration at speed `v` on a grade of `slope` (rise over run): the
    /// tractive force ([`drive_limit`](Self::drive_limit)) less rolling resistance,
    /// aerodynamic drag and the grade, capped by `max_accel` (gearing and comfort on the
    /// level). May be negative (the grade is too steep at this speed).
    pub fn accel_limit(&self, v: f64, slope: f64) -> f64 {
        let m = self.mass;
        let cos = 1.0 / libm::sqrt(1.0 + slope * slope);
        let net = self.drive_limit(v) / m
            - self.rolling_resistance * G * cos
            - 0.5 * RHO_AIR * self.drag_area * v * v / m
            - G * slope * cos;
        net.min(self.max_accel)
    }

    /// The speed a corner of deflection `turn` (radians) allows when the path may bend on a
    /// circle no wider than `room` metres of tangent on either side: the lateral-acceleration
    /// limit on the widest fillet that fits, never a radius below the turning radius.
    pub fn corner_speed(&self, turn: f64, room: f64) -> f64 {
        let half = (turn.abs() / 2.0).min(1.55);
        if half < 1e-6 {
            return f64::INFINITY;
        }
        let radius = (room / libm::tan(half)).max(self.turning_radius);
        libm::sqrt(self.max_lateral_accel * radius)
    }

    /// The steering angle of the tightest turn (bicycle model), radians.
    pub fn max_steer(&self) -> f64 {
        libm::atan(self.wheelbase / self.turning_radius)
    }
}

/// Parameters shared by every trooper type: the body and the Pandolf load-speed relation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TroopParams {
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Body mass W, kg.
    pub body_mass: f64,
    /// Standing height, m.
    pub height: f64,
    /// Walking speed with no load on the level, m/s (sets the metabolic budget).
    pub unloaded_speed: f64,
    /// Slowest walking speed however heavy the load, m/s.
    pub min_speed: f64,
    /// How fast a trooper turns, degrees per second.
    pub turn_rate_deg_s: f64,
    /// Pandolf terrain factor η (1.0 on a paved road).
    pub terrain_factor: f64,
    /// Blue troopers.
    pub blue: TroopType,
    /// Red adversaries.
    pub red: TroopType,
    /// The VIP.
    pub vip: TroopType,
}

/// One trooper type: what it carries.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TroopType {
    /// What it is.
    pub name: String,
    /// Carried load L, kg.
    pub load: f64,
}

impl TroopParams {
    /// Pandolf (1977) metabolic power, W, of walking at `v` m/s with `load` kg on a grade of
    /// `grade_percent` (negative grades count as level).
    pub fn metabolic_power(&self, load: f64, v: f64, grade_percent: f64) -> f64 {
        let w = self.body_mass;
        let g = grade_percent.max(0.0);
        1.5 * w
            + 2.0 * (w + load) * (load / w) * (load / w)
            + self.terrain_factor * (w + load) * (1.5 * v * v + 0.35 * v * g)
    }

    /// Walking speed, m/s, with `load` kg on a grade of `grade_percent`: the speed whose
    /// Pandolf power equals the unloaded walk's on the level, clamped to
    /// `[min_speed, unloaded_speed]`.
    ///
    /// ```
    /// use vitro_tactical::types::TypeBook;
    /// let t = &TypeBook::builtin().troops;
    /// assert!((t.walking_speed(0.0, 0.0) - t.unloaded_speed).abs() < 1e-9);
    /// let loaded = t.walking_speed(33.0, 0.0);
    /// assert!(loaded < 1.2 && loaded > 1.0, "{loaded}");
    /// assert!(t.walking_speed(33.0, 5.0) < loaded);
    /// ```
    pub fn walking_speed(&self, load: f64, grade_percent: f64) -> f64 {
        let budget = self.metabolic_power(0.0, self.unloaded_speed, 0.0);
        let w = self.body_mass;
        let g = grade_percent.max(0.0);
        let base = 1.5 * w + 2.0 * (w + load) * (load / w) * (load / w);
        // a v² + b v - c = 0 with a = 1.5 η (W+L), b = 0.35 η (W+L) G, c = budget - base.
        let a = 1.5 * self.terrain_factor * (w + load);
        let b = 0.35 * self.terrain_factor * (w + load) * g;
        let c = budget - base;
        let v = if c <= 0.0 || a <= 0.0 {
            0.0
        } else {
            (-b + libm::sqrt(b * b + 4.0 * a * c)) / (2.0 * a)
        };
        v.clamp(self.min_speed, self.unloaded_speed)
    }

    /// The type of `kind`.
    pub fn of(&self, kind: TroopKind) -> &TroopType {
        match kind {
            TroopKind::Blue => &self.blue,
            TroopKind::Red => &self.red,
            TroopKind::Vip => &self.vip,
        }
    }

    /// Turn rate, rad/s.
    pub fn turn_rate(&self) -> f64 {
        self.turn_rate_deg_s.to_radians()
    }
}

/// Parameters of a fixed-wing UAV type (kinematic limits).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CtolType {
    /// What it is.
    pub name: String,
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Mass, kg.
    pub mass: f64,
    /// Wing span, m.
    pub span: f64,
    /// Slowest airspeed (it cannot stop or hover), m/s.
    pub min_speed: f64,
    /// Cruise airspeed, m/s.
    pub cruise_speed: f64,
    /// Fastest airspeed, m/s.
    pub max_speed: f64,
    /// Bank limit, degrees.
    pub max_bank_deg: f64,
    /// Roll rate limit, degrees per second.
    pub roll_rate_deg_s: f64,
    /// Flight-path (pitch) angle limit, degrees.
    pub max_flight_path_deg: f64,
    /// Pitch rate limit, degrees per second.
    pub pitch_rate_deg_s: f64,
    /// Airspeed change limit, m/s².
    pub max_accel: f64,
}

impl CtolType {
    /// Radius of a coordinated level turn at airspeed `v` and bank `bank` (radians):
    /// `v² / (g tan bank)`.
    pub fn turn_radius(v: f64, bank: f64) -> f64 {
        v * v / (G * libm::tan(bank))
    }
    /// The tightest turn radius at cruise speed, m.
    pub fn min_turn_radius(&self) -> f64 {
        Self::turn_radius(self.cruise_speed, self.max_bank_deg.to_radians())
    }
}

/// Parameters of a helicopter UAV type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VtolType {
    /// What it is.
    pub name: String,
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Mass, kg.
    pub mass: f64,
    /// Main rotor diameter, m.
    pub rotor_diameter: f64,
    /// Engine power, kW.
    pub power_kw: f64,
    /// Fastest level flight, m/s.
    pub max_speed: f64,
    /// Cruise speed the autopilots use, m/s.
    pub cruise_speed: f64,
    /// Fastest climb or descent the autopilots command, m/s.
    pub max_climb: f64,
    /// Full-collective thrust over weight.
    pub thrust_to_weight: f64,
    /// Largest body tilt the autopilots command, degrees.
    pub max_tilt_deg: f64,
    /// Rotor disc tilt at full cyclic, degrees.
    pub cyclic_tilt_deg: f64,
    /// Radius of gyration in roll over rotor radius.
    pub gyration_roll: f64,
    /// Radius of gyration in pitch over rotor radius.
    pub gyration_pitch: f64,
    /// Radius of gyration in yaw over rotor radius.
    pub gyration_yaw: f64,
    /// Rotor hub height above the centre of mass, m.
    pub hub_height: f64,
    /// Tail rotor distance behind the centre of mass, m.
    pub tail_arm: f64,
    /// Main-rotor reaction torque per newton of thrust, in rotor radii (N·m per N / R).
    pub torque_fraction: f64,
}

impl VtolType {
    /// Main rotor radius, m.
    pub fn rotor_radius(&self) -> f64 {
        self.rotor_diameter / 2.0
    }
    /// Largest main-rotor thrust, N.
    pub fn max_thrust(&self) -> f64 {
        self.thrust_to_weight * self.mass * G
    }
    /// Principal moments of inertia (roll, pitch, yaw), kg·m².
    pub fn inertia(&self) -> [f64; 3] {
        let r = self.rotor_radius();
        let i = |k: f64| self.mass * (k * r) * (k * r);
        [
            i(self.gyration_roll),
            i(self.gyration_pitch),
            i(self.gyration_yaw),
        ]
    }
    /// Drag area Cd·A, m², such that at `max_speed` the thrust tilted by `max_tilt_deg`
    /// balances drag in level flight.
    pub fn drag_area(&self) -> f64 {
        let tilt = self.max_tilt_deg.to_radians();
        self.mass * G * libm::tan(tilt) / (0.5 * RHO_AIR * self.max_speed * self.max_speed)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GroundTable {
    car: GroundType,
    cargo_truck: GroundType,
    mdars: GroundType,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CtolTable {
    procerus: CtolType,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct VtolTable {
    vidar: VtolType,
    skeldar: VtolType,
}

/// Every entity type's parameters (the contents of a types file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TypeBook {
    /// Street speed limits.
    pub speed_limits: SpeedLimits,
    ground: GroundTable,
    /// Trooper parameters.
    pub troops: TroopParams,
    ctol: CtolTable,
    vtol: VtolTable,
}

/// The embedded `data/types.toml`.
pub const BUILTIN_TYPES: &str = include_str!("../../../data/types.toml");

impl TypeBook {
    /// The parameters shipped with the crate (`data/types.toml`), parsed once.
    ///
    /// # Panics
    /// Never for a released crate: the embedded file is checked by the crate's tests.
    pub fn builtin() -> &'static TypeBook {
        static BOOK: OnceLock<TypeBook> = OnceLock::new();
        BOOK.get_or_init(|| {
            TypeBook::from_toml(BUILTIN_TYPES).expect("the embedded data/types.toml is valid")
        })
    }

    /// Parses and checks a types file.
    pub fn from_toml(text: &str) -> Result<Self, TypesError> {
        let book: TypeBook = toml::from_str(text)?;
        book.validate()?;
        Ok(book)
    }

    /// The parameters of a ground vehicle type.
    pub fn ground(&self, kind: GroundKind) -> &GroundType {
        match kind {
            GroundKind::Car => &self.ground.car,
            GroundKind::CargoTruck => &self.ground.cargo_truck,
            GroundKind::Mdars => &self.ground.mdars,
        }
    }
    /// The parameters of a fixed-wing UAV type.
    pub fn ctol(&self, kind: CtolKind) -> &CtolType {
        match kind {
            CtolKind::Procerus => &self.ctol.procerus,
        }
    }
    /// The parameters of a helicopter UAV type.
    pub fn vtol(&self, kind: VtolKind) -> &VtolType {
        match kind {
            VtolKind::Vidar => &self.vtol.vidar,
            VtolKind::Skeldar => &self.vtol.skeldar,
        }
    }

    fn validate(&self) -> Result<(), TypesError> {
        let pos = |table: String, key: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(TypesError::Range {
                    table,
                    key,
                    value: v,
                    why: "must be positive",
                })
            }
        };
        let sl = &self.speed_limits;
        for (k, v) in [
            ("default_kmh", sl.default_kmh),
            ("motorway_kmh", sl.motorway_kmh),
            ("motorway_link_kmh", sl.motorway_link_kmh),
            ("trunk_kmh", sl.trunk_kmh),
            ("living_street_kmh", sl.living_street_kmh),
            ("service_kmh", sl.service_kmh),
            ("unclassified_kmh", sl.unclassified_kmh),
        ] {
            pos("speed_limits".into(), k, v)?;
        }
        for kind in GroundKind::ALL {
            let g = self.ground(kind);
            let t = format!("ground.{}", kind.key());
            for (k, v) in [
                ("mass", g.mass),
                ("power_kw", g.power_kw),
                ("max_speed_kmh", g.max_speed_kmh),
                ("max_accel", g.max_accel),
                ("max_decel", g.max_decel),
                ("max_lateral_accel", g.max_lateral_accel),
                ("turning_radius", g.turning_radius),
                ("length", g.length),
                ("width", g.width),
                ("height", g.height),
                ("wheelbase", g.wheelbase),
                ("wheel_radius", g.wheel_radius),
                ("drag_area", g.drag_area),
                ("rolling_resistance", g.rolling_resistance),
            ] {
                pos(t.clone(), k, v)?;
            }
        }
        let tr = &self.troops;
        for (k, v) in [
            ("body_mass", tr.body_mass),
            ("height", tr.height),
            ("unloaded_speed", tr.unloaded_speed),
            ("min_speed", tr.min_speed),
            ("turn_rate_deg_s", tr.turn_rate_deg_s),
            ("terrain_factor", tr.terrain_factor),
        ] {
            pos("troops".into(), k, v)?;
        }
        if tr.min_speed > tr.unloaded_speed {
            return Err(TypesError::Range {
                table: "troops".into(),
                key: "min_speed",
                value: tr.min_speed,
                why: "must not exceed unloaded_speed",
            });
        }
        for kind in TroopKind::ALL {
            let l = tr.of(kind).load;
            if !(l.is_finite() && l >= 0.0) {
                return Err(TypesError::Range {
                    table: format!("troops.{}", kind.key()),
                    key: "load",
                    value: l,
                    why: "must be zero or positive",
                });
            }
        }
        let c = self.ctol(CtolKind::Procerus);
        for (k, v) in [
            ("mass", c.mass),
            ("span", c.span),
            ("min_speed", c.min_speed),
            ("cruise_speed", c.cruise_speed),
            ("max_speed", c.max_speed),
            ("max_bank_deg", c.max_bank_deg),
            ("roll_rate_deg_s", c.roll_rate_deg_s),
            ("max_flight_path_deg", c.max_flight_path_deg),
            ("pitch_rate_deg_s", c.pitch_rate_deg_s),
            ("max_accel", c.max_accel),
        ] {
            pos("ctol.procerus".into(), k, v)?;
        }
        if !(c.min_speed <= c.cruise_speed && c.cruise_speed <= c.max_speed) {
            return Err(TypesError::Range {
                table: "ctol.procerus".into(),
                key: "cruise_speed",
                value: c.cruise_speed,
                why: "must lie between min_speed and max_speed",
            });
        }
        if c.max_bank_deg >= 80.0 {
            return Err(TypesError::Range {
                table: "ctol.procerus".into(),
                key: "max_bank_deg",
                value: c.max_bank_deg,
                why: "must be below 80 degrees",
            });
        }
        for kind in VtolKind::ALL {
            let v = self.vtol(kind);
            let t = format!("vtol.{}", kind.key());
            for (k, x) in [
                ("mass", v.mass),
                ("rotor_diameter", v.rotor_diameter),
                ("power_kw", v.power_kw),
                ("max_speed", v.max_speed),
                ("cruise_speed", v.cruise_speed),
                ("max_climb", v.max_climb),
                ("max_tilt_deg", v.max_tilt_deg),
                ("cyclic_tilt_deg", v.cyclic_tilt_deg),
                ("gyration_roll", v.gyration_roll),
                ("gyration_pitch", v.gyration_pitch),
                ("gyration_yaw", v.gyration_yaw),
                ("hub_height", v.hub_height),
                ("tail_arm", v.tail_arm),
                ("torque_fraction", v.torque_fraction),
            ] {
                pos(t.clone(), k, x)?;
            }
            if v.thrust_to_weight <= 1.0 {
                return Err(TypesError::Range {
                    table: t,
                    key: "thrust_to_weight",
                    value: v.thrust_to_weight,
                    why: "must exceed 1 (it must be able to hover)",
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_parses_and_every_table_names_a_source() {
        let b = TypeBook::builtin();
        for k in GroundKind::ALL {
            assert!(!b.ground(k).source.is_empty() && !b.ground(k).notes.is_empty());
        }
        for k in VtolKind::ALL {
            assert!(!b.vtol(k).source.is_empty());
        }
        assert!(!b.ctol(CtolKind::Procerus).source.is_empty());
        assert!(!b.troops.source.is_empty() && !b.speed_limits.source.is_empty());
    }

    #[test]
    fn bad_values_are_refused_with_their_place() {
        let text = BUILTIN_TYPES.replace("mass = 1270.0", "mass = -1.0");
        match TypeBook::from_toml(&text) {
            Err(TypesError::Range { table, key, .. }) => {
                assert_eq!((table.as_str(), key), ("ground.car", "mass"));
            }
            other => panic!("{other:?}"),
        }
        let text = BUILTIN_TYPES.replace("[ground.mdars]", "[ground.tank]");
        assert!(matches!(
            TypeBook::from_toml(&text),
            Err(TypesError::Toml(_))
        ));
    }

    #[test]
    fn power_limits_acceleration_at_speed() {
        let b = TypeBook::builtin();
        let truck = b.ground(GroundKind::CargoTruck);
        // Gearing-limited when slow, power-limited when fast.
        assert_eq!(truck.accel_limit(1.0, 0.0), truck.max_accel);
        let p = truck.power() / (truck.mass * 20.0);
        assert!(truck.accel_limit(20.0, 0.0) < p && truck.accel_limit(20.0, 0.0) < 1.0);
        // A 10 % grade costs about 1 m/s² at speed, nothing when slow (low gear).
        let d = truck.accel_limit(20.0, 0.0) - truck.accel_limit(20.0, 0.1);
        assert!((d - 0.98).abs() < 0.05, "{d}");
        assert_eq!(truck.accel_limit(2.0, 0.1), truck.max_accel);
        // The steepest grade it climbs from rest: traction-limited (sin θ < 0.7).
        assert!(truck.accel_limit(0.5, 0.8) > 0.0);
        assert!(truck.accel_limit(0.5, 1.0) < 0.0);
        // The car out-accelerates the truck.
        assert!(b.ground(GroundKind::Car).accel_limit(10.0, 0.0) > truck.accel_limit(10.0, 0.0));
    }

    #[test]
    fn corners_slow_vehicles_down() {
        let car = TypeBook::builtin().ground(GroundKind::Car);
        assert!(car.corner_speed(0.0, 10.0).is_infinite());
        // A right angle with 10 m of room: a 10 m fillet, sqrt(3 * 10) m/s.
        let v = car.corner_speed(std::f64::consts::FRAC_PI_2, 10.0);
        assert!((v - 30f64.sqrt()).abs() < 1e-9, "{v}");
        // A hairpin with no room: the turning radius bounds it from below.
        let v = car.corner_speed(3.1, 0.1);
        assert!((v - (3.0 * 5.45f64).sqrt()).abs() < 1e-9, "{v}");
    }
}
