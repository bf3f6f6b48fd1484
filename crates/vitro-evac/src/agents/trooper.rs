//! Blue troopers and the VIP on foot: they walk in formation where the commander orders
//! (see the [squad module](super::squad)), come back on board, report hostile contacts,
//! and — when sent after the high-value target — hunt it as a team (the first pursuer runs
//! the search, see [`hunt`](super::hunt)).

use super::hunt::{Hunt, TurnClock};
use super::squad::{self, Part, Squad, note};
use super::tender::{CNET, cnet_config};
use super::{Reporter, SENSE, last_known, note_friends, tell};
use crate::act::{ActError, Board, Capture, Walk};
use crate::brief::{BLUE, Brief};
use crate::radio::{Evac, Order, Radio};
use crate::sense::{Myself, Vision};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::comm::Envelope;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::protocol::{ContractNet, Handled, Reply};
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_behaviour::belief::{Beacon, Whereabouts};
use vitro_behaviour::formation::{Leader, Member};
use vitro_site::map::Mode;
use vitro_tactical::actuate::troop::directed::MoveAndTurn;
use vitro_tactical::arena::Ev;
use vitro_tactical::condition::Status;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::troop::StepCmd;
use vitro_tactical::model::{Controller, Intention};

mod bidding;
mod hunting;

pub use bidding::LEAD_COST_M;

/// Timer key of the hunt's turns.
pub(crate) const TURN: u64 = 20;
/// Timer key: the hunt's search is done (its simulated thinking time has passed).
pub(crate) const DECIDED: u64 = 21;

/// What a trooper is doing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Serialize, Deserialize)]
pub struct Trooper {
    #[serde(with = "vitro_mission::snapshot::briefed")]
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
    /// The lead of the hunt it is on (maybe itself), and when it last heard from it.
    lead: Option<(EntityId, SimTime)>,
    last_order: Option<Order>,
    clock: TurnClock,
    /// The last report sent (to whom, what): repeated if the same order comes again.
    #[serde(with = "report_word")]
    report: Option<(EntityId, &'static str)>,
    /// Its part in the squad walking in formation, if it is in one.
    squad: Option<Squad>,
    /// The timer index of the latest formation controller it embedded.
    ticks: u64,
    /// True once a formation controller has steered its body at the directed level: the
    /// walk actuator's idea of its last node is then stale, and it walks on its own as a
    /// squad of one.
    steered: bool,
    /// Its own id, known from its first input.
    me: Option<EntityId>,
    /// Where it believes the others are (their reports, its own eyes).
    known: Whereabouts,
    beacon: Beacon,
    /// The contract net (it bids for hunt slots).
    cnet: ContractNet<Radio>,
    /// Its hunt contract, if it won a slot: where to report.
    pub contract: Option<Reply>,
}

impl Trooper {
    /// A trooper (or the VIP) of `brief` walking at `walk`'s level.
    pub fn new(brief: Arc<Brief>, walk: Walk) -> Self {
        Trooper {
            known: super::whereabouts(&brief),
            beacon: super::beacon(&brief),
            brief,
            walk,
            task: Task::Idle,
            goal: None,
            under_way: false,
            reporter: Reporter::default(),
            hunt: None,
            hunters: Vec::new(),
            lead: None,
            last_order: None,
            clock: TurnClock::default(),
            report: None,
            squad: None,
            ticks: 0,
            steered: false,
            me: None,
            cnet: ContractNet::new(CNET, cnet_config()),
            contract: None,
        }
    }

    /// Where it believes the others are: their position reports and its own eyes' fixes.
    pub fn known(&self) -> &Whereabouts {
        &self.known
    }

    /// The formation leader it embeds while it leads a squad (or walks as a squad of one).
    pub fn leader(&self) -> Option<&Leader> {
        match &self.squad.as_ref()?.part {
            Part::Lead { leader, .. } => Some(leader),
            Part::Follow(_) => None,
        }
    }

    /// The formation member it embeds while it follows a squad leader.
    pub fn member(&self) -> Option<&Member> {
        match &self.squad.as_ref()?.part {
            Part::Follow(m) => Some(m),
            Part::Lead { .. } => None,
        }
    }

    /// Takes the part `make` gives in a squad, with a fresh timer index (false if none).
    fn join_squad(&mut self, make: impl FnOnce(&Brief, u64) -> Option<Squad>) -> bool {
        self.ticks += 1;
        let Some(squad) = make(&self.brief, self.ticks) else {
            return false;
        };
        self.squad = Some(squad);
        self.task = Task::Idle;
        self.goal = None;
        if self.walk.0 != Level::Discrete {
            self.steered = true;
        }
        true
    }

