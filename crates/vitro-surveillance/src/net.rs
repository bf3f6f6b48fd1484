//! What the team says over the radio: the contract net's bodies (a call for a sector, a
//! bid, a refusal, a confirmation), the auction's rounds and bids, the central plan's
//! assignments, status reports, sighting reports and revocations.
//!
//! The mission has its own vocabulary: the tactical model's message type is the mission's
//! to choose ([`vitro_tactical::radio`]), and the contract net reads bids from it through
//! [`Bid`].

use serde::{Deserialize, Serialize};
use vitro::comm::{GroupId, Protocol};
use vitro::entity::EntityId;
use vitro::protocol::Bid;

/// The multicast group of the team and its station.
pub const TEAM: GroupId = GroupId(1);

/// The protocol the auction's and the central plan's messages are counted under.
pub const ALLOCATION: Protocol = Protocol::Custom(1);

/// A message of the surveillance mission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Net {
    /// (Station → UAVs, a contract net call) "Who will search this sector?"
    Call {
        /// The sector.
        sector: u32,
        /// Its area, town metres `[x_min, y_min, x_max, y_max]`.
        area: [f64; 4],
    },
    /// (UAV → station, a proposal) "I will, at this cost": the seconds until it would have
    /// searched the sector once, its current sectors first.
    Offer {
        /// The sector.
        sector: u32,
        /// The bid: lower wins.
        cost: f64,
    },
    /// (UAV → station, a refusal) "I cannot" (it has no position to bid from).
    Decline {
        /// The sector.
        sector: u32,
    },
    /// (UAV → station, the contract's report) "The sector is mine now."
    Holding {
        /// The sector.
        sector: u32,
    },
    /// (UAV → team) its status: where it is, the sectors it holds, the targets it tracks
    /// (blue-force tracking; the station also hears that the UAV is alive).
    Status {
        /// Its GPS position, world metres.
        pos: [f64; 3],
        /// The sectors it holds, in order.
        sectors: Vec<u32>,
        /// The targets it follows (not the ones merely locked in passing).
        tracking: Vec<EntityId>,
    },
    /// (UAV → team) "I see `target` at `pos`" (its own camera's lock, last fix at
    /// `seen_ns`).
    Sighting {
        /// The target.
        target: EntityId,
        /// Where, world metres.
        pos: [f64; 3],
        /// When it was last seen, simulated nanoseconds.
        seen_ns: u64,
        /// Whether the sender follows it.
        following: bool,
    },
    /// (Station → UAV) "Drop these sectors: another UAV holds them."
    Revoke {
        /// The sectors.
        sectors: Vec<u32>,
    },
    /// (Station → team, an auction round) the last round's award, and "bid for one of
    /// these sectors".
    Round {
        /// The round's number.
        round: u64,
        /// The last round's award: the winner, the sector and its area.
        award: Option<(EntityId, u32, [f64; 4])>,
        /// The sectors waiting, with their areas (empty: the award only).
        sectors: Vec<(u32, [f64; 4])>,
    },
    /// (UAV → station, an auction bid) "I add this sector at this cost."
    Bid {
        /// The round.
        round: u64,
        /// The sector.
        sector: u32,
        /// The bid (the seconds until it would have searched it once): lower wins.
        cost: f64,
    },
    /// (Station → UAV, the central plan) "Add these sectors to yours."
    Assign {
        /// The sectors, with their areas.
        sectors: Vec<(u32, [f64; 4])>,
    },
}

impl Net {
    /// A short name of the message's kind, for recordings.
    pub fn kind(&self) -> &'static str {
        match self {
            Net::Call { .. } => "call",
            Net::Offer { .. } => "offer",
            Net::Decline { .. } => "decline",
            Net::Holding { .. } => "holding",
            Net::Status { .. } => "status",
            Net::Sighting { .. } => "sighting",
            Net::Revoke { .. } => "revoke",
            Net::Round { .. } => "round",
            Net::Bid { .. } => "bid",
            Net::Assign { .. } => "assign",
        }
    }
}

impl Bid for Net {
    fn bid(&self) -> Option<f64> {
        match self {
            Net::Offer { cost, .. } => Some(*cost),
            _ => None,
        }
    }
}
