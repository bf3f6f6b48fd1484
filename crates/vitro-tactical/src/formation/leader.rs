//! The squad leader: takes orders, walks the walk graph with the squad in formation, and
//! runs the leader's rule program (formation, pace, arrival).

use super::kb::{self, Signature, answers, atom, fact};
use super::motion::{Follow, Mover, xy};
use super::pattern::{Pattern, Trail, slot_point};
use super::sense::{FreeSlot, Hostiles, NearestNode, SideClearance, WalkRoute};
use super::{FormationError, FormationParams};
use crate::arena::{Ev, OwnPose, TrackTarget};
use crate::entity::route::wrap_angle;
use crate::entity::{Level, Pose};
use crate::geo::{P2, dist};
use crate::model::{Controller, Tactical};
use crate::radio::{Order, Radio};
use crate::world::Side;
use vitro::comm::{Address, Envelope, Outgoing};
use vitro::entity::EntityId;
use vitro::protocol::TimerTag;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_algo::rules::{Bindings, Interpreter, KbError, ModuleSet, Query, Term, Update};

/// The leader's modules and their update operations.
const MODULES: Signature = &[
    ("eyes", &[]),
    ("squad", &["form", "brief"]),
    ("route", &["pace", "report"]),
];
const EYES: usize = 0;
const SQUAD: usize = 1;
const ROUTE: usize = 2;

/// Timer tag of the leader's deliberation tick ("FL").
const TICK: TimerTag = TimerTag(0x464c);
/// The members are briefed again at least this often (in case a message was lost).
const REBRIEF: SimDuration = SimDuration::from_secs(10);
/// A change of the facing beyond this (radians) calls for a new briefing.
const FACING_CHANGE: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Where the leader probes the ground, metres ahead along its route.
const PROBES: [f64; 4] = [0.0, 5.0, 10.0, 15.0];

/// What the ground ahead of the leader is (see the [module docs](super)).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Ground {
    /// Walls close on both sides.
    Narrow,
    /// Walls on both sides.
    Street,
    /// Not walled in on both sides.
    Open,
}

impl Ground {
    /// The name in the leader program: `narrow`, `street`, `open`.
    pub fn name(self) -> &'static str {
        match self {
            Ground::Narrow => "narrow",
            Ground::Street => "street",
            Ground::Open => "open",
        }
    }
}

/// One logged position.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackPoint {
    /// When.
    pub t: SimTime,
    /// Who (the leader or a member).
    pub id: EntityId,
    /// Where, world metres.
    pub pos: [f64; 3],
    /// For a member: its slot then (free of forbidden zones; at the discrete level the node
    /// nearest to it), world metres.
    pub slot: Option<P2>,
}

/// A change of formation.
#[derive(Clone, Debug, PartialEq)]
pub struct Switch {
    /// When.
    pub t: SimTime,
    /// The formation before.
    pub from: Pattern,
    /// The formation after.
    pub to: Pattern,
    /// What the leader's eyes reported: `contact`, or the ground (`narrow`, `street`,
    /// `open`).
    pub reason: String,
    /// Where the leader was, world metres.
    pub at: P2,
}

/// An order carried out.
#[derive(Clone, Debug, PartialEq)]
pub struct Arrival {
    /// When `arrived` was sent.
    pub t: SimTime,
    /// Who gave the order (and was told).
    pub requester: EntityId,
    /// The ordered point, world metres.
    pub goal: P2,
    /// True if every member was at its slot; false if the leader stopped waiting.
    pub gathered: bool,
}

/// How much the squad lags: the worst member's distance to its slot.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Lag {
    None,
    Some,
    Far,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Pace {
    Normal,
    Slow,
    Halt,
}

/// An order being carried out.
#[derive(Clone, Debug)]
struct Route {
    follow: Follow,
    requester: EntityId,
    goal: P2,
}

