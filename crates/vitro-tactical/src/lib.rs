//! # vitro-tactical: the tactical environment every mission shares
//!
//! On a static site from `vitro-site` (the town, its terrain, line of sight), this crate
//! holds what moves and what senses: entities at several levels of fidelity ([`entity`]:
//! vehicles at nodes, on the ground mesh or as rigid bodies; troopers at nodes or directed;
//! aircraft on lattices, kinematic or with rotor dynamics), with their type parameters from
//! public specifications ([`types`]), live in the [`arena`] (the storages) beside their
//! [`condition`]s; layered actuators ([`actuate`]) and [`autopilot`]s move them, so a
//! controller written against the top actuator runs unchanged at every level of the
//! [`model`]. Agents learn about the [`world`] through [`sensor`]s and talk over the
//! [`radio`]. The abstract levels follow a fitted timing model ([`calibration`]) where a
//! scenario names one; [`setup`] loads a town to run on, and [`scenario`] holds the tables
//! missions share.
//!
//! What is built on the environment lives above it: reusable behaviours (route following,
//! flight missions, formations) in `vitro-behaviour`, the cross-level check in
//! `vitro-check`, the fitting of calibrations in `vitro-calibrate`, and each mission (the
//! evacuation in `vitro-evac`) in a crate of its own.
//!
//! ## One controller, three levels
//!
//! A controller is written against a *top* actuator: for a ground vehicle, `GoToNode`
//! (command: a node; answer: [`arena::Ev::Arrived`]). Each level of the vehicle has its own
//! `GoToNode` over its own storage: [`actuate::ground::discrete`] schedules hops along the
//! route, [`actuate::ground::interpolated`] moves a point on the ground mesh every 0.1 s,
//! [`actuate::ground::physical`] steers a rigid body with engine and brakes. The controller
//! below drives across the town at all three, unchanged; only the level the body is placed
//! at and the actuator it is given differ.
//!
//! ```
//! use vitro::prelude::*;
//! use vitro_tactical::actuate::MoveError;
//! use vitro_tactical::actuate::ground::{discrete, interpolated, physical};
//! use vitro_tactical::arena::{Arena, Ev};
//! use vitro_tactical::entity::Level;
//! use vitro_tactical::entity::route::Track;
//! use vitro_tactical::model::{Controller, Tactical};
//! use vitro_tactical::setup::Setup;
//! use vitro_tactical::types::GroundKind;
//!
//! /// Drives to `to` through the goal-node actuator `goto`; notes when it gets there.
//! struct DriveTo<A> {
//!     to: NodeId,
//!     goto: A,
//!     arrived: Option<SimTime>,
//! }
//!
//! impl<A> Controller for DriveTo<A>
//! where
//!     A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
//! {
//!     fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
//!         match input {
//!             Input::Event(Ev::Start) => cx.act(&self.goto, self.to).expect("a known node"),
//!             Input::Event(Ev::Arrived(n)) if *n == self.to => self.arrived = Some(cx.now()),
//!             _ => {}
//!         }
//!     }
//! }
//!
//! // The town (Kotka, OpenStreetMap) on its terrain, with its street graphs and the
//! // entity types' parameters.
//! let setup = Setup::default_town().unwrap();
//! let drive = &setup.roads.drive;
//! let (from, to) = (drive.nearest_connected([-150.0, -100.0]).unwrap(),
//!                   drive.nearest_connected([150.0, 100.0]).unwrap());
//!
//! /// When a car placed at `level` and driven through `goto` reaches `to`, seconds.
//! fn arrival<A>(setup: &Setup, level: Level, goto: A, from: NodeId, to: NodeId) -> f64
//! where
//!     A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
//! {
//!     // Facing down the first street (a rigid body does not turn on the spot).
//!     let path = setup.roads.drive.path(from, to).unwrap();
//!     let ty = setup.types.ground(GroundKind::Car);
//!     let track = Track::plan_vehicle(&setup.site, &setup.roads.drive, &path, ty, &setup.types.speed_limits);
//!     let heading = track.unwrap().heading_at(0.0);
//!     let mut sim = Simulation::<Tactical>::new(setup.arena(), setup.seed);
//!     // The brain: a handle to it, typed.
//!     let car = sim.add("car", DriveTo { to, goto, arrived: None }).unwrap();
//!     // The body: a row in the storage of `level`.
//!     sim.env_mut().add_vehicle(car.id(), GroundKind::Car, level, from, heading).unwrap();
//!     sim.schedule(SimTime::ZERO, Target::Entity(car.id()), Ev::Start).unwrap();
//!     sim.run_until(SimTime::from_secs(1200));
//!     sim.agent(&car).unwrap().arrived.unwrap().as_secs_f64()
//! }
//!
//! let d = arrival(&setup, Level::Discrete, discrete::GoToNode, from, to);
//! let i = arrival(&setup, Level::Interpolated, interpolated::GoToNode, from, to);
//! let p = arrival(&setup, Level::Physical, physical::GoToNode, from, to);
//! // The discrete level's time is the estimate the others are held to (`vitro-check`).
//! assert!((i - d).abs() <= 0.02 * d + 2.0, "{i} vs {d}");
//! assert!((p - d).abs() <= 0.12 * d + 5.0, "{p} vs {d}");
//! ```
//!
//! ## Where next
//!
//! - Write a controller: implement [`model::Controller`] (sense with `cx.sense`, e.g.
//!   [`arena::OwnPose`]; act with `cx.act` through a top actuator or an [`autopilot`]);
//!   `vitro-behaviour` has the generic ones (`VisitNodes`, `FlightMission`, formations).
//! - Hold it to properties at every level: `vitro-check`; `vitro check levels` runs the
//!   standard ones.
//! - Put it in a mission: the shared scenario tables of [`scenario`], the radio vocabulary of
//!   [`radio`], and the `vitro-mission` traits.
//! - The guide (`docs/guide`) walks through all of it, from a synthetic graph to a batch
//!   experiment.

pub mod actuate;
pub mod arena;
pub mod autopilot;
pub mod calibration;
pub mod condition;
pub mod entity;
pub mod model;
pub mod radio;
#[cfg(feature = "record")]
pub mod record;
pub mod scenario;
pub mod sensor;
pub mod setup;
pub mod types;
pub mod world;
