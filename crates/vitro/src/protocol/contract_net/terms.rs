//! The contract net's vocabulary: bids, deadlines, participants, failures and the events an
//! agent handles.

use crate::comm::{DeliveryError, Envelope, GroupId};
use crate::entity::EntityId;
use crate::protocol::Reply;
use crate::time::SimDuration;
use serde::{Deserialize, Serialize};

/// Reads the bid a proposal's body carries (implemented by the model's `Msg`).
///
/// ```
/// use vitro::protocol::Bid;
/// #[derive(Clone, serde::Serialize)]
/// enum Msg { Task(u32), Offer { task: u32, cost: f64 }, Nothing }
/// impl Bid for Msg {
///     fn bid(&self) -> Option<f64> {
///         match self { Msg::Offer { cost, .. } => Some(*cost), _ => None }
///     }
/// }
/// assert_eq!(Msg::Offer { task: 1, cost: 2.5 }.bid(), Some(2.5));
/// ```
pub trait Bid {
    /// The cost this proposal bids (lower wins), `None` if the body carries no bid.
    fn bid(&self) -> Option<f64>;
}

/// Deadlines of the contract net.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CnetConfig {
    /// (Initiator) how long after a call it decides, at the latest.
    pub proposal_deadline: SimDuration,
    /// (Initiator) how long after the award the winner has to report.
    pub report_deadline: SimDuration,
    /// (Participant) how long after proposing it waits for an accept or a reject; make it
    /// longer than the initiator's proposal deadline plus the channel's delays.
    pub proposal_expiry: SimDuration,
}

impl Default for CnetConfig {
    /// 1 s to propose, 10 s to report, proposals expire after 2 s.
    fn default() -> Self {
        CnetConfig {
            proposal_deadline: SimDuration::from_secs(1),
            report_deadline: SimDuration::from_secs(10),
            proposal_expiry: SimDuration::from_secs(2),
        }
    }
}

/// Who a call for proposals goes to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Participants<'p> {
    /// These agents, one direct message each.
    Agents(&'p [EntityId]),
    /// A multicast group (every member but the initiator).
    Group(GroupId),
    /// Every agent but the initiator.
    Broadcast,
}

/// Why a call ended without the task done.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum CallFailure {
    /// No valid proposal by the deadline.
    NoProposals,
    /// The winner reported a failure.
    WinnerFailed {
        /// The winner.
        winner: EntityId,
    },
    /// The winner did not report within the report deadline (or its report was lost, or the
    /// accept was).
    ReportTimedOut {
        /// The winner.
        winner: EntityId,
    },
    /// The accept came back undelivered.
    WinnerUnreachable {
        /// The winner.
        winner: EntityId,
        /// Why.
        error: DeliveryError,
    },
}

/// What happened in the contract net.
#[derive(Debug, PartialEq)]
pub enum CnetEvent<'a, Msg> {
    /// (Initiator) the best proposal was accepted, the others rejected; the winner's report is
    /// awaited.
    Awarded {
        /// The call.
        conversation: u64,
        /// The task label given to [`ContractNet::announce`](crate::protocol::ContractNet::announce).
        task: u64,
        /// The winner.
        winner: EntityId,
        /// Its bid.
        bid: f64,
        /// How many valid proposals there were.
        proposals: usize,
    },
    /// (Initiator) the winner reported the task done. Closed.
    Done {
        /// The call.
        conversation: u64,
        /// The task label.
        task: u64,
        /// The winner.
        winner: EntityId,
        /// Its report.
        report: &'a Envelope<Msg>,
    },
    /// (Initiator) the call ended without the task done. Closed; re-announce `cfp` if need be.
    Failed {
        /// The call.
        conversation: u64,
        /// The task label.
        task: u64,
        /// Why.
        reason: CallFailure,
        /// The winner's failure report, if that is why.
        report: Option<&'a Envelope<Msg>>,
        /// The call's body, handed back.
        cfp: Msg,
    },
    /// (Participant) a call for proposals: [`propose`](crate::protocol::ContractNet::propose) or
    /// [`refuse`](crate::protocol::ContractNet::refuse).
    CallForProposals {
        /// Where to answer.
        reply: Reply,
        /// The call.
        cfp: &'a Envelope<Msg>,
    },
    /// (Participant) its proposal won: do the task and report.
    Accepted {
        /// Where to report.
        reply: Reply,
        /// The accept (echoing the proposal).
        accept: &'a Envelope<Msg>,
        /// True if the proposal had already expired (or was never made): the agent decides
        /// whether it can still do the task, and reports a failure if not.
        late: bool,
    },
    /// (Participant) its proposal lost.
    Rejected {
        /// The call.
        reply: Reply,
    },
    /// (Participant) no accept or reject within the expiry, or the proposal came back
    /// undelivered: it binds no more.
    Expired {
        /// The call.
        reply: Reply,
    },
}
