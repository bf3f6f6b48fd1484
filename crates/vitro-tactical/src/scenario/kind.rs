//! What each entity type is: its file name, its levels of fidelity, what the presets give it.

use super::{EntityType, Preset};
use crate::entity::Level;

impl EntityType {
    /// Every type, in a fixed order.
    pub const ALL: [EntityType; 9] = [
        EntityType::Truck,
        EntityType::Car,
        EntityType::Ugv,
        EntityType::Trooper,
        EntityType::Vip,
        EntityType::Hvt,
        EntityType::Procerus,
        EntityType::Vidar,
        EntityType::Skeldar,
    ];

    /// Lower-case name, as in the file.
    pub fn name(self) -> &'static str {
        match self {
            EntityType::Truck => "truck",
            EntityType::Car => "car",
            EntityType::Ugv => "ugv",
            EntityType::Trooper => "trooper",
            EntityType::Vip => "vip",
            EntityType::Hvt => "hvt",
            EntityType::Procerus => "procerus",
            EntityType::Vidar => "vidar",
            EntityType::Skeldar => "skeldar",
        }
    }

    /// Whether it flies (and so needs an altitude).
    pub fn is_aircraft(self) -> bool {
        matches!(
            self,
            EntityType::Procerus | EntityType::Vidar | EntityType::Skeldar
        )
    }

    /// Whether it is a ground vehicle.
    pub fn is_vehicle(self) -> bool {
        matches!(self, EntityType::Truck | EntityType::Car | EntityType::Ugv)
    }

    /// Whether it walks (troopers, the VIP, the HVT).
    pub fn is_trooper(self) -> bool {
        matches!(
            self,
            EntityType::Trooper | EntityType::Vip | EntityType::Hvt
        )
    }

    /// The levels this type has, coarsest first.
    pub fn levels(self) -> &'static [Level] {
        match self {
            EntityType::Truck | EntityType::Car | EntityType::Ugv => {
                &[Level::Discrete, Level::Interpolated, Level::Physical]
            }
            EntityType::Trooper | EntityType::Vip | EntityType::Hvt => {
                &[Level::Discrete, Level::Directed]
            }
            EntityType::Procerus => &[Level::Discrete, Level::Kinematic],
            EntityType::Vidar | EntityType::Skeldar => &[Level::Discrete, Level::Dynamic],
        }
    }

    /// The key of `[fidelity]` that sets this type's level.
    pub fn fidelity_key(self) -> &'static str {
        if self.is_trooper() {
            "trooper"
        } else {
            self.name()
        }
    }

    /// The level `preset` gives this type.
    pub fn preset_level(self, preset: Preset) -> Level {
        match preset {
            Preset::Discrete => Level::Discrete,
            Preset::Interpolated => {
                if self.is_vehicle() {
                    Level::Interpolated
                } else if self.is_trooper() {
                    Level::Directed
                } else if self == EntityType::Procerus {
                    Level::Kinematic
                } else {
                    Level::Discrete
                }
            }
            Preset::Physical => {
                if self.is_vehicle() {
                    Level::Physical
                } else if self.is_trooper() {
                    Level::Directed
                } else if self == EntityType::Procerus {
                    Level::Kinematic
                } else {
                    Level::Dynamic
                }
            }
        }
    }
}

impl std::fmt::Display for EntityType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
