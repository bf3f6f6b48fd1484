//! A squad member: keeps the slot its leader gives it, through its actuators only, and
//! reports red troopers it sees.

use super::kb::{self, Signature, answers, atom, fact};
use super::motion::{Follow, Mover, xy};
use super::pattern::{Pattern, Trail, slot_point};
use super::sense::{ClearWay, FreeSlot, Gait, Hostile, Hostiles, NextNode, WalkRoute};
use super::{FormationError, FormationParams, LINK_STALE, MEMBER_PROGRAM, at_level};
use serde::{Deserialize, Serialize};

mod briefing;
use crate::belief::{Fix, Whereabouts};
use briefing::Brief;
use vitro::comm::{Address, Envelope, Outgoing};
use vitro::entity::EntityId;
use vitro::protocol::TimerTag;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_algo::rules::{Bindings, Interpreter, KbError, ModuleSet, Query, Term, Update};
use vitro_site::geo::{P2, dist};
use vitro_tactical::arena::{Ev, OwnPose};
use vitro_tactical::entity::{Level, Pose};
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::radio::{Contact, Signal, SquadTalk};
use vitro_tactical::world::Side;

/// The member's modules and their update operations.
const MODULES: Signature = &[
    ("orders", &[]),
    ("motion", &["close", "around", "stop"]),
    ("eyes", &["report"]),
];
const ORDERS: usize = 0;
const MOTION: usize = 1;
const EYES: usize = 2;

/// Timer tag of the member's deliberation tick ("FM").
const TICK: TimerTag = TimerTag(0x464d);
/// A walk-graph detour is planned again after this long, or when the slot moved a spacing.
const REPLAN: SimDuration = SimDuration::from_secs(10);
/// How far ahead along a detour the member looks for a straight way, metres.
const LOOK: f64 = 4.0;
/// A walking member keeps up at up to this multiple of its walking speed.
const WALK_MARGIN: f64 = 1.25;
/// How many points of the leader's trail a member tries as a way round an obstacle.
const TRAIL_TRIES: usize = 24;
/// How much of its own way a member remembers, metres.
const OWN_TRAIL: f64 = 150.0;

/// Everything the member's modules read and write.
#[derive(Debug, Serialize, Deserialize)]
struct State {
    leader: EntityId,
    params: FormationParams,
    brief: Option<Brief>,
    trail: Trail,
    pose: Option<Pose>,
    leader_seen: bool,
    /// The slot, free of forbidden zones.
    slot: Option<P2>,
    /// Where the slot will be one period from now.
    target: Option<P2>,
    /// The point of the leader's way the slot is measured from.
    base: Option<P2>,
    clear: bool,
    gap: f64,
    walk: f64,
    detour: Option<(Follow, P2, SimTime)>,
    /// The member's own way (to back out of a dead end by); not recorded while backing out.
    own: Trail,
    backing: bool,
    mover: Mover,
    moved: bool,
    seen: Vec<Hostile>,
    reported: Vec<(EntityId, SimTime)>,
    problems: Vec<String>,
    /// Where the leader is, from its position reports.
    known: Whereabouts,
    /// Its own last fix sent to the leader.
    sent: Option<Fix>,
}

/// A squad member (a [`Controller`]) following the leader `leader`: see the
/// [module docs](super). It stands still until the leader briefs it.
#[derive(Serialize, Deserialize)]
pub struct Member {
    interp: Option<Interpreter>,
    st: State,
    doing: String,
    started: bool,
    cycles: u64,
    tick_index: u64,
}

impl Member {
    /// A member of `leader`'s squad running the built-in program ([`MEMBER_PROGRAM`]).
    /// Its body is placed by the caller; it starts deliberating at its first input.
    pub fn new(leader: EntityId, params: FormationParams) -> Member {
        let (interp, problem) = match kb::load("member.jz", MEMBER_PROGRAM, MODULES) {
            Ok(i) => (Some(i), None),
            Err(e) => (None, Some(e.to_string())),
        };
        let mut m = Member::build(interp, leader, params);
        m.st.problems.extend(problem);
        m
    }

    /// A member running its own rule program `program` (source text; the modules as in
    /// `data/rules/formation/member.jz`).
    ///
    /// # Errors
    /// [`FormationError::Program`] (the program named `member.jz`) or
    /// [`FormationError::Param`].
    pub fn with_program(
        program: &str,
        leader: EntityId,
        params: FormationParams,
    ) -> Result<Member, FormationError> {
        params.validate()?;
        let interp = kb::load("member.jz", program, MODULES)?;
        Ok(Member::build(Some(interp), leader, params))
    }

