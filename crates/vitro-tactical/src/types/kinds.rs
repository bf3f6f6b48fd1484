//! The kinds of bodies the type book describes, and the physical constants their parameters use.

use serde::{Deserialize, Serialize};

/// Standard gravity, m/s².
pub const G: f64 = 9.80665;

/// Sea-level air density (ISA), kg/m³.
pub const RHO_AIR: f64 = 1.225;

/// Share of a ground vehicle's weight its driven tyres can turn into tractive force on a
/// paved road (an estimate: all four wheels driven, tyre-road friction about 0.7 and up).
pub const TRACTION: f64 = 0.7;

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