    /// Leaves its squad, if it is in one, and stops where it stands (a hop under way at the
    /// discrete level ends at its node). With `announce`, a member tells its leader it leaves
    /// and a leader dismisses its members (they stand still until the truck names another
    /// leader), so that nobody follows it away.
    fn leave_squad(&mut self, announce: bool, cx: &mut Context<'_, Evac>) {
        let Some(squad) = self.squad.take() else {
            return;
        };
        if announce {
            let me = cx.me().0.to_string();
            match &squad.part {
                Part::Follow(m) => tell(cx, m.leader(), Radio::Signal("leave".into(), me)),
                Part::Lead { leader, .. } => {
                    for &m in leader.roster() {
                        let none = Radio::Signal("formation".into(), "none".into());
                        tell(cx, m, none);
                    }
                }
            }
        }
        if self.steered
            && let Some((_, Some(pose))) = cx.sense(&Myself)
        {
            let stop = StepCmd {
                toward: pose.pos,
                speed: 0.0,
            };
            let _ = cx.act(&MoveAndTurn, stop);
        }
    }

    /// Leads the squad to `to` (the truck's `GoTo`): becomes the leader if it was not (a
    /// member promoted), and hands the order to its formation leader unless it is the one
    /// under way.
    fn lead(&mut self, env: &Envelope<Radio>, to: [f64; 2], cx: &mut Context<'_, Evac>) {
        let leading = matches!(&self.squad, Some(s) if matches!(s.part, Part::Lead { .. }));
        if !leading {
            self.leave_squad(false, cx);
            if !self.join_squad(Squad::lead) {
                // The program did not load (it was checked at setup): walk alone.
                if let Some(node) = self.brief.walk_node([to[0], to[1], 0.0]) {
                    self.task = Task::GoTo {
                        node,
                        boss: env.from,
                    };
                    self.walk_to(node, cx);
                }
                return;
            }
        }
        let Some(squad) = self.squad.as_mut() else {
            return;
        };
        let under_way = squad.under_way();
        if let Part::Lead { goal, .. } = &mut squad.part {
            if *goal == Some(to) && under_way {
                return;
            }
            *goal = Some(to);
        }
        squad.forward(Input::Message(env), cx);
    }

    /// Follows `leader` in formation (the truck's `Follow` of a person): becomes its member
    /// if it was not, and tells it `join` (every time, in case a `join` was lost).
    fn follow(&mut self, env: &Envelope<Radio>, leader: EntityId, cx: &mut Context<'_, Evac>) {
        if leader == cx.me() {
            return;
        }
        let following = self.squad.as_ref().and_then(Squad::leader) == Some(leader);
        if !following {
            self.leave_squad(true, cx);
            self.join_squad(|b, i| Some(Squad::follow(b, leader, i)));
            // Its first input starts the member's deliberation.
            if let Some(s) = self.squad.as_mut() {
                s.forward(Input::Message(env), cx);
            }
        }
        let me = cx.me().0.to_string();
        tell(cx, leader, Radio::Signal("join".into(), me));
    }

    /// Walks to `node` now, or as soon as the current walk ends.
    fn walk_to(&mut self, node: NodeId, cx: &mut Context<'_, Evac>) {
        self.goal = Some(node);
        if !self.under_way {
            self.under_way = cx.act(&self.walk, node).is_ok();
        }
    }

