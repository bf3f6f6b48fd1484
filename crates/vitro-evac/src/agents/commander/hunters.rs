//! The commander's side of the HVT hunt: the pursuer slots are allocated by contract net
//! (see [`Tender`](crate::agents::tender::Tender) for who is called, lost and replaced).

use super::{Commander, Phase};
use crate::agents::tell;
use crate::agents::tender::{HUNT_TASK, RECALL_S};
use crate::radio::{Evac, Order, Radio};
use vitro::entity::EntityId;
use vitro::protocol::{CallFailure, CnetEvent, Participants};
use vitro::sim::Context;

impl Commander {
    /// Whether pursuers are out after the HVT, not yet captured.
    pub(super) fn hunting(&self) -> bool {
        !self.hunters.is_empty() && !self.hunt_pending && !self.hunt_done
    }

    /// The troopers a call goes to: the team, less the fallen and the hunters.
    fn bidders(&self) -> Vec<EntityId> {
        (self.brief.team.iter().copied())
            .filter(|id| !self.fallen.contains(id) && !self.hunters.contains(id))
            .collect()
    }

    /// The HVT was reported at `at`: the first report opens `hvt_pursuers` slots (as many as
    /// troopers are up once the VIP is out) and calls for the first.
    pub(super) fn start_hunt(&mut self, at: [f64; 3], cx: &mut Context<'_, Evac>) {
        self.tender.target_at = Some([at[0], at[1]]);
        let k = self.brief.mission.hvt_pursuers;
        if self.hunt_called || k == 0 || self.hunt_done {
            return;
        }
        self.hunt_called = true;
        self.tender.open = if self.phase == Phase::Done {
            self.bidders().len() as u32
        } else {
            k
        };
        self.call_next(cx);
    }

    /// Every trooper still up joins the hunt (the VIP is out): one more slot for each.
    pub(super) fn all_join(&mut self, cx: &mut Context<'_, Evac>) {
        self.tender.open = self.bidders().len() as u32;
        self.call_next(cx);
    }

    /// Calls for proposals for the next open slot, unless a call is out, no slot is open,
    /// the hunt is over or nobody is left to call.
    pub(super) fn call_next(&mut self, cx: &mut Context<'_, Evac>) {
        let t = &self.tender;
        if t.call.is_some() || t.open == 0 || self.hunt_done {
            return;
        }
        let to = self.bidders();
        let Some(at) = t.target_at.filter(|_| !to.is_empty()) else {
            return;
        };
        let cfp = Radio::Tender {
            task: HUNT_TASK.into(),
            at,
            cost: None,
        };
        let slot = u64::from(self.tender.open);
        let conversation = self
            .tender
            .cnet
            .announce(cx, Participants::Agents(&to), slot, cfp);
        self.tender.call = Some(conversation);
        self.tender.called_at = cx.now();
        self.tender.calls += 1;
    }

    /// Calls again, at its next look, a slot whose last call found nobody (after
    /// [`RECALL_S`]).
    pub(super) fn tender_tick(&mut self, cx: &mut Context<'_, Evac>) {
        let since = cx.now().saturating_since(self.tender.called_at);
        if self.tender.call.is_none() && since.as_secs_f64() >= RECALL_S {
            self.call_next(cx);
        }
    }

    /// The hunt lead's latest idea of the target's place (its `search` signal).
    pub(super) fn search_point(&mut self, arg: &str) {
        let v: Vec<f64> = arg
            .split_whitespace()
            .filter_map(|s| s.parse().ok())
            .collect();
        if let [x, y] = v[..] {
            self.tender.target_at = Some([x, y]);
        }
    }

