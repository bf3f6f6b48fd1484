//! The truck and its commander: drives the team to the safehouse leg by leg, sends the
//! troopers for the VIP as a squad in formation (see the [squad module](super::squad)) and
//! back with it, takes everybody on board, drives to the extraction point, and splits off
//! pursuers when the high-value target is reported (the slots allocated by contract net,
//! see [`Tender`]).

use super::hunt::SILENT;
use super::{SENSE, tell};
use crate::act::{Dismount, Drive, Unload};
use crate::brief::Brief;
use crate::radio::{Evac, Order, Radio};
use crate::sense::Myself;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::protocol::Handled;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_behaviour::belief::Beacon;
use vitro_site::map::Mode;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::arena::{Ev, StallReason};
use vitro_tactical::condition::Status;
use vitro_tactical::model::{Controller, Intention};

mod hunters;
use super::tender::Tender;

/// Timer key: the VIP is ready to leave.
const READY: u64 = 10;
/// Longest wait for troopers that do not answer (down, lost messages), seconds.
const PATIENCE_S: f64 = 600.0;
/// Orders are repeated to whoever has not answered after this long, seconds.
const REPEAT_S: f64 = 30.0;

/// Where the mission stands.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    /// Driving to the safehouse.
    Out,
    /// The squad on its way to the VIP, and waiting with it for the pickup time.
    Pickup,
    /// The squad bringing the VIP back to the truck.
    Escort,
    /// Everybody coming back on board.
    Boarding,
    /// Driving to the extraction point.
    Back,
    /// At the extraction point.
    Done,
}

/// The squad walking in formation during the pickup, as the commander made it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Squad {
    /// Who leads it (and is ordered where to go).
    pub leader: EntityId,
    /// Who follows the leader, in slot order (the VIP last, once reached).
    pub members: Vec<EntityId>,
    /// Where it is going, world (x, y).
    pub goal: [f64; 2],
}

/// The truck's controller.
#[derive(Debug, Serialize, Deserialize)]
pub struct Commander {
    #[serde(with = "vitro_mission::snapshot::briefed")]
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
    /// True once the hunt was called (the HVT first reported).
    hunt_called: bool,
    /// The pursuers, once the hunt is on.
    pub hunters: Vec<EntityId>,
    hunt_pending: bool,
    /// The allocation of the pursuer slots by contract net.
    pub tender: Tender,
    /// When each phase began.
    pub log: Vec<(SimTime, Phase)>,
    /// The last refusal of the drive actuator, if the last leg was refused.
    pub refused: Option<MoveError>,
    /// The squad on foot, while it walks.
    pub squad: Option<Squad>,
    /// Team members reported down.
    pub fallen: BTreeSet<EntityId>,
    /// The truck's blue-force tracker.
    beacon: Beacon,
    /// Trips the truck gave up (stuck: no progress for the arena's stall time), all legs.
    pub stalls: u32,
    /// Trips given up on the current leg (the leg is tried again up to [`LEG_TRIES`]
    /// times, then the truck stays where it is and says so).
    leg_stalls: u32,
}

/// How many times the truck tries a leg it got stuck on.
pub const LEG_TRIES: u32 = 3;
/// Timer key: try the current leg again after a stall.
const RETRY: u64 = 31;
/// Pause before trying a leg again, seconds.
const RETRY_S: u64 = 5;

