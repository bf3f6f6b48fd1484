//! The truck and its commander: drives the team to the safehouse leg by leg, sends the
//! troopers for the VIP, takes everybody back on board, drives to the extraction point, and
//! splits off pursuers when the high-value target is reported.

use super::{SENSE, tell};
use crate::actuate::MoveError;
use crate::arena::{Ev, TrackTarget};
use crate::condition::Status;
use crate::evac::act::{Dismount, Drive, Unload};
use crate::evac::brief::Brief;
use crate::evac::sense::Myself;
use crate::map::Mode;
use crate::model::{Controller, Intention, Tactical};
use crate::radio::{Order, Radio};
use std::collections::BTreeSet;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};

/// Timer key: the VIP is ready to leave.
const READY: u64 = 10;
/// Longest wait for troopers that do not answer (down, lost messages), seconds.
const PATIENCE_S: f64 = 600.0;
/// Orders are repeated to whoever has not answered after this long, seconds.
const REPEAT_S: f64 = 30.0;

/// Where the mission stands.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Driving to the safehouse.
    Out,
    /// Troopers on their way to the VIP.
    Pickup,
    /// Everybody coming back on board.
    Boarding,
    /// Driving to the extraction point.
    Back,
    /// At the extraction point.
    Done,
}

/// The truck's controller.
#[derive(Debug)]
pub struct Commander {
    brief: Arc<Brief>,
    drive: Drive,
    dismount: Dismount,
    /// Where the mission stands.
    pub phase: Phase,
    leg: usize,
    waiting: BTreeSet<EntityId>,
    waiting_since: SimTime,
    ordered_at: SimTime,
    hunt_ordered_at: SimTime,
    hunt_done: bool,
    /// The pursuers, once the hunt is on.
    pub hunters: Vec<EntityId>,
    hunt_pending: bool,
    /// When each phase began.
    pub log: Vec<(SimTime, Phase)>,
    /// The last refusal of the drive actuator, if the last leg was refused.
    pub refused: Option<MoveError>,
}

impl Commander {
    /// The commander of `brief`'s truck, driving at `drive`'s level.
    pub fn new(brief: Arc<Brief>, drive: Drive, dismount: Dismount) -> Self {
        Commander {
            brief,
            drive,
            dismount,
            phase: Phase::Out,
            leg: 0,
            waiting: BTreeSet::new(),
            waiting_since: SimTime::ZERO,
            ordered_at: SimTime::ZERO,
            hunt_ordered_at: SimTime::ZERO,
            hunt_done: false,
            hunters: Vec::new(),
            hunt_pending: false,
            log: Vec::new(),
            refused: None,
        }
    }

    fn legs(&self) -> &[NodeId] {
        match self.phase {
            Phase::Out => &self.brief.legs_out,
            _ => &self.brief.legs_back,
        }
    }

    fn enter(&mut self, phase: Phase, cx: &mut Context<'_, Tactical>) {
        self.phase = phase;
        self.log.push((cx.now(), phase));
        self.waiting_since = cx.now();
    }

    fn drive_leg(&mut self, cx: &mut Context<'_, Tactical>) {
        if let Some(&goal) = self.legs().get(self.leg) {
            self.refused = cx.act(&self.drive, goal).err();
        }
    }

    /// The team members on foot for this phase: the troopers not hunting.
    fn escorts(&self) -> Vec<EntityId> {
        let b = &self.brief;
        b.team
            .iter()
            .copied()
            .filter(|id| !self.hunters.contains(id))
            .collect()
    }

