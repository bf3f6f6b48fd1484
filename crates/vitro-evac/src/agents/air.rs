//! The watchers: UAVs over the team and the UGV ahead of it. Each reports hostile contacts
//! to the blue group.
//!
//! - [`AirRole::Patrol`] (Skeldar): flies a randomized patrol around the convoy — every
//!   patrol step the next checkpoint drawn from the policy of the patrol game
//!   ([`patrol`](super::patrol)), phase-locked to the truck's progress;
//! - [`AirRole::Cover`] (Vidar): hovers over the checkpoints the cover plan gives it ahead
//!   of the team;
//! - [`AirRole::Scout`] (Procerus): flies the route ahead of the truck;
//! - [`Ugv`]: drives to the junctions ahead of the truck.

use super::cover::{CoverPlanner, Repair, checkpoints, nearest};
use super::overwatch::Overwatch;
use super::patrol::PatrolUnit;
use super::{Reporter, SENSE, last_known, note_friends, tell};
use crate::act::{Drive, Pilot};
use crate::brief::{BLUE, Brief};
use crate::sense::{Myself, Vision};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::SimDuration;
use vitro_site::map::Mode;
use vitro_tactical::arena::{Ev, OwnPose};
use vitro_tactical::belief::{Beacon, Whereabouts};
use vitro_tactical::condition::Status;
use vitro_tactical::entity::air::FlightCommand;
use vitro_tactical::model::{Controller, Intention, Tactical};
use vitro_tactical::radio::Radio;