    /// The contract net's events: awards, failures (reallocations), reports.
    pub(super) fn on_cnet(&mut self, event: CnetEvent<'_, Radio>, cx: &mut Context<'_, Evac>) {
        match event {
            CnetEvent::Awarded {
                conversation,
                winner,
                ..
            } => {
                self.tender.awards += 1;
                self.tender.contracts.insert(winner, conversation);
                // A renewed contract: the hunter keeps its place.
                if self.tender.renewals.remove(&conversation).is_none() {
                    self.tender.call = None;
                    self.add_hunter(winner, cx);
                    self.tender.open = self.tender.open.saturating_sub(1);
                    self.call_next(cx);
                }
            }
            CnetEvent::Failed {
                conversation,
                reason,
                ..
            } => {
                if let Some(holder) = self.tender.renewals.remove(&conversation) {
                    // The holder did not take its contract again: lost.
                    if !self.hunt_done {
                        self.lose_hunter(holder, cx);
                    }
                    return;
                }
                let winner = match reason {
                    CallFailure::NoProposals => {
                        self.tender.call = None;
                        return;
                    }
                    CallFailure::WinnerFailed { winner }
                    | CallFailure::WinnerUnreachable { winner, .. }
                    | CallFailure::ReportTimedOut { winner } => winner,
                };
                if self.tender.contracts.get(&winner) != Some(&conversation) {
                    return;
                }
                self.tender.contracts.remove(&winner);
                if self.hunt_done {
                    return;
                }
                if matches!(reason, CallFailure::ReportTimedOut { .. }) {
                    // The contract ran out: offered again to its holder alone.
                    let Some(at) = self.tender.target_at else {
                        return;
                    };
                    let cfp = Radio::Tender {
                        task: HUNT_TASK.into(),
                        at,
                        cost: None,
                    };
                    let to = [winner];
                    let c = (self.tender.cnet).announce(cx, Participants::Agents(&to), 0, cfp);
                    self.tender.renewals.insert(c, winner);
                    self.tender.calls += 1;
                } else {
                    self.lose_hunter(winner, cx);
                }
            }
            CnetEvent::Done { winner, .. } => {
                self.tender.contracts.remove(&winner);
                self.tender.done += 1;
            }
            // The truck bids for nothing.
            CnetEvent::CallForProposals { reply, .. } => {
                let no = Radio::Signal("busy".into(), String::new());
                self.tender.cnet.refuse(cx, reply, no);
            }
            _ => {}
        }
    }

    /// Hunter `id` is lost (down, silent): it leaves the roster and its slot is called again.
    pub(super) fn lose_hunter(&mut self, id: EntityId, cx: &mut Context<'_, Evac>) {
        if !self.hunters.contains(&id) {
            return;
        }
        self.tender.contracts.remove(&id);
        if !self.hunt_done {
            self.tender.open += 1;
        }
        self.tender.reallocations += 1;
        self.drop_hunter(id, cx);
        self.call_next(cx);
    }

    /// Takes `id` off the roster: it is told the new roster (without it: it leaves the
    /// hunt), and so are the others.
    fn drop_hunter(&mut self, id: EntityId, cx: &mut Context<'_, Evac>) {
        if !self.hunters.contains(&id) {
            return;
        }
        self.hunters.retain(|&h| h != id);
        let Some(target) = self.brief.hvt else { return };
        if !self.fallen.contains(&id) && !self.hunt_pending {
            let team = self.hunters.clone();
            tell(cx, id, Radio::Order(Order::Pursue { target, team }));
        }
        if self.hunting() {
            self.order_hunt(cx);
        }
    }

    /// `id` won a slot: it joins the pursuers (let out at the next stop if the truck drives).
    fn add_hunter(&mut self, id: EntityId, cx: &mut Context<'_, Evac>) {
        if self.hunters.contains(&id) || self.fallen.contains(&id) {
            return;
        }
        self.hunters.push(id);
        let waited = self.waiting.remove(&id);
        self.reform(cx);
        match self.phase {
            Phase::Out | Phase::Back => self.hunt_pending = true,
            _ if self.hunt_pending => {}
            _ => self.release_hunters(cx),
        }
        if waited {
            self.all_answered(cx);
        }
    }

    /// Lets the pursuers out (if aboard) and sends them after the target.
    pub(super) fn release_hunters(&mut self, cx: &mut Context<'_, Evac>) {
        self.hunt_pending = false;
        let out: Vec<_> = (self.hunters.iter())
            .map(|&id| (id, self.brief.troop_kind(id)))
            .collect();
        let _ = cx.act(&self.dismount, out);
        self.order_hunt(cx);
    }

    /// Sends the pursuit order to every pursuer.
    pub(super) fn order_hunt(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(target) = self.brief.hvt else { return };
        self.hunt_ordered_at = cx.now();
        for &id in &self.hunters {
            let team = self.hunters.clone();
            tell(cx, id, Radio::Order(Order::Pursue { target, team }));
        }
    }
}
