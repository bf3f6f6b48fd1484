//! The discrete level of ground vehicles and troops: a body is at a node of its street graph
//! and moves by hops along graph edges, each hop an event at the time the route's speed
//! profile reaches the next node ([`Track::plan_vehicle`](super::route::Track::plan_vehicle),
//! [`Track::plan_walk`](super::route::Track::plan_walk)).

use super::route::Track;
use crate::types::{GroundKind, TroopKind};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::env::NodeId;
use vitro::event::EventId;
use vitro_site::map::Mode;

/// What a node-level body is.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum NodeKind {
    /// A ground vehicle (drives on the drive graph).
    Ground(GroundKind),
    /// A trooper (walks on the walk graph).
    Troop(TroopKind),
}

impl NodeKind {
    /// The street graph it moves on.
    pub fn mode(self) -> Mode {
        match self {
            NodeKind::Ground(_) => Mode::Drive,
            NodeKind::Troop(_) => Mode::Walk,
        }
    }
}

/// A trip under way: the planned track and the next node to reach.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trip {
    /// The goal node.
    pub goal: NodeId,
    /// Index into the track's nodes of the next node to reach.
    pub next: usize,
    /// The pending hop event.
    pub pending: Option<EventId>,
    /// The plan (not part of the state digest: it is a function of the command).
    #[serde(skip)]
    pub track: Arc<Track>,
}

impl Trip {
    /// The next node and the simulated seconds from the previous node to it.
    pub fn next_hop(&self) -> Option<(NodeId, f64)> {
        let &(i, n) = self.track.nodes.get(self.next)?;
        let prev = self
            .next
            .checked_sub(1)
            .and_then(|k| self.track.nodes.get(k))
            .map_or(0, |&(j, _)| j);
        Some((n, self.track.t[i] - self.track.t[prev]))
    }
}

/// A body at a node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AtNode {
    /// What it is.
    pub kind: NodeKind,
    /// The node it is at (the last one reached while on a trip).
    pub node: NodeId,
    /// The trip under way, if any.
    pub trip: Option<Trip>,
    /// Mean speed of the hop under way, m/s (0 at rest).
    pub speed: f64,
    /// Heading of the hop under way (or the last one), radians from east.
    pub heading: f64,
}

impl AtNode {
    /// A body at rest at `node`.
    pub fn new(kind: NodeKind, node: NodeId) -> Self {
        AtNode {
            kind,
            node,
            trip: None,
            speed: 0.0,
            heading: 0.0,
        }
    }
}
