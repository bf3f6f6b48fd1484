//! What the leader records: the squad's positions, its changes of formation, the orders
//! carried out.

use super::pattern::Pattern;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::time::SimTime;
use vitro_site::geo::P2;

/// One logged position.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrackPoint {
    /// When.
    pub t: SimTime,
    /// Who (the leader or a member).
    pub id: EntityId,
    /// Where, world metres.
    pub pos: [f64; 3],
    /// For a member: its slot then (free of forbidden zones; at the discrete level the node
    /// nearest to it), world metres.
    pub slot: Option<P2>,
}

/// A change of formation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Switch {
    /// When.
    pub t: SimTime,
    /// The formation before.
    pub from: Pattern,
    /// The formation after.
    pub to: Pattern,
    /// What the leader's eyes reported: `contact`, or the ground (`narrow`, `street`,
    /// `open`).
    pub reason: String,
    /// Where the leader was, world metres.
    pub at: P2,
}

/// An order carried out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Arrival {
    /// When `arrived` was sent.
    pub t: SimTime,
    /// Who gave the order (and was told).
    pub requester: EntityId,
    /// The ordered point, world metres.
    pub goal: P2,
    /// True if every member was at its slot; false if the leader stopped waiting.
    pub gathered: bool,
}