/// Everything the leader's modules read and write.
#[derive(Debug)]
struct State {
    params: FormationParams,
    roster: Vec<EntityId>,
    pattern: Pattern,
    switched_at: Option<SimTime>,
    briefed: bool,
    briefed_at: SimTime,
    facing: Option<f64>,
    briefed_facing: Option<f64>,
    trail: Trail,
    route: Option<Route>,
    at_goal_since: Option<SimTime>,
    lag: Lag,
    lag_since: Option<SimTime>,
    gathered: bool,
    pace: Option<Pace>,
    contact: Option<(SimTime, P2)>,
    ground: Ground,
    pose: Option<Pose>,
    mover: Mover,
    next_log: SimTime,
    log: Vec<TrackPoint>,
    switches: Vec<Switch>,
    arrivals: Vec<Arrival>,
    problems: Vec<String>,
}

/// The squad leader (a [`Controller`]): see the [module docs](super) for what it does and
/// the radio protocol.
pub struct Leader {
    interp: Interpreter,
    st: State,
    started: bool,
    cycles: u64,
}

impl Leader {
    /// A leader running the rule program `program` (source text, e.g. [`LEADER_PROGRAM`])
    /// over a squad of `members` (in slot order), with `params`. Its body is placed by the
    /// caller ([`Arena::add_trooper`](crate::arena::Arena::add_trooper)); it starts
    /// deliberating at its first input (e.g. [`Ev::Start`]).
    ///
    /// # Errors
    /// [`FormationError::Program`] if the program does not parse or uses a module or
    /// operation the leader lacks (with line and column, the program named `leader.jz`);
    /// [`FormationError::Param`] for a parameter out of range.
    ///
    /// [`LEADER_PROGRAM`]: super::LEADER_PROGRAM
    pub fn new(
        program: &str,
        members: Vec<EntityId>,
        params: FormationParams,
    ) -> Result<Leader, FormationError> {
        params.validate()?;
        let interp = kb::load("leader.jz", program, MODULES)?;
        let mut roster: Vec<EntityId> = Vec::new();
        for m in members {
            if !roster.contains(&m) {
                roster.push(m);
            }
        }
        Ok(Leader {
            interp,
            st: State {
                params,
                roster,
                pattern: Pattern::File,
                switched_at: None,
                briefed: false,
                briefed_at: SimTime::ZERO,
                facing: None,
                briefed_facing: None,
                trail: Trail::new(),
                route: None,
                at_goal_since: None,
                lag: Lag::None,
                lag_since: None,
                gathered: true,
                pace: None,
                contact: None,
                ground: Ground::Open,
                pose: None,
                mover: Mover::default(),
                next_log: SimTime::ZERO,
                log: Vec::new(),
                switches: Vec::new(),
                arrivals: Vec::new(),
                problems: Vec::new(),
            },
            started: false,
            cycles: 0,
        })
    }