/// Timer key of the flight re-planning.
const PLAN: u64 = 40;
/// Re-planning period of the aircraft, seconds.
const PLAN_S: f64 = 20.0;
/// Timer key of the check whether to support the HVT hunt.
const OVERWATCH: u64 = 41;
/// Period of that check, seconds.
const OVERWATCH_S: f64 = 20.0;

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
    #[serde(with = "crate::snapshot::briefed")]
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
    /// Cover checkpoints to fly to, in order (Vidars).
    queue: Vec<usize>,
    /// The checkpoints of the last waypoint command.
    flying: Vec<usize>,
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
            queue: Vec::new(),
            flying: Vec::new(),
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
    fn truck(&self, cx: &mut Context<'_, Tactical>) -> Option<[f64; 3]> {
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
    fn patrol_step(&mut self, cx: &mut Context<'_, Tactical>) {
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
        let game = &unit.game;
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

    /// The lead's turn: makes or repairs the cover plan and hands out the steps.
    fn lead_cover(&mut self, cx: &mut Context<'_, Tactical>) {
        let Some(truck) = self.truck(cx) else {
            return;
        };
        let me = cx.me();
        let now = cx.now();
        let own = cx.sense(&OwnPose).map(|p| p.pos);
        let Some(planner) = self.cover.as_mut() else {
            return;
        };
        let k = nearest(&planner.points, truck);
        let team = planner.team.clone();
        // Each Vidar where its last report puts it (itself: its own GPS).
        let at: Vec<usize> = team
            .iter()
            .map(|&id| {
                let pos = if id == me {
                    own
                } else {
                    last_known(&self.known, id, now)
                };
                pos.map_or(0, |p| nearest(&planner.points, p))
            })
            .collect();
        let Some(Repair { steps, replace, .. }) = planner.update(k, &at) else {
            return;
        };
        for (id, mine) in team.into_iter().zip(steps) {
            if mine.is_empty() && !replace {
                continue;
            }
            if id == me {
                self.take_steps(mine, replace, cx);
            } else {
                let mut body = vec![if replace { "replace" } else { "append" }.to_string()];
                body.extend(mine.iter().map(|c| format!("c{c}")));
                tell(cx, id, Radio::Plan(body));
                if let Some(c) = self.cover.as_mut() {
                    c.messages += 1;
                }
            }
        }
    }

    /// Takes new cover steps and flies them.
    fn take_steps(&mut self, steps: Vec<usize>, replace: bool, cx: &mut Context<'_, Tactical>) {
        if replace {
            self.queue = steps;
        } else {
            self.queue.extend(steps);
        }
        let points: Vec<[f64; 3]> = self
            .queue
            .iter()
            .filter_map(|&c| self.points.get(c).copied())
            .map(|p| self.above(p))
            .collect();
        if points.is_empty() {
            return;
        }
        self.flying = self.queue.clone();
        self.fly(points, cx);
    }

    /// Waypoint `i` of the last command reached: drops the steps flown.
    fn reached(&mut self, i: usize) {
        let Some(&c) = self.flying.get(i) else { return };
        if let Some(j) = self.queue.iter().position(|&q| q == c) {
            self.queue.drain(..=j);
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
    fn check_hunt(&mut self, cx: &mut Context<'_, Tactical>) {
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
    fn fly_orbit(&mut self, cx: &mut Context<'_, Tactical>) {
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
    fn fly(&mut self, points: Vec<[f64; 3]>, cx: &mut Context<'_, Tactical>) {
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

    fn plan(&mut self, cx: &mut Context<'_, Tactical>) {
        if self.hunting {
            return;
        }
        match self.role {
            AirRole::Cover { .. } => return self.lead_cover(cx),
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

impl Controller for Aircraft {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                self.beacon.start(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
                // The first plan once the first position reports are in.
                cx.set_timer(SimDuration::from_secs(1), PLAN);
                cx.set_timer(SimDuration::from_secs_f64(OVERWATCH_S), OVERWATCH);
            }
            Input::Timer(Beacon::TIMER) => self.beacon.tick(cx),
            Input::Timer(OVERWATCH) => {
                self.check_hunt(cx);
                if !self.hunting {
                    cx.set_timer(SimDuration::from_secs_f64(OVERWATCH_S), OVERWATCH);
                }
            }
            Input::Timer(PLAN) => {
                self.plan(cx);
                let again = !matches!(self.role, AirRole::Cover { .. }) || self.cover.is_some();
                let period = match &self.patrol {
                    Some(unit) => unit.game.step_s,
                    None => PLAN_S,
                };
                if again {
                    cx.set_timer(SimDuration::from_secs_f64(period), PLAN);
                }
            }
            // Round the orbit again from its last point.
            Input::Event(Ev::Waypoint(i)) if self.hunting && *i as usize + 1 >= self.path.len() => {
                self.fly_orbit(cx);
            }
            Input::Event(Ev::Waypoint(_)) if self.hunting => {}
            Input::Event(Ev::Waypoint(i)) => self.reached(*i as usize),
            Input::Message(env) => {
                self.known.hear(env);
                if self.overwatch.hear(&env.body) && self.hunting {
                    self.fly_orbit(cx);
                }
                if let Radio::Plan(body) = &env.body
                    && !self.hunting
                    && let Some((how, rest)) = body.split_first()
                {
                    let steps = rest
                        .iter()
                        .filter_map(|c| c.strip_prefix('c')?.parse().ok())
                        .collect();
                    self.take_steps(steps, how == "replace", cx);
                }
            }
            Input::Timer(SENSE) => {
                let active = cx
                    .sense(&Myself)
                    .is_some_and(|(c, _)| c.status == Status::Active);
                if active {
                    let seen = cx.sense(&Vision(self.brief.sensors.air.vision()));
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
                self.queue.iter().map(|c| format!("fly to c{c}")).collect(),
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

/// The unmanned ground vehicle: drives to the route junctions ahead of the truck.
#[derive(Debug, Serialize, Deserialize)]
pub struct Ugv {
    #[serde(with = "crate::snapshot::briefed")]
    brief: Arc<Brief>,
    drive: Drive,
    reporter: Reporter,
    goal: Option<NodeId>,
    known: Whereabouts,
    beacon: Beacon,
}

impl Ugv {
    /// The UGV of `brief`, driving at `drive`'s level.
    pub fn new(brief: Arc<Brief>, drive: Drive) -> Self {
        Ugv {
            known: super::whereabouts(&brief),
            beacon: super::beacon(&brief),
            brief,
            drive,
            reporter: Reporter::default(),
            goal: None,
        }
    }
    fn next(&mut self, cx: &mut Context<'_, Tactical>) {
        let Some(truck) = last_known(&self.known, self.brief.truck, cx.now()) else {
            // No report of the truck yet: it waits and asks again.
            cx.set_timer(SimDuration::from_secs(10), PLAN);
            return;
        };
        let r = &self.brief.route;
        let k = (progress(&self.brief, truck) + 6).min(r.len().saturating_sub(1));
        let Some(&goal) = r.get(k) else { return };
        if self.goal != Some(goal) && cx.act(&self.drive, goal).is_ok() {
            self.goal = Some(goal);
        } else {
            self.goal = None;
            cx.set_timer(SimDuration::from_secs(10), PLAN);
        }
    }
}

impl Controller for Ugv {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                self.beacon.start(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
                // The first goal once the first position reports are in.
                cx.set_timer(SimDuration::from_secs(1), PLAN);
            }
            Input::Timer(Beacon::TIMER) => self.beacon.tick(cx),
            Input::Message(env) => {
                self.known.hear(env);
            }
            Input::Event(Ev::Arrived(_)) | Input::Timer(PLAN) => self.next(cx),
            // Stuck on the way: a new goal later, planned from where it stands.
            Input::Event(Ev::Stalled(_)) => {
                self.goal = None;
                cx.set_timer(SimDuration::from_secs(10), PLAN);
            }
            Input::Timer(SENSE) => {
                let seen = cx.sense(&Vision(self.brief.sensors.ground.vision()));
                note_friends(&mut self.known, &seen, cx.now());
                self.reporter.report(&seen, cx);
                cx.set_timer(
                    SimDuration::from_secs_f64(self.brief.sensors.period_s),
                    SENSE,
                );
            }
            _ => {}
        }
    }
    fn intention(&self) -> Option<Intention> {
        Some(Intention {
            text: "scout the junctions ahead".into(),
            path: self
                .goal
                .and_then(|g| self.brief.node_point(Mode::Drive, g))
                .into_iter()
                .collect(),
            ..Intention::default()
        })
    }
}
