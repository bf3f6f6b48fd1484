//! Rounds: a set of agents activated once each, in a fresh random order, every period.
//!
//! The activation schedule of the agent-based modelling frameworks (MASON's `RandomSequence`,
//! Mesa's `RandomActivation`, krABMaga's repeating schedule) as one event of the queue per
//! firing: the driver shuffles the members (from the run's `"round_order"` small stream) and
//! hands each an [`Input::Timer`](super::Input::Timer) with the round's key, one after the
//! other, at the round's instant. Each activation is traced (the member's id after the
//! round's event), so the trace hash still sees every activation and its order.
//!
//! An agent that would otherwise schedule its own next activation each step, drawing an
//! instant in the step's window to get a random order, costs a queue push, a pop, a slot and
//! a draw per activation; a member of a round costs a draw of the shuffle.

use crate::entity::EntityId;
use crate::time::{SimDuration, SimTime};
use serde::{Deserialize, Serialize};

/// Handle of a round ([`Simulation::add_round`](super::Simulation::add_round)).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct RoundId(pub(crate) u32);

/// One round's members and timing.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Round {
    /// The members in the order of the last firing, then those that joined since; each
    /// entity at most once (`listed`).
    pub members: Vec<EntityId>,
    /// Per entity index: wants to be activated.
    pub active: Vec<bool>,
    /// Per entity index: in `members` (or in the order being fired).
    pub listed: Vec<bool>,
    /// The key every activation's timer carries.
    pub key: u64,
    /// Time between firings.
    pub period: SimDuration,
    /// When it fires next (if it is pending) or would have (if it went idle).
    pub next_at: SimTime,
    /// A firing is pending in the queue.
    pub pending: bool,
    /// Some member left since the list was last cleaned.
    pub left: bool,
}

impl Round {
    /// Marks `e` a member; true if it was not one. Returns whether it must be appended to
    /// `members` (it is not listed yet).
    pub fn join(&mut self, e: EntityId) -> bool {
        let i = e.index();
        if self.active.len() <= i {
            self.active.resize(i + 1, false);
        }
        if self.listed.len() <= i {
            self.listed.resize(i + 1, false);
        }
        let was = std::mem::replace(&mut self.active[i], true);
        if !self.listed[i] {
            self.listed[i] = true;
            self.members.push(e);
        }
        !was
    }

    /// Marks `e` no longer a member (it leaves the list after the next firing); true if it
    /// was one.
    pub fn leave(&mut self, e: EntityId) -> bool {
        let was = self
            .active
            .get_mut(e.index())
            .is_some_and(|a| std::mem::replace(a, false));
        self.left |= was;
        was
    }

    /// True if `e` wants to be activated.
    #[inline]
    pub fn is_active(&self, e: EntityId) -> bool {
        self.active.get(e.index()).copied().unwrap_or(false)
    }

    /// After a firing over `order`: keeps the members still active (in that order), then
    /// those that joined during the firing, and puts them back.
    pub fn settle(&mut self, mut order: Vec<EntityId>) {
        order.append(&mut self.members);
        if std::mem::take(&mut self.left) {
            let (active, listed) = (&self.active, &mut self.listed);
            order.retain(|e| {
                let keep = active.get(e.index()).copied().unwrap_or(false);
                if !keep && let Some(l) = listed.get_mut(e.index()) {
                    *l = false;
                }
                keep
            });
        }
        self.members = order;
    }

    /// Number of members.
    pub fn len(&self) -> usize {
        self.members.iter().filter(|e| self.is_active(**e)).count()
    }
}
