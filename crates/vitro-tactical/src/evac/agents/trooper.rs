//! Blue troopers and the VIP on foot: they walk where the commander orders, come back on
//! board, report hostile contacts, and — when sent after the high-value target — hunt it
//! as a team (the first pursuer runs the search, see [`hunt`](super::hunt)).

use super::hunt::{Hunt, HuntStep, TurnClock};
use super::{Reporter, SENSE, tell};
use crate::arena::{Ev, TrackTarget};
use crate::condition::Status;
use crate::evac::act::{Board, Capture, Walk};
use crate::evac::brief::{BLUE, Brief};
use crate::evac::sense::{Myself, Vision};
use crate::map::Mode;
use crate::model::{Controller, Intention, Tactical};
use crate::radio::{Order, Radio};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::SimDuration;

/// Timer key of the hunt's turns.
pub(crate) const TURN: u64 = 20;
/// Timer key: the hunt's search is done (its simulated thinking time has passed).
pub(crate) const DECIDED: u64 = 21;

/// What a trooper is doing.
#[derive(Clone, Debug, PartialEq)]
pub enum Task {
    /// Nothing (or riding).
    Idle,
    /// Walking to a node, then reporting to `boss`.
    GoTo {
        /// The goal.
        node: NodeId,
        /// Who to tell on arrival.
        boss: EntityId,
    },
    /// Coming back to a vehicle to board it.
    Board(EntityId),
    /// Hunting the high-value target.
    Hunt(EntityId),
}

/// A blue trooper or the VIP.
#[derive(Debug)]
pub struct Trooper {
    brief: Arc<Brief>,
    walk: Walk,
    /// What it is doing.
    pub task: Task,
    goal: Option<NodeId>,
    under_way: bool,
    reporter: Reporter,
    /// The hunt it leads, if it leads one.
    pub hunt: Option<Hunt>,
    hunters: Vec<EntityId>,
    last_order: Option<Order>,
    clock: TurnClock,
    /// The last report sent (to whom, what): repeated if the same order comes again.
    report: Option<(EntityId, &'static str)>,
}

impl Trooper {
    /// A trooper (or the VIP) of `brief` walking at `walk`'s level.
    pub fn new(brief: Arc<Brief>, walk: Walk) -> Self {
        Trooper {
            brief,
            walk,
            task: Task::Idle,
            goal: None,
            under_way: false,
            reporter: Reporter::default(),
            hunt: None,
            hunters: Vec::new(),
            last_order: None,
            clock: TurnClock::default(),
            report: None,
        }
    }

    /// Walks to `node` now, or as soon as the current walk ends.
    fn walk_to(&mut self, node: NodeId, cx: &mut Context<'_, Tactical>) {
        self.goal = Some(node);
        if !self.under_way {
            self.under_way = cx.act(&self.walk, node).is_ok();
        }
    }

    fn on_order(&mut self, from: EntityId, order: &Order, cx: &mut Context<'_, Tactical>) {
        if Some(order) == self.last_order.as_ref() && self.report.is_some() {
            // A repeated order (the first answer was lost): answer again.
            if let Some((to, what)) = self.report {
                tell(cx, to, Radio::Signal(what.into(), String::new()));
            }
            return;
        }
        self.last_order = Some(order.clone());
        self.report = None;
        if matches!(self.task, Task::Hunt(_)) && !matches!(order, Order::GoTo(_)) {
            return;
        }
        match order {
            Order::GoTo(p) => {
                let Some(node) = self.brief.walk_node([p[0], p[1], 0.0]) else {
                    return;
                };
                if !matches!(self.task, Task::Hunt(_)) {
                    self.task = Task::GoTo { node, boss: from };
                }
                self.walk_to(node, cx);
            }
            Order::Follow(vehicle) => {
                self.task = Task::Board(*vehicle);
                self.try_board(cx);
            }
            Order::Pursue { target, team } => {
                self.task = Task::Hunt(*target);
                self.hunters = team.iter().copied().filter(|&id| id != cx.me()).collect();
                if team.first() == Some(&cx.me()) {
                    let hunt = Hunt::new(self.brief.clone(), *target, team.clone());
                    self.hunt = hunt;
                    cx.set_timer(SimDuration::ZERO, TURN);
                }
            }
            Order::Hold => {
                self.task = Task::Idle;
                self.goal = None;
            }
        }
    }

