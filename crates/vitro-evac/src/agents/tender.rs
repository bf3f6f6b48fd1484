//! The truck's allocation of the HVT hunt's pursuer slots by contract net: its state
//! ([`Tender`]) and the contract net's settings shared with the bidders. What the commander
//! does with it: see [`Commander`](super::commander::Commander).
//!
//! When the HVT is first reported, the commander opens `mission.hvt_pursuers` slots (every
//! trooper still up once the VIP is out) and calls for proposals for one slot at a time
//! ([`Radio::Tender`] `"hunt"`, with the target's last reported place) among the troopers
//! it counts on: the team, less those it knows are down and those already hunting. Each
//! trooper bids its own cost (see [`LEAD_COST_M`](crate::agents::trooper::LEAD_COST_M)); the
//! lowest wins and joins the hunt, and the next slot is called. A hunter is *lost* when it
//! is reported down, when it led the hunt and the pursuers report it silent (no move for
//! long turns: down unseen, or out of radio reach), or when its contract fails (its accept
//! bounced, or it gave no report within [`CONTRACT_S`]): it leaves
//! the roster and its slot is called again among the others (a *reallocation*). A
//! contract that ran out while the hunter is still on the roster is offered again to the
//! hunter alone (a renewal call): it keeps its place if it bids, else it is lost. A call
//! nobody answered is repeated every [`RECALL_S`] while slots are open.

use crate::radio::Radio;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro::protocol::{CnetConfig, ContractNet, TimerTag};
use vitro::time::{SimDuration, SimTime};

/// The task name of a hunt slot's call.
pub const HUNT_TASK: &str = "hunt";
/// How long a hunter's contract runs without a report before its slot is called again,
/// seconds (a hunter reports `done` when the target is captured).
pub const CONTRACT_S: u64 = 1200;
/// A slot whose call found nobody is called again after this long, seconds.
pub const RECALL_S: f64 = 120.0;
/// The timer tag of the contract net (the commander's and the troopers').
pub const CNET: TimerTag = TimerTag(0x434e);

/// The contract net's deadlines in the mission: 1 s to propose (radio delays are tens of
/// milliseconds), [`CONTRACT_S`] to report, proposals bind for 3 s.
pub fn cnet_config() -> CnetConfig {
    CnetConfig {
        proposal_deadline: SimDuration::from_secs(1),
        report_deadline: SimDuration::from_secs(CONTRACT_S),
        proposal_expiry: SimDuration::from_secs(3),
    }
}

/// The commander's allocation of the hunt's pursuer slots.
#[derive(Debug, Serialize, Deserialize)]
pub struct Tender {
    pub(crate) cnet: ContractNet<Radio>,
    /// Slots still to fill.
    pub(crate) open: u32,
    /// The call out (conversation), if any: one at a time.
    pub(crate) call: Option<u64>,
    /// When the last call went out.
    pub(crate) called_at: SimTime,
    /// Renewal calls out (conversation → the hunter whose contract ran out).
    pub(crate) renewals: BTreeMap<u64, EntityId>,
    /// The running contracts: hunter → conversation.
    pub(crate) contracts: BTreeMap<EntityId, u64>,
    /// Where the target was last reported, world (x, y).
    pub(crate) target_at: Option<[f64; 2]>,
    /// Calls for proposals made.
    pub calls: u64,
    /// Slots awarded (contracts renewed included).
    pub awards: u64,
    /// Slots called again because a hunter was lost.
    pub reallocations: u64,
    /// Contracts reported done (the target captured).
    pub done: u64,
}

impl Default for Tender {
    fn default() -> Self {
        Tender {
            cnet: ContractNet::new(CNET, cnet_config()),
            open: 0,
            call: None,
            called_at: SimTime::ZERO,
            renewals: BTreeMap::new(),
            contracts: BTreeMap::new(),
            target_at: None,
            calls: 0,
            awards: 0,
            reallocations: 0,
            done: 0,
        }
    }
}

impl Tender {
    /// The contract net machine (the commander hands it its inputs).
    pub(crate) fn cnet(&mut self) -> &mut ContractNet<Radio> {
        &mut self.cnet
    }
    /// Pursuer slots still to fill.
    pub fn open(&self) -> u32 {
        self.open
    }
    /// Whether `id` holds a running hunt contract (as far as the truck knows).
    pub fn holds(&self, id: EntityId) -> bool {
        self.contracts.contains_key(&id)
    }
    /// Calls, awards and reallocations so far.
    pub fn counts(&self) -> (u64, u64, u64) {
        (self.calls, self.awards, self.reallocations)
    }
}
