//! Conditions: who each entity is in the tactical world (role, side, size) and what state it
//! is in (active, aboard a vehicle, down, captured, hidden, extracted).
//!
//! Kept as a storage of the [`Arena`](crate::arena::Arena) beside the bodies: sensors read it
//! (friend-or-foe vision needs each body's side and height), mission actuators write it
//! (boarding, fire, capture).

use crate::scenario::EntityType;
use crate::world::Side;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;

/// What an entity is.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Role {
    /// Cargo truck.
    Truck,
    /// Passenger car.
    Car,
    /// Unmanned ground vehicle (MDARS).
    Ugv,
    /// Trooper (blue or red).
    Trooper,
    /// The very important person to evacuate.
    Vip,
    /// The high-value target.
    Hvt,
    /// Fixed-wing UAV (Procerus).
    Procerus,
    /// Helicopter UAV (Vidar).
    Vidar,
    /// Helicopter UAV (Skeldar).
    Skeldar,
}

impl From<EntityType> for Role {
    fn from(t: EntityType) -> Role {
        match t {
            EntityType::Truck => Role::Truck,
            EntityType::Car => Role::Car,
            EntityType::Ugv => Role::Ugv,
            EntityType::Trooper => Role::Trooper,
            EntityType::Vip => Role::Vip,
            EntityType::Hvt => Role::Hvt,
            EntityType::Procerus => Role::Procerus,
            EntityType::Vidar => Role::Vidar,
            EntityType::Skeldar => Role::Skeldar,
        }
    }
}

impl Role {
    /// Lower-case name, as in scenario files and recordings.
    pub fn name(self) -> &'static str {
        match self {
            Role::Truck => "truck",
            Role::Car => "car",
            Role::Ugv => "ugv",
            Role::Trooper => "trooper",
            Role::Vip => "vip",
            Role::Hvt => "hvt",
            Role::Procerus => "procerus",
            Role::Vidar => "vidar",
            Role::Skeldar => "skeldar",
        }
    }
    /// The body's height, metres (the top of a vehicle, a person's head, an aircraft's
    /// airframe): what lines of sight reach.
    pub fn height(self) -> f64 {
        match self {
            Role::Truck => 3.2,
            Role::Car => 1.5,
            Role::Ugv => 1.6,
            Role::Trooper | Role::Vip | Role::Hvt => 1.8,
            Role::Procerus | Role::Vidar | Role::Skeldar => 1.0,
        }
    }
    /// True for the aircraft.
    pub fn is_aircraft(self) -> bool {
        matches!(self, Role::Procerus | Role::Vidar | Role::Skeldar)
    }
    /// True for people on foot (troopers, VIP, HVT).
    pub fn is_person(self) -> bool {
        matches!(self, Role::Trooper | Role::Vip | Role::Hvt)
    }
}

/// The state an entity is in.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Status {
    /// Acting, with a body in the arena.
    Active,
    /// Riding in a vehicle (no body of its own).
    Aboard(EntityId),
    /// Hit: out of action.
    Down,
    /// Captured (the high-value target).
    Captured,
    /// Not yet in the world (the high-value target before it shows up).
    Hidden,
    /// Brought to the extraction point.
    Extracted,
}

impl Status {
    /// Lower-case name, as in recordings.
    pub fn name(self) -> &'static str {
        match self {
            Status::Active => "active",
            Status::Aboard(_) => "aboard",
            Status::Down => "down",
            Status::Captured => "captured",
            Status::Hidden => "hidden",
            Status::Extracted => "extracted",
        }
    }
}

/// Who an entity is and its state.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Condition {
    /// What it is.
    pub role: Role,
    /// Its allegiance.
    pub side: Side,
    /// Its height, metres (sensors sit on top; it is seen if its middle is seen).
    pub height: f64,
    /// Its state.
    pub status: Status,
}

impl Condition {
    /// An active entity.
    pub fn new(role: Role, side: Side, height: f64) -> Self {
        Condition {
            role,
            side,
            height,
            status: Status::Active,
        }
    }
}