    fn try_board(&mut self, cx: &mut Context<'_, Tactical>) {
        let Task::Board(vehicle) = self.task else {
            return;
        };
        let reach = Board { reach: 40.0 };
        if cx.act(&reach, vehicle).is_ok() {
            self.task = Task::Idle;
            self.goal = None;
            self.report = Some((vehicle, "aboard"));
            tell(cx, vehicle, Radio::Signal("aboard".into(), String::new()));
            return;
        }
        let at = cx.sense(&TrackTarget(vehicle)).map(|p| p.pos);
        if let Some(node) = at.and_then(|p| self.brief.walk_node(p)) {
            self.walk_to(node, cx);
        }
    }

    fn on_arrived(&mut self, node: NodeId, cx: &mut Context<'_, Tactical>) {
        self.under_way = false;
        if let Some(goal) = self.goal.filter(|&g| g != node) {
            self.walk_to(goal, cx);
            return;
        }
        self.goal = None;
        match self.task.clone() {
            Task::GoTo { boss, .. } => {
                self.task = Task::Idle;
                self.report = Some((boss, "arrived"));
                tell(cx, boss, Radio::Signal("arrived".into(), String::new()));
            }
            Task::Board(_) => self.try_board(cx),
            // The lead's move is done: the next turn, no sooner than MIN_TURN after this one
            // began.
            Task::Hunt(_) if self.hunt.is_some() => self.clock.after_move(TURN, cx),
            _ => {}
        }
    }

    fn on_sense(&mut self, cx: &mut Context<'_, Tactical>) {
        let Some((me, _)) = cx.sense(&Myself) else {
            return;
        };
        match me.status {
            Status::Active => {}
            Status::Aboard(_) => {
                cx.set_timer(self.period(), SENSE);
                return;
            }
            _ => return,
        }
        let seen = cx.sense(&Vision(self.brief.sensors.ground.vision()));
        self.reporter.report(&seen, cx);
        if let Task::Hunt(target) = self.task
            && let Some(s) = seen.iter().find(|s| s.id == target)
        {
            let reach = self.brief.mission.capture_range_m;
            if s.distance <= reach && cx.act(&Capture { reach }, target).is_ok() {
                let mut told = self.team_of_hunt();
                told.push(self.brief.truck);
                for id in told {
                    tell(cx, id, Radio::Signal("captured".into(), String::new()));
                }
                self.task = Task::Idle;
            }
            if let Some(h) = self.hunt.as_mut() {
                h.observe(cx.now(), s.pos);
            }
        }
        cx.set_timer(self.period(), SENSE);
    }

    /// The other pursuers (all but me) of the hunt I am on.
    fn team_of_hunt(&self) -> Vec<EntityId> {
        self.hunters.clone()
    }

    fn period(&self) -> SimDuration {
        SimDuration::from_secs_f64(self.brief.sensors.period_s)
    }

    fn on_turn(&mut self, cx: &mut Context<'_, Tactical>) {
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
        match hunt.turn(cx) {
            HuntStep::Think(delay) => {
                cx.set_timer(delay, DECIDED);
            }
            HuntStep::Over => {}
        }
    }

    fn on_decided(&mut self, cx: &mut Context<'_, Tactical>) {
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

impl Controller for Trooper {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
            }
            Input::Event(Ev::Arrived(n)) => self.on_arrived(*n, cx),
            Input::Timer(SENSE) => self.on_sense(cx),
            Input::Timer(TURN) => self.on_turn(cx),
            Input::Timer(DECIDED) => self.on_decided(cx),
            Input::Message(env) => match &env.body {
                Radio::Order(o) => self.on_order(env.from, o, cx),
                Radio::Signal(s, _) if s == "captured" => {
                    if let Some(h) = self.hunt.as_mut() {
                        h.over = true;
                    }
                    self.task = Task::Idle;
                }
                Radio::Contact { target, pos, .. } => {
                    if let Some(h) = self.hunt.as_mut()
                        && h.target == *target
                    {
                        h.observe(cx.now(), *pos);
                    }
                }
                _ => {}
            },
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        let text = match &self.task {
            Task::Idle => return None,
            Task::GoTo { .. } => "walk to the VIP".to_string(),
            Task::Board(_) => "back to the truck".to_string(),
            Task::Hunt(_) => match &self.hunt {
                Some(h) => h.describe(),
                None => "pursue the HVT".to_string(),
            },
        };
        let path = self
            .goal
            .and_then(|g| self.brief.node_point(Mode::Walk, g))
            .into_iter()
            .collect();
        let plan = self.hunt.as_ref().map(|h| h.plan()).unwrap_or_default();
        let belief = self.hunt.as_ref().map(|h| h.belief()).unwrap_or_default();
        Some(Intention {
            text,
            plan,
            path,
            belief,
            ..Intention::default()
        })
    }
}
