//! Layered actuators: one controller runs unchanged over two different storages.
//!
//! The `Patrol` controller is written against a top-level actuator whose command is "go to
//! this node" and an `Arrived` event. It runs here over two worlds:
//!
//! - **discrete**: a car is a node of the street graph; `GoToNodeDiscrete` writes the goal node
//!   into the storage after the shortest-path travel time (a delayed actuator effect);
//! - **continuous**: a car is a body with x, y, heading and speed; `GoToNodeContinuous` plans
//!   the route and drives the lower actuator `MoveInDirection` waypoint by waypoint, while the
//!   environment integrates motion in fixed physics steps.
//!
//! Run: `cargo run -p vitro --example layered`. It prints both trajectories' arrival times,
//! which agree within one physics step per leg.

use serde::{Deserialize, Serialize};
use std::convert::Infallible;
use vitro::prelude::*;

/// Events shared by both worlds.
#[derive(Clone, Debug, Serialize, Deserialize)]
enum Ev {
    /// Starts a controller.
    Start,
    /// Tells a controller it reached a node.
    Arrived(NodeId),
    /// Discrete world: the delayed effect of GoToNode.
    Reach(EntityId, NodeId),
    /// Continuous world: one physics step.
    Physics,
}

/// The street graph: node positions in metres.
fn streets() -> GraphStorage<(f64, f64), ()> {
    let mut g = GraphStorage::default();
    let pts: [(f64, f64); 5] = [
        (0.0, 0.0),
        (100.0, 0.0),
        (100.0, 100.0),
        (0.0, 100.0),
        (200.0, 50.0),
    ];
    let n: Vec<NodeId> = pts.iter().map(|&p| g.add_node(p)).collect();
    for (a, b) in [(0, 1), (1, 2), (2, 3), (3, 0), (1, 4), (4, 2)] {
        let (pa, pb) = (pts[a], pts[b]);
        let len = libm::hypot(pa.0 - pb.0, pa.1 - pb.1);
        g.add_undirected_edge(n[a], n[b], len, ());
    }
    g
}

const SPEED: f64 = 10.0; // m/s

// ---------------------------------------------------------------- the controller

/// Visits its route's nodes in a loop, forever. Knows nothing of the storage underneath.
struct Patrol<A> {
    route: Vec<NodeId>,
    next: usize,
    goto: A,
    log: Vec<(SimTime, NodeId)>,
}

impl<M, A> Agent<M> for Patrol<A>
where
    M: Model<Event = Ev, Agent = Self>,
    A: Actuator<M::Env, Ev, Command = NodeId, Error = Infallible>,
{
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        match input {
            Input::Event(Ev::Arrived(n)) => self.log.push((cx.now(), *n)),
            Input::Event(Ev::Start) => {}
            _ => return,
        }
        let goal = self.route[self.next % self.route.len()];
        self.next += 1;
        let Ok(()) = cx.act(&self.goto, goal);
    }
}

// ---------------------------------------------------------------- discrete world

struct Discrete {
    graph: GraphStorage<(f64, f64), ()>,
    at: EntityStorage<NodeId>,
}

/// GoToNode on the discrete storage: the entity appears at the goal after the travel time.
struct GoToNodeDiscrete;

impl Actuator<Discrete, Ev> for GoToNodeDiscrete {
    type Command = NodeId;
    type Error = Infallible;
    fn actuate(
        &self,
        w: &mut Discrete,
        me: EntityId,
        goal: NodeId,
        fx: &mut Effects<Ev>,
    ) -> Result<(), Infallible> {
        let from = w.at.get(me).copied().unwrap_or(goal);
        let len = w.graph.shortest_path(from, goal).map_or(0.0, |(l, _)| l);
        fx.schedule_in(
            SimDuration::from_secs_f64(len / SPEED),
            Target::Env,
            Ev::Reach(me, goal),
        );
        Ok(())
    }
}

