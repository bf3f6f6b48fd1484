//! The world of the demo: storages (streets, cars, the visit log), the sensors that read them,
//! the `GoToNode` actuator that writes them, and the motion that moves cars over time.
//!
//! Agents never see [`Town`]: its storages are private to this module, and the patrol
//! controller reaches them only through [`Gps`], [`Navigator`] and [`GoToNode`].

use crate::town::{Streets, distances};
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects, EntityStorage, KeyValueStorage, NodeId, Probe, Sensor};
use vitro::event::Target;
use vitro::time::{SimDuration, SimTime};

/// Events of the demo.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Event {
    /// Wakes every car at the start.
    Start,
    /// A motion update of one car (for the environment).
    Tick(EntityId),
    /// A car reached a junction; `goal` is true at the end of its route.
    AtNode {
        /// The junction.
        node: NodeId,
        /// True if it is the goal of the current route.
        goal: bool,
    },
    /// A car finished deliberating and picks its next goal.
    Decide,
}

/// The body of a car: where it is and where it is going.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Car {
    /// The junction last reached.
    node: NodeId,
    /// The junction it is driving to along the current street, `None` when parked at `node`.
    next: Option<NodeId>,
    /// Length of the street `node -> next`.
    edge_m: f64,
    /// Distance driven along that street.
    progress_m: f64,
    /// Where the pending motion update will put the car along the street.
    target_m: f64,
    /// Position, metres east.
    x: f64,
    /// Position, metres north.
    y: f64,
    /// Cruising speed.
    speed_mps: f64,
    /// Period of motion updates.
    tick: SimDuration,
    /// Junctions still to reach after `next`, last one first (the goal is `route[0]`).
    route: Vec<NodeId>,
    /// True while a motion update is pending.
    moving: bool,
}

/// What the visit log keeps for one junction: enough for exact time-averaged idleness.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NodeLog {
    /// Number of visits.
    pub visits: u64,
    /// Time of the last visit (the start of the run counts as one).
    pub last: SimTime,
    /// Longest gap between visits so far.
    pub max_gap: SimDuration,
    /// Sum of squared gaps, in ns² (twice the integral of idleness over time).
    pub gap_sq: u128,
}

/// The environment: every storage of the demo world.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Town {
    streets: Streets,
    cars: EntityStorage<Car>,
    visits: KeyValueStorage<NodeId, NodeLog>,
}

impl Town {
    /// A town on `streets` with no cars yet.
    pub fn new(streets: Streets) -> Self {
        Town {
            streets,
            cars: EntityStorage::default(),
            visits: KeyValueStorage::default(),
        }
    }

    /// Parks a new car at junction `node`.
    pub fn park(
        &mut self,
        car: EntityId,
        node: NodeId,
        speed_mps: f64,
        tick: SimDuration,
    ) -> Option<()> {
        let j = *self.streets.node(node)?;
        self.cars.insert(
            car,
            Car {
                node,
                next: None,
                edge_m: 0.0,
                progress_m: 0.0,
                target_m: 0.0,
                x: j.x,
                y: j.y,
                speed_mps,
                tick,
                route: Vec::new(),
                moving: false,
            },
        );
        Some(())
    }

    /// The street graph (read-only, for set-up and reports).
    pub fn streets(&self) -> &Streets {
        &self.streets
    }
    /// The visit log of `node`.
    pub fn visit_log(&self, node: NodeId) -> NodeLog {
        self.visits.get(&node).copied().unwrap_or_default()
    }
    /// Position (x, y) of a car.
    pub fn position(&self, car: EntityId) -> Option<(f64, f64)> {
        self.cars.get(car).map(|c| (c.x, c.y))
    }
    /// Digest of every state change so far.
    pub fn digest(&self) -> u64 {
        let mut h = vitro::trace::TraceHasher::default();
        h.write_u64(self.streets.digest());
        h.write_u64(self.cars.digest());
        h.write_u64(self.visits.digest());
        h.finish()
    }

