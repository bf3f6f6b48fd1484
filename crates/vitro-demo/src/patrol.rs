//! The patrol controller: each car keeps its own idleness map (when each junction was last
//! visited, as far as it knows), drives to the least recently visited junction that no other
//! car has claimed, and broadcasts its claim together with the visits it made on the way.
//!
//! "Least recently visited" is discounted by the driving time (`distance_weight` seconds of
//! idleness per second of driving; 0 gives pure least-recently-visited). With shared visit
//! times, pure LRV sends every car across town after the globally oldest junctions and
//! patrols worse than cars that never talk; a small discount makes talking pay.
//!
//! Conflicts (two cars claiming one junction before hearing of each other) are settled by the
//! earlier arrival, then the lower entity id: the loser picks again. Claims expire at their
//! announced arrival time, so a lost message never blocks a junction for long.

use crate::world::{Event, Town};
use crate::world::{Fix, GoToNode, Gps, Navigator};
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::prelude::*;

/// The demo model: its environment, events, messages and agents.
#[derive(Debug)]
pub struct Demo;

impl Model for Demo {
    type Env = Town;
    type Event = Event;
    type Msg = PatrolMsg;
    type Agent = Patroller;

    fn on_env_event(env: &mut Town, event: &Event, fx: &mut Effects<'_, Event>) {
        if let Event::Tick(car) = event {
            env.on_tick(*car, fx);
        }
    }

    fn locate(env: &Town, who: EntityId, _now: SimTime) -> Option<[f64; 3]> {
        env.position(who).map(|(x, y)| [x, y, 0.0])
    }

    fn state_digest(env: &Town) -> u64 {
        env.digest()
    }
}

/// The capability a patrolling car offers in the register.
pub const PATROL: &str = "patrol";

/// Timer key: try to pick a goal again (none was free).
const RETRY: u64 = 1;
/// How long to wait before picking again when every junction is claimed.
const RETRY_AFTER: SimDuration = SimDuration::from_secs(1);

/// What cars tell each other.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PatrolMsg {
    /// "I am driving to `node` and expect to be there at `eta`; on my way since my last claim
    /// I visited these junctions at these times."
    Claim {
        /// The junction claimed.
        node: NodeId,
        /// Expected arrival.
        eta: SimTime,
        /// Visits since the sender's previous claim.
        visits: Vec<(NodeId, SimTime)>,
    },
}

/// What a patroller counted about itself.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PatrolStats {
    /// Goals chosen.
    pub decisions: u64,
    /// Goals reached.
    pub goals_reached: u64,
    /// Goals given up because another car had a better claim.
    pub yielded: u64,
    /// Claims heard from other cars.
    pub claims_heard: u64,
}

/// A patrolling car's brain.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Patroller {
    /// Last known visit of each junction.
    last_visit: Vec<SimTime>,
    /// The current claim of each other car: (junction, expected arrival).
    claims: BTreeMap<EntityId, (NodeId, SimTime)>,
    /// My own claim.
    goal: Option<(NodeId, SimTime)>,
    /// Visits made since my last claim went out.
    recent: Vec<(NodeId, SimTime)>,
    /// The pending decision, if one is under way.
    deciding: Option<OwnEventId>,
    /// Price of deliberation.
    cost: CostModel,
    /// Seconds of idleness a second of travel is worth.
    distance_weight: f64,
    stats: PatrolStats,
    failure: Option<String>,
}

impl Patroller {
    /// A patroller for a town of `junctions` junctions, thinking at `cost` per junction, that
    /// trades `distance_weight` seconds of idleness for a second of travel.
    pub fn new(junctions: usize, cost: CostModel, distance_weight: f64) -> Self {
        Patroller {
            last_visit: vec![SimTime::ZERO; junctions],
            claims: BTreeMap::new(),
            goal: None,
            recent: Vec::new(),
            deciding: None,
            cost,
            distance_weight,
            stats: PatrolStats::default(),
            failure: None,
        }
    }

