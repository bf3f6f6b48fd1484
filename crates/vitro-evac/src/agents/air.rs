//! The watchers: UAVs over the team and the UGV ahead of it. Each reports hostile contacts
//! to the blue group.
//!
//! - [`AirRole::Patrol`] (Skeldar): flies a randomized patrol around the convoy — every
//!   patrol step the next checkpoint drawn from the policy of the patrol game
//!   ([`patrol`](super::patrol)), phase-locked to the truck's progress;
//! - [`AirRole::Cover`] (Vidar): hovers over the checkpoints the cover plan gives it ahead
//!   of the team;
//! - [`AirRole::Scout`] (Procerus): flies the route ahead of the truck.
//!
//! (The UGV ahead of the truck is [`Ugv`](super::ugv::Ugv).)

use super::cover::watch::{Heard, Watcher, plan_message, read_plan};
use super::cover::{CoverPlanner, CoverStep, checkpoints, nearest};
use super::overwatch::Overwatch;
use super::patrol::PatrolUnit;
use super::{Reporter, SENSE, last_known, note_friends, tell};
use crate::act::Pilot;
use crate::brief::{BLUE, Brief};
use crate::radio::{Evac, Radio};
use crate::sense::{GroundView, Myself, VisionOf};
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::SimDuration;
use vitro_behaviour::belief::{Beacon, Whereabouts};
use vitro_site::map::Mode;
use vitro_tactical::arena::{Ev, OwnPose};
use vitro_tactical::condition::Status;
use vitro_tactical::entity::air::FlightCommand;
use vitro_tactical::model::{Controller, Intention};

/// Timer key of the flight re-planning.
const PLAN: u64 = 40;
/// Re-planning period of the aircraft, seconds.
const PLAN_S: f64 = 20.0;
/// Timer key of the check whether to support the HVT hunt.
const OVERWATCH: u64 = 41;
/// Period of that check, seconds.
const OVERWATCH_S: f64 = 20.0;
/// Timer key of a Vidar's recall.
const RECALL: u64 = 42;
/// Turn period of the Vidars (the lead's repairs, each one's next step), seconds.
const COVER_S: f64 = 5.0;

/// What an aircraft does.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum AirRole {
    /// Randomized patrol around the convoy.
    Patrol,
    /// Cover the team from a checkpoint ahead; `slot` orders the covering aircraft.
    Cover {
        /// 0 for the first cover aircraft, 1 for the second, ...
        slot: usize,
    },
    /// Fly the route ahead of the truck.
    Scout,
}

/// Index of the route node nearest to `p` (the truck's progress along the route).
pub fn progress(brief: &Brief, p: [f64; 3]) -> usize {
    let town = brief.site.to_town([p[0], p[1]]);
    let g = &brief.roads.of(Mode::Drive).graph;
    let d = |n: NodeId| {
        g.node(n).map_or(f64::INFINITY, |s| {
            libm::hypot(s.pos[0] - town[0], s.pos[1] - town[1])
        })
    };
    (0..brief.route.len())
        .min_by(|&a, &b| {
            d(brief.route[a])
                .total_cmp(&d(brief.route[b]))
                .then(a.cmp(&b))
        })
        .unwrap_or(0)
}

/// A UAV of the team.
#[derive(Debug, Serialize, Deserialize)]
pub struct Aircraft {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<Brief>,
    pilot: Pilot,
    /// What it does.
    pub role: AirRole,
    /// Height above the ground, metres.
    pub height: f64,
    reporter: Reporter,
    path: Vec<[f64; 3]>,
    /// The cover plan, on the lead Vidar.
    pub cover: Option<CoverPlanner>,
    /// Its unit of the patrol game (Skeldars).
    pub patrol: Option<PatrolUnit>,
    /// Its cover steps (Vidars).
    watcher: Option<Watcher>,
    points: Vec<[f64; 3]>,
    /// The hunt's search point, from the hunt lead.
    overwatch: Overwatch,
    /// True once the convoy is done and the aircraft searches for the HVT.
    pub hunting: bool,
    /// Where it believes the others are (their reports, its own camera).
    known: Whereabouts,
    beacon: Beacon,
}

impl Aircraft {
    /// An aircraft of `brief` with `role`, flying `height` metres above the ground.
    pub fn new(brief: Arc<Brief>, pilot: Pilot, role: AirRole, height: f64) -> Self {
        Aircraft {
            known: super::whereabouts(&brief),
            beacon: super::beacon(&brief),
            brief,
            pilot,
            role,
            height,
            reporter: Reporter::default(),
            path: Vec::new(),
            cover: None,
            patrol: None,
            watcher: None,
            points: Vec::new(),
            overwatch: Overwatch::default(),
            hunting: false,
        }
    }