    /// The formation in force: `file`, `column`, `line` or `wedge`.
    pub fn formation(&self) -> &'static str {
        self.st.pattern.name()
    }
    /// The formation in force.
    pub fn pattern(&self) -> Pattern {
        self.st.pattern
    }
    /// The members, in slot order.
    pub fn roster(&self) -> &[EntityId] {
        &self.st.roster
    }
    /// The squad's positions (the leader's, then each member's with its slot), every
    /// [`FormationParams::log_every`].
    pub fn trajectory(&self) -> &[TrackPoint] {
        &self.st.log
    }
    /// The changes of formation, in order (the first one sets the formation at the start).
    pub fn switches(&self) -> &[Switch] {
        &self.st.switches
    }
    /// The orders carried out.
    pub fn arrivals(&self) -> &[Arrival] {
        &self.st.arrivals
    }
    /// What the eyes reported about the ground at the latest cycle.
    pub fn ground(&self) -> Ground {
        self.st.ground
    }
    /// True while an order is being carried out.
    pub fn under_way(&self) -> bool {
        self.st.route.is_some()
    }
    /// Deliberation cycles run.
    pub fn cycles(&self) -> u64 {
        self.cycles
    }
    /// Things that went wrong (refused commands, members dropped, failed updates), in
    /// order.
    pub fn problems(&self) -> &[String] {
        &self.st.problems
    }

    /// One deliberation cycle; false if the leader has no body (it then stops).
    fn tick(&mut self, cx: &mut Context<'_, Tactical>) -> bool {
        let Some(pose) = cx.sense(&OwnPose) else {
            self.st.problem("the leader has no body: it stops".into());
            return false;
        };
        let st = &mut self.st;
        st.pose = Some(pose);
        let now = cx.now();
        let me = xy(&pose);
        let keep = (st.roster.len() as f64 + 2.0) * st.params.spacing + 10.0;
        st.trail.record(me, keep);
        st.look_out(cx, me);
        if let Some(r) = &mut st.route {
            if pose.level != Level::Discrete {
                r.follow.advance(me);
            }
            if r.follow.done(pose.level) {
                st.at_goal_since.get_or_insert(now);
            }
        }
        let slots = st.measure(cx, &pose);
        st.ground = st.classify(cx, &pose);
        if now >= st.next_log {
            st.next_log = now + st.params.log_every;
            st.log.push(TrackPoint {
                t: now,
                id: cx.me(),
                pos: pose.pos,
                slot: None,
            });
            st.log.extend(slots);
        }
        st.pace = None;
        let seed = kb::seed(cx);
        let cycle = kb::cycle(&self.interp, &mut Bound { st, cx }, seed);
        for e in cycle.errors {
            self.st.problem(format!("leader.jz:{e}"));
        }
        self.st.drive(cx, &pose);
        self.cycles += 1;
        true
    }

    fn hear(&mut self, env: &Envelope<Radio>, cx: &mut Context<'_, Tactical>) {
        let st = &mut self.st;
        match &env.body {
            Radio::Order(Order::GoTo(p)) => st.go_to(cx, env.from, *p),
            Radio::Order(Order::Hold) => {
                st.route = None;
                st.at_goal_since = None;
                if let Some(pose) = cx.sense(&OwnPose)
                    && let Err(e) = st.mover.stop(cx, &pose)
                {
                    st.problem(e.to_string());
                }
            }
            Radio::Signal(name, arg) if name == "join" || name == "leave" => {
                let Some(id) = parse_id(arg) else {
                    st.problem(format!("{name}: {arg:?} is not an entity number"));
                    return;
                };
                if name == "join" {
                    if id != cx.me() && !st.roster.contains(&id) {
                        st.roster.push(id);
                        st.briefed = false;
                    }
                } else if let Some(i) = st.roster.iter().position(|&m| m == id) {
                    st.roster.remove(i);
                    st.briefed = false;
                    dismiss(cx, id);
                }
            }
            Radio::Contact {
                pos,
                seen_as: Side::Red,
                ..
            } => st.contact = Some((cx.now(), [pos[0], pos[1]])),
            _ => {}
        }
    }
}

/// Tells `id` it is no longer in the squad.
fn dismiss(cx: &mut Context<'_, Tactical>, id: EntityId) {
    let msg = Radio::Signal("formation".into(), "none".into());
    cx.send(Outgoing::new(Address::Agent(id), msg));
}

/// An entity number as written in `join` / `leave`: `7` or `#7`.
fn parse_id(s: &str) -> Option<EntityId> {
    let s = s.trim();
    s.strip_prefix('#').unwrap_or(s).parse().ok().map(EntityId)
}

impl State {
    fn problem(&mut self, p: String) {
        if self.problems.last() != Some(&p) {
            self.problems.push(p);
        }
    }

    fn now_waited_out(&self, now: SimTime) -> bool {
        let out = |t: Option<SimTime>| t.is_some_and(|t| now - t >= self.params.straggler_timeout);
        out(self.lag_since) || out(self.at_goal_since)
    }

