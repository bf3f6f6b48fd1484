//! A trooper on the hunt: each turn the lead pursuer runs the search and orders the team;
//! the others watch for a lead gone silent.

use super::{DECIDED, TURN, Task, Trooper};
use crate::agents::hunt::{HuntStep, LEAD_SILENT_TURNS, SILENT};
use crate::agents::tell;
use crate::radio::{Evac, Order, Radio};
use crate::sense::Myself;
use vitro::entity::EntityId;
use vitro::sim::Context;
use vitro::time::SimDuration;
use vitro_site::map::Mode;
use vitro_tactical::condition::Status;

impl Trooper {
    /// A pursuer whose hunt lead has sent no move for [`LEAD_SILENT_TURNS`] long turns
    /// tells the truck (at most once per that time): the lead may be down unseen, or out of
    /// radio reach.
    pub(super) fn check_lead(&mut self, cx: &mut Context<'_, Evac>) {
        let me = cx.me();
        let now = cx.now();
        if !matches!(self.task, Task::Hunt(_)) {
            return;
        }
        let Some((lead, heard)) = self.lead.as_mut() else {
            return;
        };
        let silent = SimDuration::from_secs_f64(LEAD_SILENT_TURNS * 2.0 * self.brief.turn_s);
        if *lead != me && now.saturating_since(*heard) >= silent {
            *heard = now;
            let msg = Radio::Signal(SILENT.into(), lead.0.to_string());
            tell(cx, self.brief.truck, msg);
        }
    }

    /// The other pursuers (all but me) of the hunt I am on.
    pub(super) fn team_of_hunt(&self) -> Vec<EntityId> {
        self.hunters.clone()
    }

    pub(super) fn period(&self) -> SimDuration {
        SimDuration::from_secs_f64(self.brief.sensors.period_s)
    }

    pub(super) fn on_turn(&mut self, cx: &mut Context<'_, Evac>) {
        let alive = cx
            .sense(&Myself)
            .is_some_and(|(c, _)| c.status == Status::Active);
        let Some(hunt) = self.hunt.as_mut() else {
            return;
        };
        if !alive {
            return;
        }
        self.clock.begin(cx);
        match hunt.turn(cx, &self.known) {
            HuntStep::Think(delay) => {
                cx.set_timer(delay, DECIDED);
            }
            HuntStep::Over => {}
        }
    }

    pub(super) fn on_decided(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(hunt) = self.hunt.as_mut() else {
            return;
        };
        let me = cx.me();
        let orders = hunt.orders();
        let mut mine = None;
        for (who, node) in orders {
            let Some(p) = self.brief.node_point(Mode::Walk, node) else {
                continue;
            };
            if who == me {
                mine = Some(node);
            } else {
                tell(cx, who, Radio::Order(Order::GoTo([p[0], p[1]])));
            }
        }
        if let Some(node) = mine {
            self.walk_to(node, cx);
        }
        // The next turn starts when the lead arrives (see on_arrived), or after a long turn
        // at the latest (a lost arrival, an order refused).
        let turn = SimDuration::from_secs_f64(2.0 * self.brief.turn_s);
        self.clock.next_in(turn, TURN, cx);
    }
}