    fn on_order(
        &mut self,
        env: &Envelope<Radio>,
        order: &Order,
        on_foot: bool,
        cx: &mut Context<'_, Evac>,
    ) {
        let from = env.from;
        // Any order from the hunt lead shows it is up (repeats included).
        if let Some((lead, heard)) = self.lead.as_mut()
            && *lead == from
        {
            *heard = cx.now();
        }
        if Some(order) == self.last_order.as_ref() && self.report.is_some() {
            // A repeated order (the first answer was lost): answer again.
            if let Some((to, what)) = self.report {
                tell(cx, to, Radio::Signal(what.into(), String::new()));
            }
            return;
        }
        self.last_order = Some(order.clone());
        self.report = None;
        // A hunter takes only its moves and new rosters of its hunt.
        if matches!(self.task, Task::Hunt(_))
            && !matches!(order, Order::GoTo(_) | Order::Pursue { .. })
        {
            return;
        }
        let hunting = matches!(self.task, Task::Hunt(_));
        let b = &self.brief;
        match order {
            // Squad orders, for troopers on foot.
            Order::GoTo(p) if from == b.truck && !hunting => {
                if on_foot {
                    self.lead(env, *p, cx);
                }
            }
            Order::Follow(who) if b.team.contains(who) || *who == b.vip => {
                if on_foot {
                    self.follow(env, *who, cx);
                }
            }
            Order::Hold if self.squad.as_ref().is_some_and(|s| s.leader().is_none()) => {
                if let Some(s) = self.squad.as_mut() {
                    s.forward(Input::Message(env), cx);
                }
            }
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
                // Told again while on its way (a squad of one then): it walks on.
                if self.task != Task::Board(*vehicle) {
                    self.leave_squad(false, cx);
                    self.task = Task::Board(*vehicle);
                }
                self.try_board(cx);
            }
            Order::Pursue { target, team } if !team.contains(&cx.me()) => self.leave_hunt(*target),
            Order::Pursue { target, team } => {
                // A new roster of the hunt it is on (pursuers joined, or one fell): the
                // lead keeps its belief; a new lead starts the turns.
                let same_hunt = self.task == Task::Hunt(*target);
                if !same_hunt {
                    self.leave_squad(true, cx);
                    self.task = Task::Hunt(*target);
                    self.hunt = None;
                }
                self.hunters = team.iter().copied().filter(|&id| id != cx.me()).collect();
                let lead = team.first().copied();
                if self.lead.map(|(l, _)| l) != lead {
                    self.lead = lead.map(|l| (l, cx.now()));
                }
                if team.first() != Some(&cx.me()) {
                    self.hunt = None;
                } else if let Some(hunt) = self.hunt.as_mut() {
                    hunt.set_team(team.clone());
                } else {
                    self.hunt = Hunt::new(self.brief.clone(), *target, team.clone());
                    self.clock.next_in(SimDuration::ZERO, TURN, cx);
                }
            }
            Order::Hold => {
                self.task = Task::Idle;
                self.goal = None;
            }
        }
    }

    /// Boards the vehicle it was told to follow if it can; else walks to it, unless it is
    /// already walking or its body is still settling (it tries again at its next look).
    fn try_board(&mut self, cx: &mut Context<'_, Evac>) {
        let Task::Board(vehicle) = self.task else {
            return;
        };
        let reach = Board { reach: 40.0 };
        let boarded = match cx.act(&reach, vehicle) {
            Ok(()) => true,
            // Already on board (it never got off): it says so.
            Err(ActError::NotActive(_)) => status(cx) == Some(Status::Aboard(vehicle)),
            Err(ActError::Moving(_)) => return,
            Err(_) => false,
        };
        if boarded {
            self.squad = None;
            self.task = Task::Idle;
            self.goal = None;
            self.report = Some((vehicle, "aboard"));
            tell(cx, vehicle, Radio::Signal("aboard".into(), String::new()));
            return;
        }
        if status(cx) != Some(Status::Active) {
            return;
        }
        if self.under_way || self.squad.is_some() {
            return;
        }
        // Where the vehicle's reports (or its own eyes) put it; none yet: it waits.
        let Some(at) = last_known(&self.known, vehicle, cx.now()) else {
            return;
        };
        let Some(node) = self.brief.walk_node(at) else {
            return;
        };
        if self.steered {
            // Its body was steered off the walk actuator's bookkeeping: it walks there as
            // a squad of one (the leader's answer comes back to itself).
            let Some(p) = self.brief.node_point(Mode::Walk, node) else {
                return;
            };
            if self.join_squad(Squad::lead) {
                self.task = Task::Board(vehicle);
                let order = note(cx, Radio::Order(Order::GoTo([p[0], p[1]])));
                if let Some(s) = self.squad.as_mut() {
                    s.forward(Input::Message(&order), cx);
                }
            }
        } else {
            self.walk_to(node, cx);
        }
    }