    /// Plans the walk to `goal` for `requester`.
    fn go_to(&mut self, cx: &mut Context<'_, Tactical>, requester: EntityId, goal: P2) {
        let leg = cx.sense(&OwnPose).and_then(|p| {
            cx.sense(&WalkRoute {
                from: xy(&p),
                to: goal,
            })
        });
        self.at_goal_since = None;
        match leg {
            Some(leg) => {
                self.route = Some(Route {
                    follow: Follow::new(leg),
                    requester,
                    goal,
                })
            }
            None => {
                self.route = None;
                let msg = Radio::Signal("unreachable".into(), format!("{} {}", goal[0], goal[1]));
                cx.send(Outgoing::new(Address::Agent(requester), msg));
                self.problem(format!("no walk route to {goal:?}"));
            }
        }
    }

    /// Own sightings, and the end of a contact that is too old.
    fn look_out(&mut self, cx: &mut Context<'_, Tactical>, me: P2) {
        let now = cx.now();
        let seen = cx.sense(&Hostiles {
            range: self.params.sight_range,
        });
        if let Some(h) = seen.iter().min_by(|a, b| {
            let (da, db) = (
                dist(me, [a.pos[0], a.pos[1]]),
                dist(me, [b.pos[0], b.pos[1]]),
            );
            da.total_cmp(&db).then(a.id.cmp(&b.id))
        }) {
            self.contact = Some((now, [h.pos[0], h.pos[1]]));
        }
        if self
            .contact
            .is_some_and(|(t, _)| now - t > self.params.contact_hold)
        {
            self.contact = None;
        }
        self.facing = self
            .contact
            .map(|(_, p)| libm::atan2(p[1] - me[1], p[0] - me[0]));
    }

    /// Drops members without a body; measures every member's distance to its slot; returns
    /// their log entries.
    fn measure(&mut self, cx: &mut Context<'_, Tactical>, pose: &Pose) -> Vec<TrackPoint> {
        let now = cx.now();
        let me = xy(pose);
        let mut out = Vec::new();
        let mut worst: f64 = 0.0;
        let mut gone = Vec::new();
        for (i, &m) in self.roster.iter().enumerate() {
            let Some(their) = cx.sense(&TrackTarget(m)) else {
                gone.push(m);
                continue;
            };
            let (base, raw) = slot_point(
                self.pattern,
                i + 1 - gone.len(),
                self.params.spacing,
                me,
                pose.heading,
                &self.trail,
                self.briefed_facing,
            );
            let mut slot = cx.sense(&FreeSlot { base, slot: raw });
            if pose.level == Level::Discrete
                && let Some((_, at)) = cx.sense(&NearestNode(slot))
            {
                slot = at;
            }
            worst = worst.max(dist(xy(&their), slot));
            out.push(TrackPoint {
                t: now,
                id: m,
                pos: their.pos,
                slot: Some(slot),
            });
        }
        for m in gone {
            self.roster.retain(|&r| r != m);
            self.briefed = false;
            self.problem(format!("member {} has no body: dropped", m.0));
        }
        let p = &self.params;
        self.lag = if worst > p.lag_wait {
            Lag::Far
        } else if worst > p.lag_slow {
            Lag::Some
        } else {
            Lag::None
        };
        self.gathered = worst <= p.gather;
        if self.lag == Lag::None {
            self.lag_since = None;
        } else {
            self.lag_since.get_or_insert(now);
        }
        out
    }