    /// Where it believes the others are: their position reports and its own camera's fixes.
    pub fn known(&self) -> &Whereabouts {
        &self.known
    }

    /// Where it believes the truck is now (dead-reckoned from the last report, or the last
    /// reported place once that is stale; none before the first report).
    fn truck(&self, cx: &mut Context<'_, Evac>) -> Option<[f64; 3]> {
        last_known(&self.known, self.brief.truck, cx.now())
    }

    /// A Vidar of the cover team `team` (in slot order); the first plans for all.
    pub fn cover(
        brief: Arc<Brief>,
        pilot: Pilot,
        team: Vec<EntityId>,
        slot: usize,
        height: f64,
    ) -> Self {
        let lead = slot == 0;
        let mut a = Aircraft::new(brief.clone(), pilot, AirRole::Cover { slot }, height);
        a.points = checkpoints(&brief);
        a.watcher = team.first().map(|&l| Watcher::new(l));
        if lead {
            a.cover = Some(CoverPlanner::new(&brief, team));
        }
        a
    }

    /// A Skeldar flying `unit` of the patrol game.
    pub fn patrol(brief: Arc<Brief>, pilot: Pilot, unit: PatrolUnit, height: f64) -> Self {
        let mut a = Aircraft::new(brief, pilot, AirRole::Patrol, height);
        a.patrol = Some(unit);
        a
    }

    /// A patrol step: the next checkpoint of the patrol game, flown to (or none: it stays).
    fn patrol_step(&mut self, cx: &mut Context<'_, Evac>) {
        let truck = self
            .truck(cx)
            .map(|p| self.brief.site.to_town([p[0], p[1]]));
        let Some(unit) = self.patrol.as_mut() else {
            return;
        };
        let now = cx.now().as_secs_f64();
        let Some(next) = unit.step(truck, now, cx.rng("patrol")) else {
            return;
        };
        let Some(p) = unit.game.point(next) else {
            return;
        };
        let points = vec![self.above(p)];
        self.fly(points, cx);
    }

    /// The patrol's intention: the phase, the next checkpoint, and where the policy may have
    /// the Skeldar now (the heat map).
    fn patrol_intention(&self, unit: &PatrolUnit) -> Intention {
        let game = unit.game_now();
        let text = format!(
            "patrol: phase {}/{}, capture prob {:.2}",
            unit.phase,
            game.last_phase(),
            game.trip_capture_probability
        );
        let plan = unit
            .at
            .map(|v| format!("fly to checkpoint {v}"))
            .into_iter()
            .collect();
        Intention {
            text,
            plan,
            path: self.path.clone(),
            heat: game.heat(unit.unit, unit.phase),
            ..Intention::default()
        }
    }

    /// A Vidar's turn: the lead makes or repairs the cover plan; each starts its next step.
    fn cover_turn(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(truck) = self.truck(cx) else {
            return;
        };
        let k = nearest(&self.points, truck);
        if self.cover.is_some() {
            self.lead_cover(k, cx);
        }
        self.watch_next(k, cx);
    }

    /// The lead's turn: makes or repairs the cover plan and hands out the steps.
    fn lead_cover(&mut self, k: usize, cx: &mut Context<'_, Evac>) {
        let me = cx.me();
        let now = cx.now();
        let own = cx.sense(&OwnPose).map(|p| p.pos);
        let Some(planner) = self.cover.as_mut() else {
            return;
        };
        // Each Vidar where its fresh report puts it (itself: its own GPS); one whose
        // reports went stale is lost.
        let team = planner.team.clone();
        let mut at = Vec::with_capacity(team.len());
        for (i, &id) in team.iter().enumerate() {
            let pos = if id == me {
                own
            } else {
                self.known.estimate(id, now)
            };
            if pos.is_none() && id != me && self.known.last(id).is_some() {
                planner.lost(i);
            }
            at.push(pos.map(|p| nearest(&planner.points, p)));
        }
        let now_s = now.as_secs_f64();
        let orders = if planner.started() {
            planner.turn(k, &at, now_s)
        } else {
            // Before their first reports the others are taken to be where the lead is
            // (they take off together).
            let here = at.first().copied().flatten().unwrap_or(k);
            let start: Vec<usize> = at.iter().map(|a| a.unwrap_or(here)).collect();
            planner.start(k, &start, now_s)
        };
        // No plan (a route too short to cover): the Vidars stay where they are.
        let Ok(orders) = orders else { return };
        for (i, steps) in orders {
            let Some(&id) = team.get(i) else { continue };
            if id == me {
                if let Some(w) = self.watcher.as_mut() {
                    w.take(steps);
                }
            } else {
                tell(cx, id, plan_message(&steps));
                if let Some(c) = self.cover.as_mut() {
                    c.messages += 1;
                }
            }
        }
    }

