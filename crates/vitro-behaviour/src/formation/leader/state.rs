//! The leader's state: its route, its pace and lag, and the rule modules it consults.

use crate::belief::Whereabouts;
use crate::formation::FormationParams;
use crate::formation::ground::Ground;
use crate::formation::kb::Signature;
use crate::formation::motion::{Follow, Mover};
use crate::formation::pattern::{Pattern, Trail};
use crate::formation::record::{Arrival, Switch, TrackPoint};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro::time::{SimDuration, SimTime};
use vitro_site::geo::P2;
use vitro_tactical::entity::Pose;

/// The leader's modules and their update operations.
pub(super) const MODULES: Signature = &[
    ("eyes", &[]),
    ("squad", &["form", "brief"]),
    ("route", &["pace", "report"]),
];

pub(super) const EYES: usize = 0;

pub(super) const SQUAD: usize = 1;

pub(super) const ROUTE: usize = 2;

/// How much the squad lags: the worst member's distance to its slot.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(super) enum Lag {
    None,
    Some,
    Far,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(super) enum Pace {
    Normal,
    Slow,
    Halt,
}

/// An order being carried out.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct Route {
    pub(super) follow: Follow,
    pub(super) requester: EntityId,
    pub(super) goal: P2,
}

/// Everything the leader's modules read and write.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct State {
    pub(super) params: FormationParams,
    pub(super) roster: Vec<EntityId>,
    pub(super) pattern: Pattern,
    pub(super) switched_at: Option<SimTime>,
    pub(super) briefed: bool,
    pub(super) briefed_at: SimTime,
    pub(super) facing: Option<f64>,
    pub(super) briefed_facing: Option<f64>,
    pub(super) trail: Trail,
    pub(super) route: Option<Route>,
    /// The route being walked when a `Hold` came.
    pub(super) held: Option<Follow>,
    /// Since when the leader has stood at the goal, and how long it may wait there.
    pub(super) at_goal_since: Option<(SimTime, SimDuration)>,
    pub(super) lag: Lag,
    /// Since when the squad has lagged, and how long the leader may slow or wait for it.
    pub(super) lag_since: Option<(SimTime, SimDuration)>,
    /// The worst member's distance to its slot at the latest cycle, metres.
    pub(super) worst: f64,
    /// The leader's own walking speed, m/s.
    pub(super) walk: f64,
    /// Per slot at the discrete level: the slot last looked up and its nearest node.
    pub(super) nodes: Vec<Option<(P2, P2)>>,
    pub(super) gathered: bool,
    pub(super) pace: Option<Pace>,
    pub(super) contact: Option<(SimTime, P2)>,
    pub(super) ground: Ground,
    /// When the ground is next looked at.
    pub(super) next_look: SimTime,
    pub(super) pose: Option<Pose>,
    pub(super) mover: Mover,
    pub(super) next_log: SimTime,
    pub(super) log: Vec<TrackPoint>,
    pub(super) switches: Vec<Switch>,
    pub(super) arrivals: Vec<Arrival>,
    pub(super) problems: Vec<String>,
    /// Where the members are, from their position reports.
    pub(super) known: Whereabouts,
    /// When each member joined (a member never heard from counts as gone
    /// [`LINK_STALE`](super::super::LINK_STALE) after).
    pub(super) joined: BTreeMap<EntityId, SimTime>,
    /// Its own last fix sent to the members.
    pub(super) sent: Option<crate::belief::Fix>,
}
