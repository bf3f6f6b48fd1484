//! The tactical radio: what agents of the [`Tactical`](crate::model::Tactical) model say to
//! each other through the simulated network (`vitro::comm`).
//!
//! One closed vocabulary for every controller of the tactical world, so that messages are
//! plain data (serialised into the trace hash) and any agent can read any report.

use crate::world::Side;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;

/// A message of the tactical model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Radio {
    /// "I see `target` at `pos`, and I take it for `seen_as`."
    Contact {
        /// Who was seen.
        target: EntityId,
        /// Where, world metres.
        pos: [f64; 3],
        /// The side the observer believes it is on.
        seen_as: Side,
    },
    /// The sender's own position, world metres.
    Position([f64; 3]),
    /// An order to the receiver: what to do next.
    Order(Order),
    /// The sender's plan, step by step (e.g. the actions of a repaired plan).
    Plan(Vec<String>),
    /// A named signal with a short argument (e.g. `("formation", "wedge")`).
    Signal(String, String),
}

/// What an [`Radio::Order`] tells the receiver to do.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Order {
    /// Go to a world point (x, y).
    GoTo([f64; 2]),
    /// Follow an entity, keeping near it.
    Follow(EntityId),
    /// Pursue `target` (a high-value target) together with `team` (the pursuers, the first
    /// of them leading).
    Pursue {
        /// Who to catch.
        target: EntityId,
        /// The pursuers; the first coordinates the others.
        team: Vec<EntityId>,
    },
    /// Stop and hold position.
    Hold,
}
