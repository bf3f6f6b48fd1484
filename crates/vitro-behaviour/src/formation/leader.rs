//! The squad leader: takes orders, walks the walk graph with the squad in formation, and
//! runs the leader's rule program (formation, pace, arrival).

use super::ground::{self, Ground};
use super::kb::{self};
use super::motion::{Mover, xy};
use super::pattern::{Pattern, Trail, slot_point};
use super::record::{Arrival, Switch, TrackPoint};
use super::sense::{FreeSlot, Gait, Hostiles, NearestNode};
use super::{FormationError, FormationParams, LINK_STALE, at_level};
use crate::belief::{Fix, Whereabouts};
use serde::{Deserialize, Serialize};
use vitro::comm::{Address, Envelope, Outgoing};
use vitro::entity::EntityId;
use vitro::protocol::TimerTag;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_algo::rules::Interpreter;
use vitro_site::geo::{P2, dist};
use vitro_tactical::arena::{Ev, OwnPose};
use vitro_tactical::entity::route::wrap_angle;
use vitro_tactical::entity::{Level, Pose};
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::radio::{Command, Contact, Signal, SquadTalk};
use vitro_tactical::world::Side;

mod modules;
mod orders;
mod state;
use modules::Bound;
use orders::{dismiss, parse_id};
use state::{Lag, MODULES, Pace, State};

/// Timer tag of the leader's deliberation tick ("FL").
const TICK: TimerTag = TimerTag(0x464c);
/// The members are briefed again at least this often (in case a message was lost).
const REBRIEF: SimDuration = SimDuration::from_secs(10);
/// A change of the facing beyond this (radians) calls for a new briefing.
const FACING_CHANGE: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// How often the leader looks at the ground.
const LOOK_EVERY: SimDuration = SimDuration::from_secs(1);

/// The squad leader (a [`Controller`]): see the [module docs](super) for what it does and
/// the radio protocol.
#[derive(Serialize, Deserialize)]
pub struct Leader {
    interp: Interpreter,
    st: State,
    started: bool,
    cycles: u64,
    tick_index: u64,
}