    fn build(interp: Option<Interpreter>, leader: EntityId, params: FormationParams) -> Member {
        Member {
            interp,
            doing: String::new(),
            st: State {
                leader,
                params,
                brief: None,
                trail: Trail::new(),
                pose: None,
                leader_seen: false,
                slot: None,
                target: None,
                base: None,
                clear: false,
                gap: 0.0,
                walk: 1.0,
                detour: None,
                own: Trail::new(),
                backing: false,
                mover: Mover::default(),
                moved: false,
                seen: Vec::new(),
                reported: Vec::new(),
                problems: Vec::new(),
                known: Whereabouts::new(LINK_STALE),
                sent: None,
            },
            started: false,
            cycles: 0,
            tick_index: 0,
        }
    }

    /// The same member, deliberating on timer `TimerTag(0x464d).key(index)` (default 0)
    /// and ignoring that tag's other keys (see [`Leader::with_timer_index`]).
    ///
    /// [`Leader::with_timer_index`]: super::Leader::with_timer_index
    pub fn with_timer_index(mut self, index: u64) -> Self {
        self.tick_index = index;
        self
    }

    /// The leader it follows.
    pub fn leader(&self) -> EntityId {
        self.st.leader
    }
    /// Its slot number, if briefed.
    pub fn slot(&self) -> Option<usize> {
        self.st.brief.map(|b| b.slot)
    }
    /// The pattern it keeps, if briefed.
    pub fn pattern(&self) -> Option<Pattern> {
        self.st.brief.map(|b| b.pattern)
    }
    /// Where its slot was at its latest cycle (world metres, free of forbidden zones), if
    /// it was briefed and saw the leader.
    pub fn slot_point(&self) -> Option<P2> {
        self.st.slot
    }
    /// Deliberation cycles run.
    pub fn cycles(&self) -> u64 {
        self.cycles
    }
    /// The updates of its latest cycle, e.g. `close motion [walk]`.
    pub fn doing(&self) -> &str {
        &self.doing
    }
    /// Things that went wrong, in order.
    pub fn problems(&self) -> &[String] {
        &self.st.problems
    }

    /// One deliberation cycle; false if the member has no body or no program (it stops).
    fn tick<M: SquadTalk>(&mut self, cx: &mut Context<'_, Tactical<M>>) -> bool {
        let Some(interp) = &self.interp else {
            return false;
        };
        let Some(pose) = cx.sense(&OwnPose) else {
            self.st.problem("the member has no body: it stops".into());
            return false;
        };
        let st = &mut self.st;
        st.pose = Some(pose);
        if !st.backing {
            st.own.record(xy(&pose), OWN_TRAIL);
        }
        st.walk = cx.sense(&Gait).unwrap_or(st.walk);
        st.locate_slot(cx, &pose);
        st.seen = cx.sense(&Hostiles {
            range: st.params.sight_range,
        });
        let hold = st.params.contact_hold;
        let now = cx.now();
        st.reported.retain(|&(_, t)| now - t <= hold);
        st.moved = false;
        let seed = kb::seed(cx);
        let cycle = kb::cycle(interp, &mut Bound { st, cx }, seed);
        self.doing = cycle.updates.join(", ");
        for e in cycle.errors {
            self.st.problem(format!("member.jz:{e}"));
        }
        if !self.st.moved
            && let Err(e) = self.st.mover.stop(cx, &pose)
        {
            self.st.problem(e.to_string());
        }
        // The formation link: its own fix to the leader, as it moves on (after this cycle's
        // command).
        let now = cx.now();
        let fix = Fix::after(
            &cx.sense(&OwnPose).unwrap_or(pose),
            now,
            self.st.sent.as_ref(),
        );
        self.st.sent = Some(fix);
        cx.send(Outgoing::new(Address::Agent(self.st.leader), M::from(fix)));
        self.cycles += 1;
        true
    }

    fn hear<M: SquadTalk>(&mut self, env: &Envelope<M>) {
        if env.from != self.st.leader {
            return;
        }
        self.st.known.hear(env);
        if let Some(Signal { name, arg }) = env.body.read::<Signal>()
            && name == "formation"
        {
            match Brief::parse(&arg) {
                Ok(b) => {
                    self.st.brief = b;
                    self.st.detour = None;
                }
                Err(e) => self.st.problem(e),
            }
        }
    }
}

impl State {
    fn problem(&mut self, p: String) {
        if self.problems.last() != Some(&p) {
            self.problems.push(p);
        }
    }