struct DiscreteModel;
impl Model for DiscreteModel {
    type Env = Discrete;
    type Event = Ev;
    type Msg = ();
    type Agent = Patrol<GoToNodeDiscrete>;
    fn on_env_event(w: &mut Discrete, ev: &Ev, fx: &mut Effects<Ev>) {
        if let Ev::Reach(who, node) = *ev {
            w.at.insert(who, node);
            fx.schedule_in(SimDuration::ZERO, Target::Entity(who), Ev::Arrived(node));
        }
    }
    fn state_digest(w: &Discrete) -> u64 {
        w.at.digest()
    }
}

// ---------------------------------------------------------------- continuous world

#[derive(Clone, Debug, Default, Serialize)]
struct Body {
    x: f64,
    y: f64,
    heading: f64,
    speed: f64,
    /// Remaining waypoints of the route being followed (GoToNode's own state).
    waypoints: Vec<NodeId>,
}

struct Continuous {
    graph: GraphStorage<(f64, f64), ()>,
    bodies: EntityStorage<Body>,
}

const DT: SimDuration = SimDuration::from_millis(100);

/// The lower actuator: head towards a point at a speed.
struct MoveInDirection;

impl Actuator<Continuous, Ev> for MoveInDirection {
    type Command = (f64, f64, f64); // x, y, speed
    type Error = Infallible;
    fn actuate(
        &self,
        w: &mut Continuous,
        me: EntityId,
        (x, y, speed): (f64, f64, f64),
        _: &mut Effects<Ev>,
    ) -> Result<(), Infallible> {
        w.bodies.update(me, |b| {
            b.heading = libm::atan2(y - b.y, x - b.x);
            b.speed = speed;
        });
        Ok(())
    }
}

/// The top actuator on the continuous storage: plans the route, then drives MoveInDirection.
struct GoToNodeContinuous;

impl Actuator<Continuous, Ev> for GoToNodeContinuous {
    type Command = NodeId;
    type Error = Infallible;
    fn actuate(
        &self,
        w: &mut Continuous,
        me: EntityId,
        goal: NodeId,
        fx: &mut Effects<Ev>,
    ) -> Result<(), Infallible> {
        let Some(body) = w.bodies.get(me) else {
            return Ok(());
        };
        let from = nearest_node(&w.graph, body.x, body.y);
        let mut path = w.graph.shortest_path(from, goal).map_or(vec![], |(_, p)| p);
        path.reverse(); // pop() gives the next waypoint
        w.bodies.update(me, |b| b.waypoints = path);
        steer_to_next(w, me, fx);
        Ok(())
    }
}