    /// The ground ahead: probes at [`PROBES`] metres along the route (along the heading
    /// without one); a single walled probe keeps the previous reading.
    fn classify(&self, cx: &mut Context<'_, Tactical>, pose: &Pose) -> Ground {
        let me = xy(pose);
        let mut probes: Vec<(P2, f64)> = Vec::new();
        match &self.route {
            Some(r) if !r.follow.done(pose.level) => {
                let pts = &r.follow.leg.pts;
                let mut along = 0.0;
                let mut prev = me;
                let mut marks = PROBES.iter().peekable();
                for i in r.follow.next.min(pts.len())..pts.len() {
                    let q = [pts[i][0], pts[i][1]];
                    along += dist(prev, q);
                    prev = q;
                    while marks.peek().is_some_and(|&&m| m <= along) {
                        marks.next();
                        let a = pts[i.saturating_sub(1)];
                        let b = pts[(i + 1).min(pts.len() - 1)];
                        let dir = if dist([a[0], a[1]], [b[0], b[1]]) > 1e-9 {
                            libm::atan2(b[1] - a[1], b[0] - a[0])
                        } else {
                            pose.heading
                        };
                        probes.push((q, dir));
                    }
                }
            }
            _ => {
                let (s, c) = (libm::sin(pose.heading), libm::cos(pose.heading));
                probes.extend(
                    PROBES
                        .iter()
                        .map(|&d| ([me[0] + d * c, me[1] + d * s], pose.heading)),
                );
            }
        }
        if probes.is_empty() {
            probes.push((me, pose.heading));
        }
        let reach = self.params.street_reach;
        let (mut narrow, mut walled) = (0, 0);
        for (at, heading) in &probes {
            let [l, r] = cx.sense(&SideClearance {
                at: *at,
                heading: *heading,
                reach,
            });
            if l < reach && r < reach {
                walled += 1;
                if l + r <= self.params.narrow_width {
                    narrow += 1;
                }
            }
        }
        let need = probes.len().min(2);
        if narrow >= need {
            Ground::Narrow
        } else if walled >= need {
            Ground::Street
        } else if walled == 0 {
            Ground::Open
        } else {
            // One walled probe of several: not enough to call it a street, nor to leave one.
            self.ground
        }
    }

    /// Moves the leader at the pace the program chose (halts without one).
    fn drive(&mut self, cx: &mut Context<'_, Tactical>, pose: &Pose) {
        let me = xy(pose);
        let pace = self.pace.unwrap_or(Pace::Halt);
        let result = match &mut self.route {
            Some(r) if pace != Pace::Halt && !r.follow.done(pose.level) => match pose.level {
                Level::Discrete => match r.follow.next_hop() {
                    Some(n) => self.mover.hop(cx, n),
                    None => Ok(()),
                },
                _ => {
                    let factor = if pace == Pace::Slow {
                        self.params.slow_factor
                    } else {
                        1.0
                    };
                    let guess = r.follow.leg.v.get(r.follow.next).copied().unwrap_or(1.0);
                    let look = (4.0 * guess * self.params.period.as_secs_f64()).max(3.0);
                    match r.follow.target(cx, me, look) {
                        Some((to, v)) => self.mover.toward(cx, pose, to, v * factor),
                        None => {
                            self.problem("no straight way onto the route".into());
                            self.mover.stop(cx, pose)
                        }
                    }
                }
            },
            _ => self.mover.stop(cx, pose),
        };
        if let Err(e) = result {
            self.problem(e.to_string());
        }
    }

    /// Tells each member its pattern, slot, the spacing and the facing.
    fn brief(&mut self, cx: &mut Context<'_, Tactical>) {
        let facing = self
            .facing
            .map_or_else(|| "-".to_string(), |f| format!("{f:.4}"));
        for (i, &m) in self.roster.iter().enumerate() {
            let text = format!(
                "{} {} {} {facing}",
                self.pattern.name(),
                i + 1,
                self.params.spacing
            );
            let msg = Radio::Signal("formation".into(), text);
            cx.send(Outgoing::new(Address::Agent(m), msg));
        }
        self.briefed = true;
        self.briefed_at = cx.now();
        self.briefed_facing = self.facing;
    }

    fn unbriefed(&self, now: SimTime) -> bool {
        let turned = match (self.facing, self.briefed_facing) {
            (None, None) => false,
            (Some(a), Some(b)) => wrap_angle(a - b).abs() > FACING_CHANGE,
            _ => true,
        };
        !self.briefed || turned || now - self.briefed_at >= REBRIEF
    }
}

/// The leader's modules bound to its state and context for one cycle.
struct Bound<'a, 'c> {
    st: &'a mut State,
    cx: &'a mut Context<'c, Tactical>,
}

impl ModuleSet for Bound<'_, '_> {
    fn find(&self, name: &str) -> Option<usize> {
        kb::index(MODULES, name)
    }

