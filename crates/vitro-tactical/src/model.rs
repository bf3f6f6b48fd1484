//! The tactical model: the [`Arena`] as a `vitro` environment, its agents any
//! [`Controller`]s, its messages the mission's own.
//!
//! [`Tactical<M>`](Tactical) is a [`Model`] whose environment is the arena, whose events
//! are [`Ev`], whose messages are the mission's type `M` and whose agents are boxed
//! [`Controller`]s, so that one simulation can hold controllers of every kind
//! and level (each generic over its top actuator, e.g. `vitro_behaviour`'s
//! `VisitNodes<GoToNode>`); a
//! controller added with [`Simulation::add`](vitro::sim::Simulation::add) is read back by
//! its handle, in its own type. Every mission on the arena runs on this one model, with its
//! own vocabulary: the shared behaviours ask of `M` only the words they speak
//! ([`radio`](crate::radio)), and `M` defaults to the stock [`Basic`].
//! The environment's own events run the levels: discrete hops and maneuvers, and the
//! fixed-step clocks of the continuous levels.
//!
//! ```
//! use std::sync::Arc;
//! use vitro::prelude::*;
//! use vitro_tactical::actuate::ground::discrete::GoToNode;
//! use vitro_tactical::arena::{Arena, Ev};
//! use vitro_tactical::entity::Level;
//! use vitro_tactical::model::{Controller, Tactical};
//! use vitro_tactical::types::GroundKind;
//! # use vitro_site::{map::{MapConfig, TownMap}, site::{Site, SiteConfig}, terrain::Terrain};
//! # let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
//! # let map = TownMap::load(format!("{root}/data/maps/kotka.osm.pbf"), &MapConfig::default()).unwrap();
//! # let terrain = Terrain::load(format!("{root}/data/terrain/valley_64x64_90m.asc")).unwrap();
//! # let site = Arc::new(Site::new(map, terrain, &SiteConfig::default()).unwrap());
//! /// Drives to one node; logs the arrival.
//! struct GoTo { to: NodeId, log: Vec<(SimTime, NodeId)> }
//! impl Controller for GoTo {
//!     fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
//!         match input {
//!             Input::Event(Ev::Start) => cx.act(&GoToNode, self.to).expect("a known node"),
//!             Input::Event(Ev::Arrived(n)) => self.log.push((cx.now(), *n)),
//!             _ => {}
//!         }
//!     }
//! }
//! let arena = Arena::new(site);
//! let drive = &arena.roads.drive;
//! let (a, b) = (drive.nearest_connected([-300.0, 0.0]).unwrap(),
//!               drive.nearest_connected([300.0, 100.0]).unwrap());
//! let mut sim = Simulation::<Tactical>::new(arena, 7);
//! let car = sim.add("car", GoTo { to: b, log: Vec::new() }).unwrap();
//! sim.env_mut().add_vehicle(car.id(), GroundKind::Car, Level::Discrete, a, 0.0).unwrap();
//! sim.schedule(SimTime::ZERO, Target::Entity(car.id()), Ev::Start).unwrap();
//! sim.run_until(SimTime::from_secs(3600));
//! let visit: &GoTo = sim.agent(&car).unwrap();
//! assert_eq!(visit.log.last().map(|&(_, n)| n), Some(b));
//! ```

use crate::arena::{Arena, Clock, Ev};
use crate::radio::{Basic, Message};
use crate::{actuate, autopilot};
use std::any::Any;
use std::marker::PhantomData;
use vitro::entity::EntityId;
use vitro::env::Effects;
use vitro::sim::{Agent, Context, Holds, Input, Model};
use vitro::time::SimTime;

/// The tactical model over the [`Arena`], its messages of type `M` (a mission's vocabulary;
/// the stock [`Basic`] by default).
pub struct Tactical<M = Basic>(PhantomData<fn() -> M>);

/// Access to a controller's concrete type (to read its state after a run).
pub trait AsAny: Any {
    /// The controller as [`Any`], for `downcast_ref`.
    fn as_any(&self) -> &dyn Any;
}