impl Commander {
    /// The commander of `brief`'s truck, driving at `drive`'s level.
    pub fn new(brief: Arc<Brief>, drive: Drive, dismount: Dismount) -> Self {
        let beacon = super::beacon(&brief);
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
            hunt_called: false,
            hunters: Vec::new(),
            hunt_pending: false,
            tender: Tender::default(),
            log: Vec::new(),
            refused: None,
            squad: None,
            fallen: BTreeSet::new(),
            beacon,
            stalls: 0,
            leg_stalls: 0,
        }
    }

    fn legs(&self) -> &[NodeId] {
        match self.phase {
            Phase::Out => &self.brief.legs_out,
            _ => &self.brief.legs_back,
        }
    }

    fn enter(&mut self, phase: Phase, cx: &mut Context<'_, Evac>) {
        self.phase = phase;
        self.log.push((cx.now(), phase));
        self.waiting_since = cx.now();
    }

    fn drive_leg(&mut self, cx: &mut Context<'_, Evac>) {
        if let Some(&goal) = self.legs().get(self.leg) {
            self.refused = cx.act(&self.drive, goal).err();
        }
    }

    /// The truck gave up its trip to `goal`: tries the leg again after a pause, up to
    /// [`LEG_TRIES`] times; then it stays, and its intention says why.
    fn on_stalled(&mut self, goal: NodeId, why: StallReason, cx: &mut Context<'_, Evac>) {
        self.stalls += 1;
        self.leg_stalls += 1;
        if self.leg_stalls < LEG_TRIES {
            cx.set_timer(SimDuration::from_secs(RETRY_S), RETRY);
        } else {
            self.refused = Some(MoveError::Stalled(cx.me(), goal, why));
        }
    }

    /// The team members on foot for this phase: the troopers not hunting nor down.
    fn escorts(&self) -> Vec<EntityId> {
        let b = &self.brief;
        b.team
            .iter()
            .copied()
            .filter(|id| !self.hunters.contains(id) && !self.fallen.contains(id))
            .collect()
    }

    fn on_arrived(&mut self, cx: &mut Context<'_, Evac>) {
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
                // The last escort leads: pursuers are taken from the first troopers, so a
                // hunt called during the walk takes members rather than the leader.
                let escorts = self.escorts();
                match escorts.split_last() {
                    Some((&leader, rest)) => {
                        self.squad = Some(Squad {
                            leader,
                            members: rest.to_vec(),
                            goal: [to[0], to[1]],
                        });
                        self.order_squad(cx);
                    }
                    // Nobody to send: the VIP comes alone.
                    None => self.board_all(cx),
                }
            }
            Phase::Back => {
                self.enter(Phase::Done, cx);
                // The VIP is out; the escort gets off to join a hunt still on, and whoever
                // stays aboard is extracted with the VIP.
                if self.hunting() {
                    let escorts = self.escorts();
                    let out: Vec<_> = (escorts.iter())
                        .map(|&id| (id, self.brief.troop_kind(id)))
                        .collect();
                    let _ = cx.act(&self.dismount, out);
                    self.all_join(cx);
                }
                let _ = cx.act(&Unload, ());
            }
            _ => {}
        }
    }

    /// Orders the squad where it goes: the leader to its goal (with the roster the truck
    /// counts on), the others to follow the leader; waits for the leader's answer.
    fn order_squad(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(s) = &self.squad else {
            return;
        };
        self.ordered_at = cx.now();
        tell(cx, s.leader, Radio::Order(Order::GoTo(s.goal)));
        let roster: Vec<String> = s.members.iter().map(|m| m.0.to_string()).collect();
        tell(
            cx,
            s.leader,
            Radio::Signal("squad".into(), roster.join(" ")),
        );
        for &m in &s.members {
            tell(cx, m, Radio::Order(Order::Follow(s.leader)));
        }
        self.waiting.clear();
        self.waiting.insert(s.leader);
    }

    /// Keeps the squad led by someone on his feet and not hunting: drops the others, and
    /// promotes the last trooper that follows when the leader is gone (ordered at once);
    /// gives the squad up (everybody back on board) when no trooper is left to lead it.
    fn reform(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(s) = &mut self.squad else {
            return;
        };
        let (fallen, hunters) = (&self.fallen, &self.hunters);
        let fit = |id: &EntityId| !fallen.contains(id) && !hunters.contains(id);
        s.members.retain(fit);
        if fit(&s.leader) {
            return;
        }
        match s.members.iter().rposition(|m| self.brief.team.contains(m)) {
            Some(i) => {
                s.leader = s.members.remove(i);
                self.order_squad(cx);
            }
            None => self.board_all(cx),
        }
    }

    /// A team member was reported down.
    fn casualty(&mut self, id: EntityId, cx: &mut Context<'_, Evac>) {
        if !self.fallen.insert(id) {
            return;
        }
        let waited = self.waiting.remove(&id);
        // A fallen pursuer leaves the roster (if it led, the next one takes over) and its
        // slot is called again.
        self.lose_hunter(id, cx);
        self.reform(cx);
        if waited {
            self.all_answered(cx);
        }
    }

    /// The pickup time is over: the squad brings the VIP back to the truck (everybody
    /// boards at once if there is no squad any more).
    fn escort_back(&mut self, cx: &mut Context<'_, Evac>) {
        let to = self.truck_point(cx);
        let Some(s) = &mut self.squad else {
            self.board_all(cx);
            return;
        };
        s.goal = to;
        self.enter(Phase::Escort, cx);
        self.order_squad(cx);
    }

    /// The walk-graph point nearest the truck, world (x, y).
    fn truck_point(&self, cx: &mut Context<'_, Evac>) -> [f64; 2] {
        let at = cx
            .sense(&Myself)
            .and_then(|(_, p)| p)
            .map_or(self.brief.places[1], |p| p.pos);
        let p = self
            .brief
            .walk_node(at)
            .and_then(|n| self.brief.node_point(Mode::Walk, n))
            .unwrap_or(at);
        [p[0], p[1]]
    }

    fn board_all(&mut self, cx: &mut Context<'_, Evac>) {
        self.squad = None;
        self.waiting.clear();
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

    fn leave(&mut self, cx: &mut Context<'_, Evac>) {
        self.waiting.clear();
        self.enter(Phase::Back, cx);
        self.leg = 0;
        self.drive_leg(cx);
    }

    fn on_signal(&mut self, from: EntityId, what: &str, arg: &str, cx: &mut Context<'_, Evac>) {
        match what {
            "captured" => self.hunt_done = true,
            super::hunt::SEARCH => {
                self.search_point(arg);
                return;
            }
            "down" => {
                let id = arg.trim().parse().ok().map(EntityId);
                let ours = |id: &EntityId| self.brief.team.contains(id) || *id == self.brief.vip;
                if let Some(id) = id.filter(ours) {
                    self.casualty(id, cx);
                }
                return;
            }
            SILENT => {
                // The hunt lead is silent: lost (down unseen, or out of reach). The next
                // pursuer leads, and the slot is called again.
                let who = arg.trim().parse().ok().map(EntityId);
                if let Some(id) = who.filter(|_| self.hunting()) {
                    self.lose_hunter(id, cx);
                }
                return;
            }
            "unreachable" if self.squad.as_ref().is_some_and(|s| s.leader == from) => {
                // No walk route for the squad: everybody back on board on their own.
                self.board_all(cx);
                return;
            }
            _ => {}
        }
        if !self.waiting.remove(&from) {
            return;
        }
        if matches!(
            (self.phase, what),
            (Phase::Pickup | Phase::Escort, "arrived") | (Phase::Boarding, "aboard")
        ) {
            self.all_answered(cx);
        }
    }

    /// Moves on once nobody is waited for any more: the VIP gets ready, or the truck leaves.
    fn all_answered(&mut self, cx: &mut Context<'_, Evac>) {
        if !self.waiting.is_empty() {
            return;
        }
        match self.phase {
            Phase::Pickup => {
                // The squad is at the VIP, who joins it.
                let vip = self.brief.vip;
                if let Some(s) = &mut self.squad
                    && !s.members.contains(&vip)
                {
                    s.members.push(vip);
                    tell(cx, vip, Radio::Order(Order::Follow(s.leader)));
                }
                let ready = SimDuration::from_secs_f64(self.brief.mission.pickup_s);
                cx.set_timer(ready, READY);
            }
            Phase::Escort => self.board_all(cx),
            Phase::Boarding => self.leave(cx),
            _ => {}
        }
    }

    /// Orders again whoever has not answered (orders or answers may be lost).
    fn repeat_orders(&mut self, cx: &mut Context<'_, Evac>) {
        if self.squad.is_some() {
            self.order_squad(cx);
            return;
        }
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

    fn on_sense(&mut self, cx: &mut Context<'_, Evac>) {
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
        if self.hunting() && since_hunt >= REPEAT_S {
            // The pursuit order may have been lost: it is idempotent, send it again.
            self.order_hunt(cx);
        }
        self.tender_tick(cx);
        if !self.waiting.is_empty() && waited > PATIENCE_S {
            match self.phase {
                Phase::Pickup | Phase::Escort => self.board_all(cx),
                Phase::Boarding => self.leave(cx),
                _ => {}
            }
        }
        let period = SimDuration::from_secs_f64(self.brief.sensors.period_s);
        cx.set_timer(period, SENSE);
    }
}

impl Controller<Evac> for Commander {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match self.tender.cnet().handle(input, cx) {
            Handled::Event(e) => return self.on_cnet(e, cx),
            Handled::Consumed => return,
            Handled::NotMine => {}
        }
        match input {
            Input::Event(Ev::Start) => {
                cx.join(crate::brief::BLUE);
                self.log.push((cx.now(), Phase::Out));
                self.drive_leg(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
                self.beacon.start(cx);
            }
            Input::Timer(Beacon::TIMER) => self.beacon.tick(cx),
            Input::Event(Ev::Arrived(n)) if self.legs().get(self.leg) == Some(n) => {
                self.leg_stalls = 0;
                self.on_arrived(cx);
            }
            Input::Event(Ev::Stalled(n, why)) if self.legs().get(self.leg) == Some(n) => {
                self.on_stalled(*n, *why, cx);
            }
            Input::Timer(RETRY) => self.drive_leg(cx),
            Input::Timer(READY) if self.phase == Phase::Pickup => self.escort_back(cx),
            Input::Timer(SENSE) => self.on_sense(cx),
            Input::Message(env) => match &env.body {
                Radio::Signal(what, arg) => self.on_signal(env.from, what, arg, cx),
                Radio::Contact { target, pos, .. } if Some(*target) == self.brief.hvt => {
                    self.start_hunt(*pos, cx);
                }
                _ => {}
            },
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        let what = match self.phase {
            Phase::Out => "drive to the safehouse",
            Phase::Pickup => "the squad fetches the VIP",
            Phase::Escort => "the squad brings the VIP to the truck",
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
        if let Some(s) = &self.squad {
            let members: Vec<String> = s.members.iter().map(|m| m.to_string()).collect();
            plan.push(format!("squad led by {}: {}", s.leader, members.join(" ")));
        }
        if !self.hunters.is_empty() {
            plan.push(format!("{} pursuers after the HVT", self.hunters.len()));
        }
        if self.tender.open() > 0 && !self.hunt_done {
            plan.push(format!("{} hunt slots to allocate", self.tender.open()));
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
