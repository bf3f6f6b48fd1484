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

mod kinds;
mod params;

pub use kinds::{CtolKind, G, GroundKind, RHO_AIR, TRACTION, TroopKind, VtolKind};

pub use params::{CtolType, GroundType, TroopParams, TroopType, VtolType};

use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

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
pub const BUILTIN_TYPES: &str = include_str!("../../../../data/types.toml");

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
                ("reverse_speed_kmh", g.reverse_speed_kmh),
                ("reverse_force", g.reverse_force),
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
}