    /// Tracks the leader (where its reports put it now) and finds the slot (free), where it
    /// will be in one period, and whether the straight way there is clear.
    fn locate_slot<M: SquadTalk>(&mut self, cx: &mut Context<'_, Tactical<M>>, pose: &Pose) {
        let now = cx.now();
        let lead = self
            .known
            .fresh(self.leader, now)
            .map(|f| f.pose(at_level(f, now, pose.level), pose.level));
        self.leader_seen = lead.is_some();
        self.slot = None;
        self.target = None;
        self.base = None;
        let Some(lead) = lead else {
            return;
        };
        let Some(b) = self.brief else {
            return;
        };
        let keep = (b.slot as f64 + 2.0) * b.spacing + 10.0;
        let mut at = xy(&lead);
        self.trail.record(at, keep);
        if pose.level == Level::Discrete && lead.speed > 0.0 {
            // The leader is hopping to the next node: the slot is taken from there, so that
            // the member hops at the same time instead of a hop behind.
            let next = NextNode {
                from: at,
                heading: lead.heading,
            };
            if let Some((_, q)) = cx.sense(&next) {
                at = q;
            }
        }
        let (base, raw) = slot_point(
            b.pattern,
            b.slot,
            b.spacing,
            at,
            lead.heading,
            &self.trail,
            b.facing,
        );
        let slot = cx.sense(&FreeSlot { base, slot: raw });
        // Where the slot will be in one period if the leader keeps its speed and heading.
        let ahead = lead.speed * self.params.period.as_secs_f64();
        let target = if ahead > 0.01 && pose.level != Level::Discrete {
            let (s, c) = (libm::sin(lead.heading), libm::cos(lead.heading));
            let shift = |p: P2| [p[0] + ahead * c, p[1] + ahead * s];
            cx.sense(&FreeSlot {
                base: shift(base),
                slot: shift(raw),
            })
        } else {
            slot
        };
        let me = xy(pose);
        // At the discrete level every way is a walk on the graph: no straight way to probe.
        self.clear = pose.level == Level::Discrete
            || cx.sense(&ClearWay {
                from: me,
                to: target,
            });
        self.gap = dist(me, slot);
        self.slot = Some(slot);
        self.target = Some(target);
        self.base = Some(base);
    }

    fn cap(&self, pace: &str) -> Result<f64, KbError> {
        match pace {
            "walk" => Ok(self.walk * WALK_MARGIN),
            "run" => Ok(self.walk * self.params.run_factor),
            other => Err(KbError::Refused(format!("no pace {other}"))),
        }
    }

    /// Straight to the slot's next position, at the speed that gets there in one period.
    fn close<M: SquadTalk>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        cap: f64,
    ) -> Result<(), KbError> {
        let (Some(pose), Some(to)) = (self.pose, self.target) else {
            return Err(KbError::Refused("no slot".into()));
        };
        self.detour = None;
        let speed = (dist(xy(&pose), to) / self.params.period.as_secs_f64()).min(cap);
        self.moved = true;
        self.mover
            .toward(cx, &pose, to, speed)
            .map_err(|e| KbError::Refused(e.to_string()))
    }

    /// Round an obstacle to the slot: by the leader's way (the slot's base point, or the
    /// point of the leader's trail nearest to it that is in a straight line), else along the
    /// walk graph (planned again when stale), else backing out the way it came.
    fn around<M: SquadTalk>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        cap: f64,
    ) -> Result<(), KbError> {
        let (Some(pose), Some(slot)) = (self.pose, self.slot) else {
            return Err(KbError::Refused("no slot".into()));
        };
        let me = xy(&pose);
        if pose.level == Level::Discrete {
            self.moved = true;
            return self
                .mover
                .toward(cx, &pose, slot, cap)
                .map_err(|e| KbError::Refused(e.to_string()));
        }
        if let Some(to) = self.by_trail(cx, me) {
            self.detour = None;
            self.backing = false;
            self.moved = true;
            return self
                .mover
                .toward(cx, &pose, to, cap)
                .map_err(|e| KbError::Refused(e.to_string()));
        }
        let now = cx.now();
        let spacing = self.brief.map_or(self.params.spacing, |b| b.spacing);
        let stale = self
            .detour
            .as_ref()
            .is_none_or(|(_, goal, at)| dist(*goal, slot) > spacing || now - *at >= REPLAN);
        if stale {
            let leg = cx.sense(&WalkRoute { from: me, to: slot });
            self.detour = leg.map(|l| (Follow::new(l), slot, now));
        }
        let step = match &mut self.detour {
            Some((follow, _, _)) => {
                follow.advance(me);
                if follow.done(pose.level) {
                    // At the node nearest the slot, and the slot still out of a straight
                    // line: the best place there is.
                    self.moved = true;
                    return self
                        .mover
                        .stop(cx, &pose)
                        .map_err(|e| KbError::Refused(e.to_string()));
                }
                follow.target(cx, me, LOOK).map(|(to, _)| to)
            }
            None => None,
        };
        let to = match step {
            Some(to) => {
                self.backing = false;
                to
            }
            None => {
                // No walk-graph node in a straight line (or off the detour): back out the
                // way it came until one is.
                self.detour = None;
                self.backing = true;
                self.back_out(cx, me)?
            }
        };
        self.moved = true;
        self.mover
            .toward(cx, &pose, to, cap)
            .map_err(|e| KbError::Refused(e.to_string()))
    }

    /// The slot's base point if the way to it is clear, else the point of the leader's trail
    /// nearest to the base (among the nearest few) that is.
    fn by_trail<M: SquadTalk>(&self, cx: &mut Context<'_, Tactical<M>>, me: P2) -> Option<P2> {
        let base = self.base?;
        let mut pts: Vec<P2> = self.trail.points().to_vec();
        pts.sort_by(|a, b| dist(*a, base).total_cmp(&dist(*b, base)));
        std::iter::once(base)
            .chain(pts.into_iter().take(TRAIL_TRIES))
            .find(|&q| dist(me, q) > 0.3 && cx.sense(&ClearWay { from: me, to: q }))
    }

    /// The oldest point of its own way it can walk back to in a straight line (forgetting
    /// the way after it once there).
    fn back_out<M: SquadTalk>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        me: P2,
    ) -> Result<P2, KbError> {
        let pts = self.own.points().to_vec();
        let Some(i) = (0..pts.len()).find(|&i| {
            cx.sense(&ClearWay {
                from: me,
                to: pts[i],
            })
        }) else {
            return Err(KbError::Refused("stuck: no way back".into()));
        };
        if dist(me, pts[i]) < 0.5 {
            self.own.truncate(i + 1);
        }
        Ok(pts[i])
    }
}