    fn supports(&self, module: usize, op: &str) -> bool {
        MODULES
            .get(module)
            .is_some_and(|(_, ops)| ops.contains(&op))
    }

    fn query(&mut self, module: usize, q: &Query) -> Vec<Bindings> {
        let st = &*self.st;
        let now = self.cx.now();
        let mut facts = Vec::new();
        match module {
            EYES => {
                if st.contact.is_some() {
                    facts.push(Term::atom("contact"));
                }
                facts.push(fact("ground", Term::atom(st.ground.name())));
            }
            SQUAD => {
                facts.push(fact("formation", Term::atom(st.pattern.name())));
                if st.switched_at.is_none_or(|t| now - t >= st.params.settle) {
                    facts.push(Term::atom("settled"));
                }
                let lag = match st.lag {
                    Lag::None => "none",
                    Lag::Some => "some",
                    Lag::Far => "far",
                };
                facts.push(fact("lag", Term::atom(lag)));
                if st.now_waited_out(now) {
                    facts.push(Term::atom("waited_out"));
                }
                if st.gathered {
                    facts.push(Term::atom("gathered"));
                }
                if st.unbriefed(now) {
                    facts.push(Term::atom("unbriefed"));
                }
            }
            ROUTE => {
                let level = st.pose.map_or(Level::Directed, |p| p.level);
                facts.push(Term::atom(match &st.route {
                    None => "idle",
                    Some(r) if r.follow.done(level) => "at_goal",
                    Some(_) => "under_way",
                }));
            }
            _ => {}
        }
        answers(q, facts)
    }

    fn update(&mut self, module: usize, u: &Update) -> Result<(), KbError> {
        let st = &mut *self.st;
        let cx = &mut *self.cx;
        match (module, u.op.as_str()) {
            (SQUAD, "form") => {
                let name = atom(u)?;
                let to = Pattern::from_name(name)
                    .ok_or_else(|| KbError::Refused(format!("no formation {name}")))?;
                let reason = if st.contact.is_some() {
                    "contact"
                } else {
                    st.ground.name()
                };
                st.switches.push(Switch {
                    t: cx.now(),
                    from: st.pattern,
                    to,
                    reason: reason.into(),
                    at: st.pose.as_ref().map_or([0.0; 2], xy),
                });
                st.pattern = to;
                st.switched_at = Some(cx.now());
                st.briefed = false;
                Ok(())
            }
            (SQUAD, "brief") => {
                st.brief(cx);
                Ok(())
            }
            (ROUTE, "pace") => {
                st.pace = Some(match atom(u)? {
                    "normal" => Pace::Normal,
                    "slow" => Pace::Slow,
                    "halt" => Pace::Halt,
                    other => return Err(KbError::Refused(format!("no pace {other}"))),
                });
                Ok(())
            }
            (ROUTE, "report") => {
                let Some(r) = st.route.take() else {
                    return Err(KbError::Refused("no order to report on".into()));
                };
                let msg = Radio::Signal(atom(u)?.to_string(), String::new());
                cx.send(Outgoing::new(Address::Agent(r.requester), msg));
                st.arrivals.push(Arrival {
                    t: cx.now(),
                    requester: r.requester,
                    goal: r.goal,
                    gathered: st.gathered,
                });
                st.at_goal_since = None;
                Ok(())
            }
            (_, op) => Err(KbError::UnknownOperation(op.into())),
        }
    }
}

impl Controller for Leader {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Timer(key) if TICK.index(key).is_some() => {
                if self.tick(cx) {
                    cx.set_timer(self.st.params.period, TICK.key(0));
                }
                return;
            }
            Input::Event(Ev::Arrived(n)) => {
                self.st.mover.arrived();
                if let Some(r) = &mut self.st.route {
                    r.follow.hopped(*n);
                }
            }
            Input::Message(env) => self.hear(env, cx),
            _ => {}
        }
        if !self.started {
            self.started = true;
            if self.tick(cx) {
                cx.set_timer(self.st.params.period, TICK.key(0));
            }
        }
    }
}