    /// What this patroller counted.
    pub fn stats(&self) -> PatrolStats {
        self.stats
    }
    /// Why this patroller stopped working, if it did.
    pub fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }
    /// The junction it is driving to.
    pub fn goal(&self) -> Option<NodeId> {
        self.goal.map(|(n, _)| n)
    }

    /// Starts deliberating; the choice is made when [`Event::Decide`] comes back.
    fn think(&mut self, cx: &mut Context<'_, Demo>) {
        if self.deciding.is_none() {
            let units = self.last_visit.len() as u64;
            self.deciding = Some(cx.decide_after(&self.cost, units, Event::Decide));
        }
    }

    /// Picks the junction with the best score, `idleness - distance_weight × travel time`
    /// (with weight 0: the least recently visited), among those reachable, not where the car
    /// stands and not claimed by another car; ties go to the nearest, then to a random one.
    fn choose(&mut self, cx: &mut Context<'_, Demo>, fix: &Fix) -> Option<(NodeId, f64)> {
        let now = cx.now();
        self.claims.retain(|_, &mut (_, eta)| eta >= now);
        let taken: Vec<NodeId> = self.claims.values().map(|&(n, _)| n).collect();
        let parked_at = fix.heading_to.is_none().then_some(fix.node);
        let dist = cx.sense(&Navigator);
        let mut best: Vec<(NodeId, f64)> = Vec::new();
        let mut best_key = (f64::NEG_INFINITY, f64::INFINITY);
        for (i, (&last, &d)) in self.last_visit.iter().zip(&dist).enumerate() {
            let n = NodeId(i as u32);
            if !d.is_finite() || Some(n) == parked_at || taken.contains(&n) {
                continue;
            }
            let idle = (now - last).as_secs_f64();
            let score = idle - self.distance_weight * d / fix.speed_mps;
            let order = best_key.0.total_cmp(&score).then(d.total_cmp(&best_key.1));
            match order {
                std::cmp::Ordering::Less => {
                    best_key = (score, d);
                    best.clear();
                    best.push((n, d));
                }
                std::cmp::Ordering::Equal => best.push((n, d)),
                std::cmp::Ordering::Greater => {}
            }
        }
        match best.len() {
            0 => None,
            1 => Some(best[0]),
            k => Some(best[cx.rng("patrol").random_range(0..k)]),
        }
    }

    fn decide(&mut self, cx: &mut Context<'_, Demo>) {
        self.deciding = None;
        let Some(fix) = cx.sense(&Gps) else {
            self.fail(cx, "no car body".to_owned());
            return;
        };
        let Some((node, d)) = self.choose(cx, &fix) else {
            self.goal = None;
            cx.set_timer(RETRY_AFTER, RETRY);
            return;
        };
        if let Err(e) = cx.act(&GoToNode, node) {
            self.fail(cx, e.to_string());
            return;
        }
        let eta = cx.now() + SimDuration::from_secs_f64(d / fix.speed_mps);
        self.goal = Some((node, eta));
        self.stats.decisions += 1;
        let visits = std::mem::take(&mut self.recent);
        let size = u32::try_from(24 + 12 * visits.len()).unwrap_or(u32::MAX);
        cx.send(
            Outgoing::new(Address::Broadcast, PatrolMsg::Claim { node, eta, visits }).size(size),
        );
    }

    fn fail(&mut self, cx: &mut Context<'_, Demo>, why: String) {
        self.failure = Some(why);
        cx.request_stop();
    }

    fn heard(&mut self, cx: &mut Context<'_, Demo>, from: EntityId, msg: &PatrolMsg) {
        if !cx.register().offers(from, PATROL) {
            return;
        }
        let PatrolMsg::Claim { node, eta, visits } = msg;
        self.stats.claims_heard += 1;
        for &(n, t) in visits {
            if let Some(last) = self.last_visit.get_mut(n.0 as usize) {
                *last = (*last).max(t);
            }
        }
        self.claims.insert(from, (*node, *eta));
        let beaten = self
            .goal
            .is_some_and(|(mine, my_eta)| mine == *node && (*eta, from) < (my_eta, cx.me()));
        if beaten {
            self.goal = None;
            self.stats.yielded += 1;
            self.think(cx);
        }
    }
}

impl Agent<Demo> for Patroller {
    fn handle(&mut self, input: Input<'_, Demo>, cx: &mut Context<'_, Demo>) {
        if self.failure.is_some() {
            return;
        }
        match input {
            Input::Event(Event::Start) => {
                cx.offer(PATROL);
                self.think(cx);
            }
            Input::Event(Event::Decide) => self.decide(cx),
            Input::Event(&Event::AtNode { node, goal }) => {
                let now = cx.now();
                if let Some(last) = self.last_visit.get_mut(node.0 as usize) {
                    *last = now;
                }
                self.recent.push((node, now));
                // A stale arrival (the goal changed meanwhile) is only a visit.
                if goal && self.goal.is_none_or(|(g, _)| g == node) {
                    self.stats.goals_reached += 1;
                    self.goal = None;
                    self.think(cx);
                }
            }
            Input::Message(env) => self.heard(cx, env.from, &env.body),
            Input::Timer(RETRY) => self.think(cx),
            // Ticks go to the environment; out-of-range copies of a broadcast come back here
            // and are counted by the network: nothing to do.
            Input::Event(Event::Tick(_)) | Input::Timer(_) | Input::Undeliverable(..) => {}
        }
    }
}