    fn record_visit(&mut self, node: NodeId, now: SimTime) {
        let mut log = self.visit_log(node);
        let gap = now.saturating_since(log.last);
        log.visits += 1;
        log.last = now;
        log.max_gap = log.max_gap.max(gap);
        log.gap_sq += u128::from(gap.as_nanos()).pow(2);
        self.visits.set(node, log);
    }

    /// Advances the motion of `car` (the handler of [`Event::Tick`]): one write to its row.
    pub(crate) fn on_tick(&mut self, car: EntityId, fx: &mut Effects<'_, Event>) {
        let now = fx.now();
        let Some(c) = self.cars.get(car) else { return };
        let Some(next) = c.next else {
            self.cars.update(car, |c| c.moving = false);
            return;
        };
        let (Some(from), Some(to)) = (self.streets.node(c.node), self.streets.node(next)) else {
            return;
        };
        let (from, to) = (*from, *to);
        let arrived = c.target_m >= c.edge_m;
        // The street after `next`, looked up before the write.
        let after = if arrived {
            c.route.last().copied()
        } else {
            None
        };
        let after_m = after.and_then(|n| self.streets.edge_length(next, n));
        let mut wake = None;
        self.cars.update(car, |c| {
            if arrived {
                c.node = next;
                c.route.pop();
                c.next = after;
                c.edge_m = after_m.unwrap_or(0.0);
                c.progress_m = 0.0;
                (c.x, c.y) = (to.x, to.y);
            } else {
                c.progress_m = c.target_m;
                let f = if c.edge_m > 0.0 {
                    c.progress_m / c.edge_m
                } else {
                    1.0
                };
                c.x = from.x + (to.x - from.x) * f;
                c.y = from.y + (to.y - from.y) * f;
            }
            wake = c.plan_step();
        });
        if arrived {
            self.record_visit(next, now);
            let goal = after.is_none();
            let at_node = Event::AtNode { node: next, goal };
            fx.schedule_in(SimDuration::ZERO, Target::Entity(car), at_node);
        }
        if let Some(delay) = wake {
            fx.schedule_in(delay, Target::Env, Event::Tick(car));
        }
    }
}

impl Car {
    /// Plans the next motion update of a car with a street ahead: a full tick, or less if it
    /// reaches the end of the street first (so junctions are reached exactly). Returns the
    /// delay to the update, `None` when the car has stopped.
    fn plan_step(&mut self) -> Option<SimDuration> {
        if self.next.is_none() {
            self.moving = false;
            return None;
        }
        let remaining = self.edge_m - self.progress_m;
        let step_m = self.speed_mps * self.tick.as_secs_f64();
        let delay = if remaining <= step_m {
            self.target_m = self.edge_m;
            SimDuration::from_secs_f64(remaining / self.speed_mps)
        } else {
            self.target_m = self.progress_m + step_m;
            self.tick
        };
        self.moving = true;
        Some(delay)
    }
}

/// Own position (a GPS with a map-matched junction): what the [`Gps`] sensor reports.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Fix {
    /// Metres east.
    pub x: f64,
    /// Metres north.
    pub y: f64,
    /// The junction last reached.
    pub node: NodeId,
    /// The junction being driven to, `None` when parked.
    pub heading_to: Option<NodeId>,
    /// Cruising speed.
    pub speed_mps: f64,
}

/// Reads the car's own position.
#[derive(Copy, Clone, Debug, Default)]
pub struct Gps;

impl Sensor<Town> for Gps {
    type Reading = Option<Fix>;
    fn read(&self, w: &Town, me: EntityId, _: &mut Probe<'_>) -> Option<Fix> {
        w.cars.get(me).map(|c| Fix {
            x: c.x,
            y: c.y,
            node: c.node,
            heading_to: c.next,
            speed_mps: c.speed_mps,
        })
    }
}

