//! The tactical radio: what agents of the [`Tactical`](crate::model::Tactical) model say to
//! each other through the simulated network (`vitro::comm`).
//!
//! One closed vocabulary for every controller of the tactical world, so that messages are
//! plain data (serialised into the trace hash) and any agent can read any report.

use crate::entity::{Level, Pose};
use crate::world::Side;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::time::{SimDuration, SimTime};

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
    /// The sender's own fix (blue-force tracking: its GPS position, heading and speed, and
    /// when it was taken).
    Position(Fix),
    /// An order to the receiver: what to do next.
    Order(Order),
    /// The sender's plan, step by step (e.g. the actions of a repaired plan).
    Plan(Vec<String>),
    /// A named signal with a short argument (e.g. `("formation", "wedge")`).
    Signal(String, String),
    /// Task allocation by contract net ([`vitro::protocol::contract_net`]): a call for
    /// proposals for `task` at `at` (no `cost`), or a proposal for it bidding `cost`
    /// (lower wins).
    Tender {
        /// What is allocated (e.g. `"hunt"`, a pursuer slot of the HVT hunt).
        task: String,
        /// Where the task is, world (x, y), as far as the caller knows.
        at: [f64; 2],
        /// The bid, in a proposal.
        cost: Option<f64>,
    },
}

impl vitro::protocol::Bid for Radio {
    /// The cost a [`Radio::Tender`] proposal bids; no other message bids.
    fn bid(&self) -> Option<f64> {
        match self {
            Radio::Tender { cost, .. } => *cost,
            _ => None,
        }
    }
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

/// One fix of an entity: where it was, which way it faced and moved, and when.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fix {
    /// Position, world metres.
    pub pos: [f64; 3],
    /// Heading (where it faces), radians counter-clockwise from east (0 if unknown).
    pub heading: f64,
    /// Course over the ground (where it moves), radians counter-clockwise from east.
    pub course: f64,
    /// Speed over the ground along the course, m/s (0 if unknown).
    pub speed: f64,
    /// When it was taken.
    pub at: SimTime,
}

impl Fix {
    /// The fix of a pose taken at `at`, moving the way it faces (vehicles, aircraft).
    pub fn of(pose: &Pose, at: SimTime) -> Fix {
        Fix {
            pos: pose.pos,
            heading: pose.heading,
            course: pose.heading,
            speed: pose.speed,
            at,
        }
    }

    /// The fix a GPS gives of `pose` at `at` after its fix `prev`: a trooper at the
    /// directed level may walk one way and face another, so its course and speed are those
    /// over the ground since `prev` (if that is at most 10 s old); anything else moves the
    /// way it faces ([`Fix::of`]).
    pub fn after(pose: &Pose, at: SimTime, prev: Option<&Fix>) -> Fix {
        let mut fix = Fix::of(pose, at);
        if pose.level == Level::Directed
            && let Some(p) = prev
        {
            let dt = at.saturating_since(p.at).as_secs_f64();
            if dt > 0.0 && dt <= 10.0 {
                let (dx, dy) = (pose.pos[0] - p.pos[0], pose.pos[1] - p.pos[1]);
                fix.course = libm::atan2(dy, dx);
                fix.speed = libm::hypot(dx, dy) / dt;
            }
        }
        fix
    }

    /// How old the fix is at `now`.
    pub fn age(&self, now: SimTime) -> SimDuration {
        now.saturating_since(self.at)
    }

    /// Where the entity is at `now` if it kept its course and speed since the fix (dead
    /// reckoning; the height is kept).
    pub fn predicted(&self, now: SimTime) -> [f64; 3] {
        let d = self.speed * self.age(now).as_secs_f64();
        [
            self.pos[0] + d * libm::cos(self.course),
            self.pos[1] + d * libm::sin(self.course),
            self.pos[2],
        ]
    }

    /// The fix as a pose at `now`: the dead-reckoned position, the reported heading and
    /// speed, at `level`.
    pub fn pose(&self, now: SimTime, level: Level) -> Pose {
        Pose {
            pos: self.predicted(now),
            heading: self.heading,
            speed: self.speed,
            level,
        }
    }
}