impl<T: Any> AsAny for T {
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// An agent of a tactical model `T` (a [`Tactical<M>`](Tactical), `M` the mission's
/// messages): it senses and acts through the context only. A controller that says nothing,
/// or speaks only shared words, is written once for every mission:
/// `impl<M: Message> Controller<Tactical<M>> for MyController`.
pub trait Controller<T: Model = Tactical>: AsAny {
    /// Reacts to one input.
    fn handle(&mut self, input: Input<'_, T>, cx: &mut Context<'_, T>);
    /// What the agent says it is doing, for viewers and recordings (never read by the
    /// simulation itself).
    fn intention(&self) -> Option<Intention> {
        None
    }
}

/// An agent's statement of what it is doing: a line of text, the steps of its current plan
/// and the path it means to follow.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Intention {
    /// One line, e.g. `"drive to the safehouse (leg 2/5)"`.
    pub text: String,
    /// The steps of its current plan, if it has one.
    pub plan: Vec<String>,
    /// The path it means to follow, world metres.
    pub path: Vec<[f64; 3]>,
    /// The plan as first made, where the current one is a repair of it.
    pub original_plan: Vec<String>,
    /// A belief about something hidden (e.g. where a pursued target may be): world points
    /// with their probabilities.
    pub belief: Vec<([f64; 3], f64)>,
    /// A policy over places (e.g. where a patroller may be now): world points with their
    /// probabilities.
    pub heat: Vec<([f64; 3], f64)>,
}

impl<M: Message> Agent<Tactical<M>> for Box<dyn Controller<Tactical<M>>> {
    fn handle(&mut self, input: Input<'_, Tactical<M>>, cx: &mut Context<'_, Tactical<M>>) {
        (**self).handle(input, cx);
    }
}

/// Any controller goes into the model boxed, and comes back out by its type:
/// [`Simulation::add`](vitro::sim::Simulation::add) returns a handle that
/// [`Simulation::agent`](vitro::sim::Simulation::agent) reads the controller back by.
impl<M: Message, A: Controller<Tactical<M>>> Holds<A> for Box<dyn Controller<Tactical<M>>> {
    fn hold(agent: A) -> Self {
        Box::new(agent)
    }
    fn held(&self) -> Option<&A> {
        (**self).as_any().downcast_ref()
    }
}

impl<M: Message> Model for Tactical<M> {
    type Env = Arena;
    type Event = Ev;
    type Msg = M;
    type Agent = Box<dyn Controller<Tactical<M>>>;

    fn on_env_event(env: &mut Arena, event: &Ev, fx: &mut Effects<'_, Ev>) {
        run_env_event(env, event, fx);
    }

    /// Where a radio is: its entity's body, or the vehicle it rides in.
    fn locate(env: &Arena, who: EntityId, _: SimTime) -> Option<[f64; 3]> {
        env.pose(who)
            .or_else(|| match env.conditions.get(who)?.status {
                crate::condition::Status::Aboard(v) => env.pose(v),
                _ => None,
            })
            .map(|p| p.pos)
    }

    fn state_digest(env: &Arena) -> u64 {
        env.digest()
    }
}

/// What the environment does with its own events (for models that embed the arena in a
/// larger environment and forward its events).
pub fn run_env_event(env: &mut Arena, event: &Ev, fx: &mut Effects<'_, Ev>) {
    match event {
        Ev::Hop(who) => actuate::on_hop(env, *who, fx),
        Ev::Tick(clock) if !env.is_due(*clock, fx) => {} // stale or forged: ignored
        Ev::Tick(Clock::Kinematic) => actuate::tick_kinematic(env, fx),
        Ev::Tick(Clock::Physics) => actuate::tick_physics(env, fx),
        Ev::Tick(Clock::Flight) => autopilot::tick_flight(env, fx),
        Ev::Maneuver(who) => autopilot::on_maneuver(env, *who, fx),
        Ev::Start | Ev::Arrived(_) | Ev::Stalled(..) | Ev::Waypoint(_) => {}
    }
}