    /// Starts the next cover step if it is due, the truck at checkpoint `k`.
    fn watch_next(&mut self, k: usize, cx: &mut Context<'_, Evac>) {
        let here = cx
            .sense(&OwnPose)
            .map_or(k, |p| nearest(&self.points, p.pos));
        let Some(s) = self.watcher.as_mut().and_then(|w| w.next(k, here)) else {
            return;
        };
        if let Some(&p) = self.points.get(s.spot) {
            let p = self.above(p);
            self.fly(vec![p], cx);
        }
    }

    /// The cover step under way reached its checkpoint: the camera looks at it, and the
    /// look is reported to the lead.
    fn look(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(w) = self.watcher.as_mut() else {
            return;
        };
        let Some(step) = w.arrived() else { return };
        let lead = w.lead;
        let Some(&point) = self.points.get(step.spot) else {
            return;
        };
        let range = self.brief.sensors.air.vision().range;
        let seen = cx.sense(&GroundView { point, range });
        let glitch = cx.rng("cover").random::<f64>() < self.brief.repair.failure_rate;
        self.report(lead, Heard::Look(step, seen && !glitch), cx);
        if let Some(truck) = self.truck(cx) {
            let k = nearest(&self.points, truck);
            self.watch_next(k, cx);
        }
    }

    /// Tells the lead `what` (the lead itself takes it at once).
    fn report(&mut self, lead: EntityId, what: Heard, cx: &mut Context<'_, Evac>) {
        if lead != cx.me() {
            tell(cx, lead, what.message());
            return;
        }
        let now_s = cx.now().as_secs_f64();
        if let (Some(c), Heard::Look(step, ok)) = (self.cover.as_mut(), what) {
            c.report(0, step, ok, now_s);
        }
    }

    /// The lead hears a Vidar's report.
    fn hear_cover(&mut self, from: EntityId, body: &Radio, now_s: f64) {
        let Some(c) = self.cover.as_mut() else { return };
        let (Some(heard), Some(i)) = (Heard::read(body), c.index_of(from)) else {
            return;
        };
        match heard {
            Heard::Look(step, ok) => c.report(i, step, ok, now_s),
            Heard::Recalled => c.lost(i),
        }
    }

    /// Recalled by its base: it tells the lead and flies back to the route's start.
    fn recall(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(w) = self.watcher.as_mut() else {
            return;
        };
        w.recalled = true;
        let lead = w.lead;
        self.report(lead, Heard::Recalled, cx);
        if let Some(&p) = self.points.first() {
            let p = self.above(p);
            self.fly(vec![p], cx);
        }
    }

    fn above(&self, p: [f64; 3]) -> [f64; 3] {
        let g = self.brief.site.ground([p[0], p[1]]).unwrap_or(p[2]);
        [p[0], p[1], g + self.height]
    }

    fn route_point(&self, i: usize) -> Option<[f64; 3]> {
        let r = &self.brief.route;
        let n = *r.get(i.min(r.len().saturating_sub(1)))?;
        self.brief.node_point(Mode::Drive, n)
    }

    /// Joins the hunt once the truck is at the extraction point and the hunt lead has named a
    /// search point.
    fn check_hunt(&mut self, cx: &mut Context<'_, Evac>) {
        if self.hunting || self.overwatch.point.is_none() {
            return;
        }
        let last = self.brief.route.len().saturating_sub(1);
        let done = self
            .truck(cx)
            .is_some_and(|p| progress(&self.brief, p) >= last);
        if done {
            self.hunting = true;
            self.fly_orbit(cx);
        }
    }

    /// Circles the hunt's search point (aircraft spread round it by id).
    fn fly_orbit(&mut self, cx: &mut Context<'_, Evac>) {
        let slot = cx.me().0 as usize;
        let points: Vec<[f64; 3]> = self
            .overwatch
            .orbit(slot)
            .into_iter()
            .map(|p| self.above([p[0], p[1], 0.0]))
            .collect();
        self.fly(points, cx);
    }

    /// Flies through `points` (world metres; none: no command) and shows them as its path.
    fn fly(&mut self, points: Vec<[f64; 3]>, cx: &mut Context<'_, Evac>) {
        if points.is_empty() {
            return;
        }
        self.path = points.clone();
        let _ = cx.act(
            &self.pilot,
            FlightCommand::Waypoints {
                points,
                speed: None,
            },
        );
    }