/// Reads the driving distance from the car to every junction (an on-board navigator with the
/// town map). A moving car first finishes its street. Unreachable junctions read infinity.
#[derive(Copy, Clone, Debug, Default)]
pub struct Navigator;

impl Sensor<Town> for Navigator {
    type Reading = Vec<f64>;
    fn read(&self, w: &Town, me: EntityId, _: &mut Probe<'_>) -> Vec<f64> {
        match w.cars.get(me) {
            Some(Car {
                next: Some(n),
                edge_m,
                progress_m,
                ..
            }) => distances(&w.streets, &[(*n, edge_m - progress_m)]),
            Some(c) => distances(&w.streets, &[(c.node, 0.0)]),
            None => vec![f64::INFINITY; w.streets.node_count()],
        }
    }
}

/// Why [`GoToNode`] refused a command.
#[derive(Copy, Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GoToError {
    /// The commanding entity has no car body.
    #[error("entity {0} has no car")]
    NoCar(EntityId),
    /// The goal is not a junction of the town.
    #[error("junction {0:?} does not exist")]
    NoSuchJunction(NodeId),
    /// No street leads there.
    #[error("junction {0:?} cannot be reached")]
    Unreachable(NodeId),
}

/// Drives the car to a junction along the shortest route, over time: the car moves at its
/// speed, junction by junction, and its agent receives [`Event::AtNode`] at each (with
/// `goal: true` at the last). A new command replaces the route; a moving car first finishes
/// the street it is on (no U-turns).
#[derive(Copy, Clone, Debug, Default)]
pub struct GoToNode;