/// The member's modules bound to its state and context for one cycle.
struct Bound<'a, 'c, M: SquadTalk> {
    st: &'a mut State,
    cx: &'a mut Context<'c, Tactical<M>>,
}

impl<M: SquadTalk> ModuleSet for Bound<'_, '_, M> {
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
        let mut facts = Vec::new();
        match module {
            ORDERS => {
                if let Some(b) = st.brief {
                    facts.push(Term::atom("briefed"));
                    facts.push(fact("formation", Term::atom(b.pattern.name())));
                    facts.push(fact("slot", Term::Int(b.slot as i64)));
                }
            }
            MOTION => {
                if st.leader_seen {
                    facts.push(Term::atom("leader_seen"));
                }
                if st.slot.is_some() && st.clear {
                    facts.push(Term::atom("clear"));
                }
                if st.slot.is_some() && st.gap > st.params.far {
                    facts.push(Term::atom("far"));
                }
            }
            EYES => {
                for h in &st.seen {
                    facts.push(fact("hostile", Term::Int(i64::from(h.id.0))));
                }
                for (id, _) in &st.reported {
                    facts.push(fact("reported", Term::Int(i64::from(id.0))));
                }
            }
            _ => {}
        }
        answers(q, facts)
    }

    fn update(&mut self, module: usize, u: &Update) -> Result<(), KbError> {
        let st = &mut *self.st;
        let cx = &mut *self.cx;
        match (module, u.op.as_str()) {
            (MOTION, "close") => {
                let cap = st.cap(atom(u)?)?;
                st.close(cx, cap)
            }
            (MOTION, "around") => {
                let cap = st.cap(atom(u)?)?;
                st.around(cx, cap)
            }
            (MOTION, "stop") => {
                st.moved = true;
                match st.pose {
                    Some(p) => st
                        .mover
                        .stop(cx, &p)
                        .map_err(|e| KbError::Refused(e.to_string())),
                    None => Ok(()),
                }
            }
            (EYES, "report") => {
                let n = u
                    .term
                    .as_int()
                    .ok_or_else(|| KbError::Refused(format!("{} is not a number", u.term)))?;
                let Some(h) = st.seen.iter().find(|h| i64::from(h.id.0) == n).copied() else {
                    return Err(KbError::Refused(format!("{n} is not in sight")));
                };
                let msg = M::from(Contact {
                    target: h.id,
                    pos: h.pos,
                    seen_as: Side::Red,
                });
                cx.send(Outgoing::new(Address::Agent(st.leader), msg));
                st.reported.push((h.id, cx.now()));
                Ok(())
            }
            (_, op) => Err(KbError::UnknownOperation(op.into())),
        }
    }
}

impl<M: SquadTalk> Controller<Tactical<M>> for Member {
    fn handle(&mut self, input: Input<'_, Tactical<M>>, cx: &mut Context<'_, Tactical<M>>) {
        match input {
            Input::Timer(key) if TICK.index(key).is_some() => {
                if TICK.index(key) == Some(self.tick_index) && self.tick(cx) {
                    cx.set_timer(self.st.params.period, TICK.key(self.tick_index));
                }
                return;
            }
            Input::Event(Ev::Arrived(_)) => self.st.mover.arrived(),
            Input::Message(env) => self.hear(env),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_program_loads() {
        let m = Member::new(EntityId(0), FormationParams::default());
        assert!(
            m.interp.is_some() && m.problems().is_empty(),
            "{:?}",
            m.problems()
        );
    }
}