    fn on_arrived(&mut self, node: NodeId, cx: &mut Context<'_, Evac>) {
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
            // At the vehicle's node: boards, or tries again at its next look (never walks
            // again at once, which at the same instant could go on for ever).
            Task::Board(_) => {
                self.under_way = true;
                self.try_board(cx);
                self.under_way = false;
            }
            // The lead's move is done: the next turn, no sooner than MIN_TURN after this one
            // began.
            Task::Hunt(_) if self.hunt.is_some() => self.clock.after_move(TURN, cx),
            _ => {}
        }
    }

    fn on_message(&mut self, env: &Envelope<Radio>, cx: &mut Context<'_, Evac>) {
        self.known.hear(env);
        let status = status(cx);
        let on_foot = status == Some(Status::Active);
        if matches!(status, Some(Status::Down | Status::Captured)) {
            return;
        }
        match &env.body {
            Radio::Order(o) => self.on_order(env, o, on_foot, cx),
            Radio::Signal(s, _) if s == "captured" => {
                if let Some(h) = self.hunt.as_mut() {
                    h.over = true;
                }
                self.task = Task::Idle;
                self.report_capture(cx);
            }
            Radio::Signal(s, _)
                if s == "join"
                    && on_foot
                    && self.squad.is_none()
                    && matches!(self.task, Task::Idle | Task::GoTo { .. }) =>
            {
                // Someone follows it before its own order came: it leads.
                self.join_squad(Squad::lead);
            }
            Radio::Signal(s, roster) if s == "squad" && env.from == self.brief.truck => {
                if let Some(squad) = self.squad.as_mut() {
                    squad.keep_only(roster, cx);
                }
            }
            Radio::Contact { target, pos, .. } => {
                if let Some(h) = self.hunt.as_mut()
                    && h.target == *target
                {
                    h.observe(cx.now(), *pos);
                }
            }
            _ => {}
        }
        if let Some(s) = self.squad.as_mut() {
            s.hear(env, cx);
        }
    }

    fn on_sense(&mut self, cx: &mut Context<'_, Evac>) {
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
        note_friends(&mut self.known, &seen, cx.now());
        self.reporter.report(&seen, cx);
        if let Some(s) = self.squad.as_mut() {
            s.watch(&self.brief, cx);
        }
        self.check_lead(cx);
        if matches!(self.task, Task::Board(_)) {
            self.try_board(cx);
        }
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
                self.report_capture(cx);
            }
            if let Some(h) = self.hunt.as_mut() {
                h.observe(cx.now(), s.pos);
            }
        }
        cx.set_timer(self.period(), SENSE);
    }
}

impl Controller<Evac> for Trooper {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        self.me = Some(cx.me());
        match self.cnet.handle(input, cx) {
            Handled::Event(e) => return self.on_cnet(e, cx),
            Handled::Consumed => return,
            Handled::NotMine => {}
        }
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                self.beacon.start(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
            }
            Input::Timer(Beacon::TIMER) => self.beacon.tick(cx),
            Input::Event(Ev::Arrived(n)) => match self.squad.as_mut() {
                // The end of a hop of the formation's (or of one begun before it).
                Some(s) => {
                    self.under_way = false;
                    s.forward(input, cx);
                }
                None => self.on_arrived(*n, cx),
            },
            Input::Timer(SENSE) => self.on_sense(cx),
            Input::Timer(TURN) => self.on_turn(cx),
            Input::Timer(DECIDED) => self.on_decided(cx),
            Input::Timer(key) if squad::is_tick(key) => {
                if status(cx) != Some(Status::Active) {
                    // Down (or aboard): the formation has no body to steer.
                    self.squad = None;
                } else if let Some(s) = self.squad.as_mut() {
                    s.forward(input, cx);
                }
            }
            Input::Message(env) => self.on_message(env, cx),
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        if let Some(s) = &self.squad {
            let what = if matches!(self.task, Task::Board(_)) {
                "back to the truck"
            } else if self.me == Some(self.brief.vip) {
                "escorted"
            } else {
                "escort"
            };
            return Some(s.intention(&self.brief, what));
        }
        let text = match &self.task {
            Task::Idle => return None,
            Task::GoTo { .. } => "walk to the ordered point".to_string(),
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

/// The acting entity's own status, if it has a condition.
fn status(cx: &mut Context<'_, Evac>) -> Option<Status> {
    cx.sense(&Myself).map(|(c, _)| c.status)
}

/// Serde for the last report (`Option<(EntityId, &'static str)>`): the text is read back as
/// one of the words a trooper reports.
mod report_word {
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use vitro::entity::EntityId;
    /// The words a trooper reports.
    const WORDS: [&str; 2] = ["aboard", "arrived"];
    /// Writes the pair.
    pub(super) fn serialize<S: Serializer>(
        v: &Option<(EntityId, &'static str)>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        v.serialize(s)
    }
    /// Reads the pair; a word a trooper does not report is an error.
    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<(EntityId, &'static str)>, D::Error> {
        let v: Option<(EntityId, String)> = Deserialize::deserialize(d)?;
        v.map(|(id, w)| {
            WORDS
                .iter()
                .find(|x| **x == w)
                .map(|x| (id, *x))
                .ok_or_else(|| D::Error::custom(format!("unknown word {w:?}")))
        })
        .transpose()
    }
}