impl Actuator<Town, Event> for GoToNode {
    type Command = NodeId;
    type Error = GoToError;
    fn actuate(
        &self,
        w: &mut Town,
        me: EntityId,
        goal: NodeId,
        fx: &mut Effects<'_, Event>,
    ) -> Result<(), GoToError> {
        let c = w.cars.get(me).ok_or(GoToError::NoCar(me))?;
        if w.streets.node(goal).is_none() {
            return Err(GoToError::NoSuchJunction(goal));
        }
        let from = c.next.unwrap_or(c.node);
        let (_, path) = w
            .streets
            .shortest_path(from, goal)
            .ok_or(GoToError::Unreachable(goal))?;
        let parked = c.next.is_none();
        if parked && path.len() == 1 {
            // Already there: a visit now.
            w.record_visit(goal, fx.now());
            fx.schedule_in(
                SimDuration::ZERO,
                Target::Entity(me),
                Event::AtNode {
                    node: goal,
                    goal: true,
                },
            );
            return Ok(());
        }
        let mut route: Vec<NodeId> = path[1..].iter().rev().copied().collect();
        let first = match route.pop() {
            Some(n) if parked => {
                let len = w
                    .streets
                    .edge_length(from, n)
                    .ok_or(GoToError::Unreachable(goal))?;
                Some((n, len))
            }
            Some(n) => {
                route.push(n);
                None
            }
            None => None,
        };
        let mut wake = None;
        w.cars.update(me, |c| {
            c.route = route;
            if let Some((n, len)) = first {
                c.next = Some(n);
                c.edge_m = len;
                c.progress_m = 0.0;
                c.target_m = 0.0;
            }
            if !c.moving {
                wake = c.plan_step();
            }
        });
        if let Some(delay) = wake {
            fx.schedule_in(delay, Target::Env, Event::Tick(me));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TownConfig;
    use crate::town::generate;
    use rand::SeedableRng;
    use vitro::event::{EventId, EventQueue, Schedule, ScheduleError};
    use vitro::rng::{Owner, RngStreams};

    /// A bare event loop for driving the world without agents.
    struct Loop(EventQueue<(Target, Event)>);
    impl Schedule<Event> for Loop {
        fn now(&self) -> SimTime {
            self.0.now()
        }
        fn schedule_at(
            &mut self,
            at: SimTime,
            t: Target,
            e: Event,
        ) -> Result<EventId, ScheduleError> {
            self.0.push(at, (t, e))
        }
        fn cancel(&mut self, id: EventId) -> bool {
            self.0.cancel(id)
        }
    }

    fn town() -> Town {
        let cfg = TownConfig {
            columns: 3,
            rows: 2,
            block_m: 100.0,
            diagonal_share: 0.0,
            missing_blocks: 0,
        };
        Town::new(generate(
            &cfg,
            &mut rand_chacha::ChaCha8Rng::seed_from_u64(0),
        ))
    }

    #[test]
    fn car_reaches_goal_exactly_and_logs_visits() {
        let mut w = town();
        let car = EntityId(0);
        w.park(car, NodeId(0), 8.0, SimDuration::from_secs(1))
            .unwrap();
        let mut rngs = RngStreams::new(0);
        let mut q = Loop(EventQueue::new());
        let mut fx = Effects::new(Owner::Entity(car), &mut rngs, &mut q);
        // Junction 5 is the north-east corner: 300 m away.
        GoToNode.actuate(&mut w, car, NodeId(5), &mut fx).unwrap();
        let mut at_nodes = Vec::new();
        while let Some(p) = q.0.pop() {
            match p.payload {
                (Target::Env, Event::Tick(c)) => {
                    let mut fx = Effects::new(Owner::Global, &mut rngs, &mut q);
                    w.on_tick(c, &mut fx);
                }
                (Target::Entity(_), Event::AtNode { node, goal }) => {
                    at_nodes.push((p.time, node, goal))
                }
                other => panic!("unexpected {other:?}"),
            }
        }
        assert_eq!(at_nodes.len(), 3);
        let last = at_nodes[2];
        assert_eq!(
            (last.0, last.1, last.2),
            (SimTime::from_nanos(37_500_000_000), NodeId(5), true)
        );
        assert!(!at_nodes[0].2);
        assert_eq!(w.position(car), Some((200.0, 100.0)));
        assert_eq!(w.visit_log(NodeId(5)).visits, 1);
        assert_eq!(w.visit_log(NodeId(0)).visits, 0);
        // Halfway: a second car's gps reads continuous positions.
        let car2 = EntityId(1);
        let mut q = Loop(EventQueue::new());
        w.park(car2, NodeId(0), 10.0, SimDuration::from_secs(3))
            .unwrap();
        let mut fx = Effects::new(Owner::Entity(car2), &mut rngs, &mut q);
        GoToNode.actuate(&mut w, car2, NodeId(1), &mut fx).unwrap();
        let p = q.0.pop().unwrap();
        let mut fx = Effects::new(Owner::Global, &mut rngs, &mut q);
        w.on_tick(car2, &mut fx);
        assert_eq!(p.time, SimTime::from_secs(3));
        assert_eq!(w.position(car2), Some((30.0, 0.0)));
        let mut probe = Probe::new(p.time, car2, &mut rngs);
        let d = Navigator.read(&w, car2, &mut probe);
        assert_eq!((d[1], d[0]), (70.0, 170.0));
    }

    #[test]
    fn refusals_are_typed() {
        let mut w = town();
        let mut rngs = RngStreams::new(0);
        let mut q = Loop(EventQueue::new());
        let mut fx = Effects::new(Owner::Global, &mut rngs, &mut q);
        let car = EntityId(0);
        assert_eq!(
            GoToNode.actuate(&mut w, car, NodeId(1), &mut fx),
            Err(GoToError::NoCar(car))
        );
        w.park(car, NodeId(0), 1.0, SimDuration::from_secs(1))
            .unwrap();
        assert_eq!(
            GoToNode.actuate(&mut w, car, NodeId(99), &mut fx),
            Err(GoToError::NoSuchJunction(NodeId(99)))
        );
    }
}