fn nearest_node(g: &GraphStorage<(f64, f64), ()>, x: f64, y: f64) -> NodeId {
    (0..g.node_count() as u32)
        .map(NodeId)
        .min_by(|&a, &b| {
            let d = |n| {
                g.node(n)
                    .map_or(f64::INFINITY, |&(px, py)| libm::hypot(px - x, py - y))
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap_or_default()
}

fn steer_to_next(w: &mut Continuous, me: EntityId, fx: &mut Effects<Ev>) {
    let next = w.bodies.get(me).and_then(|b| b.waypoints.last().copied());
    match next.and_then(|n| w.graph.node(n).copied()) {
        Some((x, y)) => {
            let Ok(()) = MoveInDirection.actuate(w, me, (x, y, SPEED), fx);
        }
        None => {
            w.bodies.update(me, |b| b.speed = 0.0);
        }
    }
}

struct ContinuousModel;
impl Model for ContinuousModel {
    type Env = Continuous;
    type Event = Ev;
    type Msg = ();
    type Agent = Patrol<GoToNodeContinuous>;
    fn on_env_event(w: &mut Continuous, ev: &Ev, fx: &mut Effects<Ev>) {
        if !matches!(ev, Ev::Physics) {
            return;
        }
        let dt = DT.as_secs_f64();
        let ids: Vec<EntityId> = w.bodies.iter().map(|(id, _)| id).collect();
        for id in ids {
            let Some(b) = w.bodies.get(id).cloned() else {
                continue;
            };
            let Some(&wp) = b.waypoints.last() else {
                continue;
            };
            let Some(&(tx, ty)) = w.graph.node(wp) else {
                continue;
            };
            let dist = libm::hypot(tx - b.x, ty - b.y);
            if dist <= b.speed * dt {
                // Reached the waypoint: snap to it, then steer to the next or report arrival.
                w.bodies.update(id, |b| {
                    b.x = tx;
                    b.y = ty;
                    b.waypoints.pop();
                });
                steer_to_next(w, id, fx);
                if w.bodies.get(id).is_some_and(|b| b.waypoints.is_empty()) {
                    fx.schedule_in(SimDuration::ZERO, Target::Entity(id), Ev::Arrived(wp));
                }
            } else {
                w.bodies.update(id, |b| {
                    b.x += b.speed * dt * libm::cos(b.heading);
                    b.y += b.speed * dt * libm::sin(b.heading);
                });
            }
        }
        fx.schedule_in(DT, Target::Env, Ev::Physics);
    }
    fn state_digest(w: &Continuous) -> u64 {
        w.bodies.digest()
    }
}

// ---------------------------------------------------------------- run both

fn route() -> Vec<NodeId> {
    [2, 4, 0, 3].map(NodeId).to_vec()
}

/// Runs the patrol on both worlds; returns each one's arrival log.
#[allow(clippy::type_complexity)]
fn run_both(end: SimTime) -> (Vec<(SimTime, NodeId)>, Vec<(SimTime, NodeId)>) {
    let mut d = Simulation::<DiscreteModel>::new(
        Discrete {
            graph: streets(),
            at: EntityStorage::default(),
        },
        1,
    );
    let car = d
        .add_agent(
            "car",
            Patrol {
                route: route(),
                next: 0,
                goto: GoToNodeDiscrete,
                log: vec![],
            },
        )
        .expect("fresh name");
    d.env_mut().at.insert(car, NodeId(0));
    d.schedule(SimTime::ZERO, Target::Entity(car), Ev::Start)
        .expect("t=0");
    d.run_until(end);

    let mut c = Simulation::<ContinuousModel>::new(
        Continuous {
            graph: streets(),
            bodies: EntityStorage::default(),
        },
        1,
    );
    let car2 = c
        .add_agent(
            "car",
            Patrol {
                route: route(),
                next: 0,
                goto: GoToNodeContinuous,
                log: vec![],
            },
        )
        .expect("fresh name");
    c.env_mut().bodies.insert(car2, Body::default());
    c.schedule(SimTime::ZERO, Target::Entity(car2), Ev::Start)
        .expect("t=0");
    c.schedule(SimTime::ZERO, Target::Env, Ev::Physics)
        .expect("t=0");
    c.run_until(end);
    println!(
        "discrete: {} events, trace {:016x}; continuous: {} events, trace {:016x}",
        d.events_fired(),
        d.trace_hash(),
        c.events_fired(),
        c.trace_hash()
    );
    (
        d.agent(car).map(|a| a.log.clone()).unwrap_or_default(),
        c.agent(car2).map(|a| a.log.clone()).unwrap_or_default(),
    )
}

fn main() {
    let (ld, lc) = run_both(SimTime::from_secs(120));
    println!("node  discrete_s  continuous_s");
    for ((td, nd), (tc, _)) in ld.iter().zip(&lc) {
        println!(
            "{:>4}  {:>10.1}  {:>12.1}",
            nd.0,
            td.as_secs_f64(),
            tc.as_secs_f64()
        );
    }
}

#[test]
fn one_controller_two_storages_same_decisions() {
    let (ld, lc) = run_both(SimTime::from_secs(120));
    assert!(
        ld.len() >= 8,
        "the discrete car completed two loops: {ld:?}"
    );
    assert_eq!(ld.len(), lc.len(), "same number of arrivals");
    for (leg, ((td, nd), (tc, nc))) in ld.iter().zip(&lc).enumerate() {
        assert_eq!(nd, nc, "same controller, same goals");
        // Each leg of the continuous car may overrun the exact time by up to a physics step
        // per waypoint: at most 3 waypoints per leg here.
        let slack = DT.as_secs_f64() * 3.0 * (leg as f64 + 1.0);
        let dt = tc.as_secs_f64() - td.as_secs_f64();
        assert!((0.0..=slack).contains(&dt), "leg {leg}: {td} vs {tc}");
    }
}