    fn on_arrived(&mut self, cx: &mut Context<'_, Tactical>) {
        if self.hunt_pending {
            self.release_hunters(cx);
        }
        self.leg += 1;
        if self.leg < self.legs().len() {
            self.drive_leg(cx);
            return;
        }
        match self.phase {
            Phase::Out => {
                let out: Vec<_> = self
                    .escorts()
                    .into_iter()
                    .map(|id| (id, self.brief.troop_kind(id)))
                    .collect();
                let _ = cx.act(&self.dismount, out);
                self.enter(Phase::Pickup, cx);
                let to = self.vip_point();
                self.ordered_at = cx.now();
                for id in self.escorts() {
                    tell(cx, id, Radio::Order(Order::GoTo([to[0], to[1]])));
                    self.waiting.insert(id);
                }
            }
            Phase::Back => {
                self.enter(Phase::Done, cx);
                let _ = cx.act(&Unload, ());
            }
            _ => {}
        }
    }

    fn board_all(&mut self, cx: &mut Context<'_, Tactical>) {
        self.enter(Phase::Boarding, cx);
        let me = cx.me();
        self.ordered_at = cx.now();
        let mut who = self.escorts();
        who.push(self.brief.vip);
        for id in who {
            tell(cx, id, Radio::Order(Order::Follow(me)));
            self.waiting.insert(id);
        }
    }

    fn leave(&mut self, cx: &mut Context<'_, Tactical>) {
        self.waiting.clear();
        self.enter(Phase::Back, cx);
        self.leg = 0;
        self.drive_leg(cx);
    }

    fn start_hunt(&mut self, cx: &mut Context<'_, Tactical>) {
        let k = self.brief.mission.hvt_pursuers as usize;
        if !self.hunters.is_empty() || k == 0 || self.phase == Phase::Done {
            return;
        }
        self.hunters = self.brief.team.iter().copied().take(k).collect();
        let waited_for_hunters = self.hunters.iter().any(|id| self.waiting.remove(id));
        match self.phase {
            Phase::Out | Phase::Back => self.hunt_pending = true,
            _ => self.release_hunters(cx),
        }
        if waited_for_hunters {
            self.all_answered(cx);
        }
    }

    /// Lets the pursuers out (if aboard) and sends them after the target.
    fn release_hunters(&mut self, cx: &mut Context<'_, Tactical>) {
        self.hunt_pending = false;
        let out: Vec<_> = self
            .hunters
            .iter()
            .map(|&id| (id, self.brief.troop_kind(id)))
            .collect();
        let _ = cx.act(&self.dismount, out);
        self.order_hunt(cx);
    }

    /// Sends the pursuit order to every pursuer.
    fn order_hunt(&mut self, cx: &mut Context<'_, Tactical>) {
        let Some(target) = self.brief.hvt else { return };
        self.hunt_ordered_at = cx.now();
        for &id in &self.hunters {
            tell(
                cx,
                id,
                Radio::Order(Order::Pursue {
                    target,
                    team: self.hunters.clone(),
                }),
            );
        }
    }

    fn on_signal(&mut self, from: EntityId, what: &str, cx: &mut Context<'_, Tactical>) {
        if what == "captured" {
            self.hunt_done = true;
        }
        if !self.waiting.remove(&from) {
            return;
        }
        if matches!(
            (self.phase, what),
            (Phase::Pickup, "arrived") | (Phase::Boarding, "aboard")
        ) {
            self.all_answered(cx);
        }
    }

    /// Moves on once nobody is waited for any more: the VIP gets ready, or the truck leaves.
    fn all_answered(&mut self, cx: &mut Context<'_, Tactical>) {
        if !self.waiting.is_empty() {
            return;
        }
        match self.phase {
            Phase::Pickup => {
                let ready = SimDuration::from_secs_f64(self.brief.mission.pickup_s);
                cx.set_timer(ready, READY);
            }
            Phase::Boarding => self.leave(cx),
            _ => {}
        }
    }

    /// Orders again whoever has not answered (orders or answers may be lost).
    fn repeat_orders(&mut self, cx: &mut Context<'_, Tactical>) {
        self.ordered_at = cx.now();
        let me = cx.me();
        let to = self.vip_point();
        let who: Vec<EntityId> = self.waiting.iter().copied().collect();
        for id in who {
            let order = match self.phase {
                Phase::Pickup => Order::GoTo([to[0], to[1]]),
                _ => Order::Follow(me),
            };
            tell(cx, id, Radio::Order(order));
        }
    }