    fn plan(&mut self, cx: &mut Context<'_, Evac>) {
        if self.hunting {
            return;
        }
        match self.role {
            AirRole::Cover { .. } => return self.cover_turn(cx),
            AirRole::Patrol if self.patrol.is_some() => return self.patrol_step(cx),
            _ => {}
        }
        let Some(truck) = self.truck(cx) else {
            return;
        };
        let k = progress(&self.brief, truck);
        let points: Vec<[f64; 3]> = match self.role {
            // Without a patrol game: over the truck.
            AirRole::Patrol => vec![truck],
            AirRole::Cover { slot } => self.route_point(k + 2 + 3 * slot).into_iter().collect(),
            AirRole::Scout => (1..=4)
                .filter_map(|j| self.route_point(k + 3 * j))
                .collect(),
        };
        let points: Vec<[f64; 3]> = points.into_iter().map(|p| self.above(p)).collect();
        self.fly(points, cx);
    }
}

impl Controller<Evac> for Aircraft {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                self.beacon.start(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
                // The first plan once the first position reports are in.
                cx.set_timer(SimDuration::from_secs(1), PLAN);
                cx.set_timer(SimDuration::from_secs_f64(OVERWATCH_S), OVERWATCH);
                // A Vidar other than the lead may be recalled, at a time drawn from its
                // own stream (the scenario's `repair.failure_rate` per mission).
                if matches!(self.role, AirRole::Cover { slot } if slot > 0) {
                    let rng = cx.rng("recall");
                    let (draw, when) = (rng.random::<f64>(), rng.random::<f64>());
                    if draw < self.brief.repair.failure_rate {
                        let at = 60.0 + 540.0 * when;
                        cx.set_timer(SimDuration::from_secs_f64(at), RECALL);
                    }
                }
            }
            Input::Timer(RECALL) if !self.hunting => self.recall(cx),
            Input::Timer(Beacon::TIMER) => self.beacon.tick(cx),
            Input::Timer(OVERWATCH) => {
                self.check_hunt(cx);
                if !self.hunting {
                    cx.set_timer(SimDuration::from_secs_f64(OVERWATCH_S), OVERWATCH);
                }
            }
            Input::Timer(PLAN) => {
                self.plan(cx);
                let period = match (&self.patrol, self.role) {
                    (Some(unit), _) => unit.game.step_s,
                    (None, AirRole::Cover { .. }) => COVER_S,
                    (None, _) => PLAN_S,
                };
                cx.set_timer(SimDuration::from_secs_f64(period), PLAN);
            }
            // Round the orbit again from its last point.
            Input::Event(Ev::Waypoint(i)) if self.hunting && *i as usize + 1 >= self.path.len() => {
                self.fly_orbit(cx);
            }
            Input::Event(Ev::Waypoint(_)) if self.hunting => {}
            Input::Event(Ev::Waypoint(_)) => self.look(cx),
            Input::Message(env) => {
                self.known.hear(env);
                if self.overwatch.hear(&env.body) && self.hunting {
                    self.fly_orbit(cx);
                }
                self.hear_cover(env.from, &env.body, cx.now().as_secs_f64());
                if let Radio::Plan(body) = &env.body
                    && !self.hunting
                    && let Some(w) = self.watcher.as_mut()
                {
                    w.take(read_plan(body));
                    if let Some(truck) = self.truck(cx) {
                        let k = nearest(&self.points, truck);
                        self.watch_next(k, cx);
                    }
                }
            }
            Input::Timer(SENSE) => {
                let active = cx
                    .sense(&Myself)
                    .is_some_and(|(c, _)| c.status == Status::Active);
                if active {
                    // Only the blue and red sightings are noted or reported.
                    let seen = cx.sense(&VisionOf::armed(self.brief.sensors.air.vision()));
                    note_friends(&mut self.known, &seen, cx.now());
                    self.reporter.report(&seen, cx);
                    let period = SimDuration::from_secs_f64(self.brief.sensors.period_s);
                    cx.set_timer(period, SENSE);
                }
            }
            _ => {}
        }
    }
    fn intention(&self) -> Option<Intention> {
        if self.hunting {
            return Some(Intention {
                text: "support the HVT hunt: search round the lead's most likely place".into(),
                path: self.path.clone(),
                ..Intention::default()
            });
        }
        if let Some(unit) = &self.patrol {
            return Some(self.patrol_intention(unit));
        }
        let text = match self.role {
            AirRole::Patrol => "patrol around the convoy",
            AirRole::Cover { .. } => "cover the team from ahead",
            AirRole::Scout => "scout the route ahead",
        };
        let (plan, original_plan) = match &self.cover {
            Some(c) => (c.current.clone(), c.original.clone()),
            None => (
                self.watcher
                    .iter()
                    .flat_map(Watcher::steps)
                    .map(|s: CoverStep| format!("watch c{}", s.spot))
                    .collect(),
                Vec::new(),
            ),
        };
        Some(Intention {
            text: text.into(),
            path: self.path.clone(),
            plan,
            original_plan,
            ..Intention::default()
        })
    }
}
