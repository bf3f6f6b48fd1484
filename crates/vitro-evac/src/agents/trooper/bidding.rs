//! A trooper's side of the hunt's contract net (the truck calls, see the commander's
//! [hunters module](crate::agents::tender)): it bids for a pursuer slot from what it
//! knows of itself, and reports its contract done when the target is captured.
//!
//! **The bid** is a cost in metres: the straight-line distance from where the trooper is to
//! the target's place named in the call, plus [`LEAD_COST_M`] if it leads a squad of others
//! (the squad would need a new leader). Where it is: its own position on foot, or where the
//! vehicle it rides was last reported (its own eyes or the vehicle's position reports)
//! when aboard. A trooper down or captured answers nothing; one bound by a proposal not yet
//! answered refuses.

use super::{Task, Trooper};
use crate::agents::last_known;
use crate::agents::tender::HUNT_TASK;
use crate::radio::{Evac, Radio};
use crate::sense::Myself;
use vitro::entity::EntityId;
use vitro::protocol::CnetEvent;
use vitro::sim::Context;
use vitro_tactical::condition::Status;

/// What leading a squad of others adds to a hunt bid, metres.
pub const LEAD_COST_M: f64 = 300.0;

impl Trooper {
    /// The contract net's events of a bidder.
    pub(super) fn on_cnet(&mut self, event: CnetEvent<'_, Radio>, cx: &mut Context<'_, Evac>) {
        let status = cx.sense(&Myself).map(|(c, _)| c.status);
        if matches!(status, None | Some(Status::Down | Status::Captured)) {
            return;
        }
        match event {
            CnetEvent::CallForProposals { reply, cfp } => {
                let at = match &cfp.body {
                    Radio::Tender {
                        task,
                        at,
                        cost: None,
                    } if task == HUNT_TASK && cfp.from == self.brief.truck => Some(*at),
                    _ => None,
                };
                match at.and_then(|at| Some((at, self.hunt_cost(at, cx)?))) {
                    Some((at, cost)) => {
                        let body = Radio::Tender {
                            task: HUNT_TASK.into(),
                            at,
                            cost: Some(cost),
                        };
                        self.cnet.propose(cx, reply, body);
                    }
                    None => {
                        let no = Radio::Signal("busy".into(), String::new());
                        self.cnet.refuse(cx, reply, no);
                    }
                }
            }
            // The slot is its own: the truck's pursuit order follows.
            CnetEvent::Accepted { reply, .. } => self.contract = Some(reply),
            _ => {}
        }
    }

    /// What it bids for a hunt slot with the target at `at`, or nothing if it cannot take
    /// one (see the module's doc).
    fn hunt_cost(&self, at: [f64; 2], cx: &mut Context<'_, Evac>) -> Option<f64> {
        if self.cnet.pending_proposals().next().is_some() {
            return None;
        }
        let (me, pose) = cx.sense(&Myself)?;
        let from = match me.status {
            Status::Active => pose?.pos,
            Status::Aboard(v) => last_known(&self.known, v, cx.now()).or(pose.map(|p| p.pos))?,
            _ => return None,
        };
        let leads_others = self.leader().is_some_and(|l| !l.roster().is_empty());
        let lead = if leads_others { LEAD_COST_M } else { 0.0 };
        Some(libm::hypot(at[0] - from[0], at[1] - from[1]) + lead)
    }

    /// Taken off the roster of its hunt of `target` (lost, its slot gone to another): it
    /// leaves the hunt and stands.
    pub(super) fn leave_hunt(&mut self, target: EntityId) {
        if self.task == Task::Hunt(target) {
            self.task = Task::Idle;
            self.goal = None;
            self.hunt = None;
            self.hunters.clear();
            self.lead = None;
            self.contract = None;
        }
    }

    /// Reports its hunt contract done (the target captured), if it holds one.
    pub(super) fn report_capture(&mut self, cx: &mut Context<'_, Evac>) {
        if let Some(reply) = self.contract.take() {
            let body = Radio::Signal("captured".into(), String::new());
            self.cnet.report_done(cx, reply, body);
        }
    }
}