impl Leader {
    /// A leader running the rule program `program` (source text, e.g. [`LEADER_PROGRAM`])
    /// over a squad of `members` (in slot order), with `params`. Its body is placed by the
    /// caller ([`Arena::add_trooper`](vitro_tactical::arena::Arena::add_trooper)); it starts
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
        Leader::named("leader.jz", program, members, params)
    }

    /// [`Leader::new`] with the program named `name` in its errors (its file, when it was
    /// read from one).
    ///
    /// # Errors
    /// As [`Leader::new`].
    pub fn named(
        name: &str,
        program: &str,
        members: Vec<EntityId>,
        params: FormationParams,
    ) -> Result<Leader, FormationError> {
        params.validate()?;
        let interp = kb::load(name, program, MODULES)?;
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
                held: None,
                at_goal_since: None,
                lag: Lag::None,
                lag_since: None,
                worst: 0.0,
                walk: 1.0,
                nodes: Vec::new(),
                gathered: true,
                pace: None,
                contact: None,
                ground: Ground::Open,
                next_look: SimTime::ZERO,
                pose: None,
                mover: Mover::default(),
                next_log: SimTime::ZERO,
                log: Vec::new(),
                switches: Vec::new(),
                arrivals: Vec::new(),
                problems: Vec::new(),
                known: Whereabouts::new(LINK_STALE),
                joined: Default::default(),
                sent: None,
            },
            started: false,
            cycles: 0,
            tick_index: 0,
        })
    }

    /// Checks a leader program without building a leader: it parses, and uses only modules
    /// and operations the leader has. Errors name the program `name`, with line and column.
    ///
    /// ```
    /// use vitro_behaviour::formation::{LEADER_PROGRAM, Leader};
    ///
    /// assert!(Leader::check_program("leader.jz", LEADER_PROGRAM).is_ok());
    /// let e = Leader::check_program("mine.jz", "when { then").unwrap_err();
    /// assert_eq!((e.file.as_str(), e.pos.line), ("mine.jz", 1));
    /// ```
    ///
    /// # Errors
    /// The program's first error ([`vitro_algo::rules::RuleError`]).
    pub fn check_program(name: &str, program: &str) -> Result<(), vitro_algo::rules::RuleError> {
        kb::load(name, program, MODULES).map(|_| ())
    }

    /// The same leader, deliberating on timer `TimerTag(0x464c).key(index)` (default 0) and
    /// ignoring that tag's other keys: an agent that replaces its formation controller gives
    /// the new one another index, so that a tick the old one left pending is not taken for
    /// the new one's.
    pub fn with_timer_index(mut self, index: u64) -> Self {
        self.tick_index = index;
        self
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
    /// The rest of the route under way (world points, from the next one to reach, at the
    /// discrete level from the next node; the goal alone once there), empty without an
    /// order.
    pub fn route_ahead(&self) -> Vec<[f64; 3]> {
        let Some(r) = &self.st.route else {
            return Vec::new();
        };
        let f = &r.follow;
        let from = match self.st.pose.map(|p| p.level) {
            Some(Level::Discrete) => f
                .leg
                .nodes
                .get(f.next_node)
                .map_or(f.leg.pts.len(), |&(i, _)| i),
            _ => f.next,
        };
        let from = from.min(f.leg.pts.len().saturating_sub(1));
        f.leg.pts.get(from..).map(<[_]>::to_vec).unwrap_or_default()
    }
    /// Things that went wrong (refused commands, members dropped, failed updates), in
    /// order.
    pub fn problems(&self) -> &[String] {
        &self.st.problems
    }

    /// One deliberation cycle; false if the leader has no body (it then stops).
    fn tick<M: SquadTalk>(&mut self, cx: &mut Context<'_, Tactical<M>>) -> bool {
        let Some(pose) = cx.sense(&OwnPose) else {
            self.st.problem("the leader has no body: it stops".into());
            return false;
        };
        let st = &mut self.st;
        st.pose = Some(pose);
        let me_id = cx.me();
        st.roster.retain(|&m| m != me_id);
        let now = cx.now();
        let me = xy(&pose);
        let keep = (st.roster.len() as f64 + 2.0) * st.params.spacing + 10.0;
        st.trail.record(me, keep);
        st.look_out(cx, me);
        st.walk = cx.sense(&Gait).unwrap_or(st.walk);
        let slots = st.measure(cx, &pose);
        let allowance = st.allowance(pose.level);
        if let Some(r) = &mut st.route {
            if pose.level != Level::Discrete {
                r.follow.advance(me);
            }
            if r.follow.done(pose.level) {
                st.at_goal_since.get_or_insert((now, allowance));
            }
        }
        if now >= st.next_look {
            st.next_look = now + LOOK_EVERY;
            st.ground = st.classify(cx, &pose);
        }
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
        // The formation link: its own fix to every member, as it moves on (after this
        // cycle's command: a hop just begun already has its speed and heading).
        let now_pose = cx.sense(&OwnPose).unwrap_or(pose);
        let fix = Fix::after(&now_pose, now, self.st.sent.as_ref());
        self.st.sent = Some(fix);
        for &m in &self.st.roster {
            cx.send(Outgoing::new(Address::Agent(m), M::from(fix)));
        }
        self.cycles += 1;
        true
    }

    fn hear<M: SquadTalk>(&mut self, env: &Envelope<M>, cx: &mut Context<'_, Tactical<M>>) {
        let st = &mut self.st;
        st.known.hear(env);
        if let Some(order) = env.body.read::<Command>() {
            match order {
                Command::GoTo(p) => st.go_to(cx, env.from, p),
                Command::Hold => {
                    st.held = st.route.take().map(|r| r.follow);
                    st.at_goal_since = None;
                    if let Some(pose) = cx.sense(&OwnPose)
                        && let Err(e) = st.mover.stop(cx, &pose)
                    {
                        st.problem(e.to_string());
                    }
                }
                Command::Follow(_) => {}
            }
        } else if let Some(Signal { name, arg }) = env.body.read::<Signal>() {
            if name != "join" && name != "leave" {
                return;
            }
            let Some(id) = parse_id(&arg) else {
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
        } else if let Some(Contact {
            pos,
            seen_as: Side::Red,
            ..
        }) = env.body.read::<Contact>()
        {
            st.contact = Some((cx.now(), [pos[0], pos[1]]));
        }
    }
}

impl State {
    fn problem(&mut self, p: String) {
        if self.problems.last() != Some(&p) {
            self.problems.push(p);
        }
    }

    fn now_waited_out(&self, now: SimTime) -> bool {
        let out = |t: Option<(SimTime, SimDuration)>| t.is_some_and(|(t, d)| now - t >= d);
        out(self.lag_since) || out(self.at_goal_since)
    }

    /// How long the leader may wait for the squad, from now: the straggler timeout, plus at
    /// the discrete level the time to walk the worst member's gap (a member there covers a
    /// whole edge before it is any nearer, and edges can take minutes).
    fn allowance(&self, level: Level) -> SimDuration {
        let mut d = self.params.straggler_timeout;
        if level == Level::Discrete {
            d += SimDuration::from_secs_f64(self.worst / self.walk.max(0.1));
        }
        d
    }

    /// Own sightings, and the end of a contact that is too old.
    fn look_out<M: SquadTalk>(&mut self, cx: &mut Context<'_, Tactical<M>>, me: P2) {
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

    /// Drops members not heard from for [`LINK_STALE`]; measures every member's distance to
    /// its slot, where its last report puts it; returns their log entries.
    fn measure<M: SquadTalk>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        pose: &Pose,
    ) -> Vec<TrackPoint> {
        let now = cx.now();
        let me = xy(pose);
        let mut out = Vec::new();
        let mut worst: f64 = 0.0;
        let mut gone = Vec::new();
        for (i, &m) in self.roster.iter().enumerate() {
            let since = *self.joined.entry(m).or_insert(now);
            let Some(their) = self
                .known
                .fresh(m, now)
                .map(|f| f.pose(at_level(f, now, pose.level), pose.level))
            else {
                let silent = self.known.last(m).map_or(since, |f| f.at.max(since));
                if now.saturating_since(silent) > LINK_STALE {
                    gone.push(m);
                }
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
            if pose.level == Level::Discrete {
                // The node nearest the slot (looked up again only when the slot moved).
                let known = self.nodes.get(i).copied().flatten();
                slot = match known {
                    Some((s, at)) if dist(s, slot) < 0.5 => at,
                    _ => {
                        let at = cx.sense(&NearestNode(slot)).map_or(slot, |(_, at)| at);
                        if self.nodes.len() <= i {
                            self.nodes.resize(i + 1, None);
                        }
                        self.nodes[i] = Some((slot, at));
                        at
                    }
                };
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
            self.joined.remove(&m);
            self.known.forget(m);
            self.problem(format!("member {} silent: dropped", m.0));
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
        self.worst = worst;
        if self.lag == Lag::None {
            self.lag_since = None;
        } else if self.lag_since.is_none() {
            self.lag_since = Some((now, self.allowance(pose.level)));
        }
        out
    }

    /// The ground ahead: probes along the route (along the heading without one).
    fn classify<M: SquadTalk>(&self, cx: &mut Context<'_, Tactical<M>>, pose: &Pose) -> Ground {
        let me = xy(pose);
        let probes = match &self.route {
            Some(r) if !r.follow.done(pose.level) => {
                ground::along(&r.follow.leg.pts, r.follow.next, me, pose.heading)
            }
            _ => ground::ahead(me, pose.heading),
        };
        ground::look(cx, &probes, &self.params, self.ground)
    }

    /// Moves the leader at the pace the program chose (halts without one).
    fn drive<M: SquadTalk>(&mut self, cx: &mut Context<'_, Tactical<M>>, pose: &Pose) {
        let me = xy(pose);
        let pace = self.pace.unwrap_or(Pace::Halt);
        let mut off_route = false;
        let result = match &mut self.route {
            Some(r) if pace != Pace::Halt && !r.follow.done(pose.level) => match pose.level {
                Level::Discrete => match r.follow.next_hop() {
                    Some(n) => self.mover.paced_hop(cx, n, pace == Pace::Slow),
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
                            // The route itself is free (the free walk graph); on to its
                            // next point, whatever the probes say.
                            off_route = true;
                            match r.follow.next_point() {
                                Some((to, v)) => self.mover.toward(cx, pose, to, v * factor),
                                None => self.mover.stop(cx, pose),
                            }
                        }
                    }
                }
            },
            _ => self.mover.stop(cx, pose),
        };
        if off_route {
            self.problem("no straight way onto the route".into());
        }
        if let Err(e) = result {
            self.problem(e.to_string());
        }
    }

    /// Tells each member its pattern, slot, the spacing and the facing.
    fn brief<M: SquadTalk>(&mut self, cx: &mut Context<'_, Tactical<M>>) {
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
            let msg = M::from(Signal::new("formation", text));
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

impl<M: SquadTalk> Controller<Tactical<M>> for Leader {
    fn handle(&mut self, input: Input<'_, Tactical<M>>, cx: &mut Context<'_, Tactical<M>>) {
        match input {
            Input::Timer(key) if TICK.index(key).is_some() => {
                if TICK.index(key) == Some(self.tick_index) && self.tick(cx) {
                    cx.set_timer(self.st.params.period, TICK.key(self.tick_index));
                }
                return;
            }
            Input::Event(Ev::Arrived(n)) => {
                self.st.mover.arrived();
                if let Some(r) = &mut self.st.route {
                    r.follow.hopped(*n);
                }
                // At the discrete level the leader waits node by node: each node reached
                // opens a new wait for stragglers.
                self.st.lag_since = None;
            }
            Input::Message(env) => self.hear(env, cx),
            _ => {}
        }
        if !self.started {
            self.started = true;
            if self.tick(cx) {
                cx.set_timer(self.st.params.period, TICK.key(self.tick_index));
            }
        }
    }
}