    fn vip_point(&self) -> [f64; 3] {
        self.brief
            .node_point(Mode::Walk, self.brief.vip_node)
            .unwrap_or(self.brief.places[1])
    }

    fn on_sense(&mut self, cx: &mut Context<'_, Tactical>) {
        let alive = cx
            .sense(&Myself)
            .is_some_and(|(c, _)| c.status == Status::Active);
        if !alive {
            return;
        }
        let waited = cx.now().saturating_since(self.waiting_since).as_secs_f64();
        let since_orders = cx.now().saturating_since(self.ordered_at).as_secs_f64();
        if !self.waiting.is_empty() && since_orders >= REPEAT_S {
            self.repeat_orders(cx);
        }
        let since_hunt = cx
            .now()
            .saturating_since(self.hunt_ordered_at)
            .as_secs_f64();
        let hunting = !self.hunters.is_empty() && !self.hunt_pending && !self.hunt_done;
        if hunting && since_hunt >= REPEAT_S {
            // The pursuit order may have been lost: it is idempotent, send it again.
            self.order_hunt(cx);
        }
        if !self.waiting.is_empty() && waited > PATIENCE_S {
            match self.phase {
                Phase::Pickup => {
                    self.waiting.clear();
                    self.board_all(cx);
                }
                Phase::Boarding => self.leave(cx),
                _ => {}
            }
        }
        let period = SimDuration::from_secs_f64(self.brief.sensors.period_s);
        cx.set_timer(period, SENSE);
    }
}

impl Controller for Commander {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(crate::evac::brief::BLUE);
                self.log.push((cx.now(), Phase::Out));
                self.drive_leg(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
            }
            Input::Event(Ev::Arrived(n)) if self.legs().get(self.leg) == Some(n) => {
                self.on_arrived(cx);
            }
            Input::Timer(READY) if self.phase == Phase::Pickup => self.board_all(cx),
            Input::Timer(SENSE) => self.on_sense(cx),
            Input::Message(env) => match &env.body {
                Radio::Signal(what, _) => self.on_signal(env.from, what, cx),
                Radio::Contact { target, .. } if Some(*target) == self.brief.hvt => {
                    self.start_hunt(cx);
                }
                _ => {}
            },
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        let what = match self.phase {
            Phase::Out => "drive to the safehouse",
            Phase::Pickup => "troopers fetch the VIP",
            Phase::Boarding => "wait for everybody on board",
            Phase::Back => "drive to the extraction point",
            Phase::Done => "at the extraction point",
        };
        let legs = self.legs();
        let rest: Vec<[f64; 3]> = legs
            .iter()
            .skip(self.leg)
            .filter_map(|&n| self.brief.node_point(Mode::Drive, n))
            .collect();
        let mut plan: Vec<String> = Vec::new();
        if matches!(self.phase, Phase::Out | Phase::Back) {
            plan.push(format!("leg {}/{}", self.leg + 1, legs.len()));
        }
        if !self.hunters.is_empty() {
            plan.push(format!("{} pursuers after the HVT", self.hunters.len()));
        }
        if let Some(e) = &self.refused {
            plan.push(format!("cannot drive: {e}"));
        }
        Some(Intention {
            text: what.into(),
            plan,
            path: if matches!(self.phase, Phase::Out | Phase::Back) {
                rest
            } else {
                Vec::new()
            },
            ..Intention::default()
        })
    }
}

/// The truck's position as the team's blue-force tracker reports it.
pub fn truck_pose(cx: &mut Context<'_, Tactical>, truck: EntityId) -> Option<[f64; 3]> {
    cx.sense(&TrackTarget(truck)).map(|p| p.pos)
}
