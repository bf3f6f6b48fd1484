//! # vitro-behaviour: controllers any mission can give its agents
//!
//! On the tactical environment of `vitro-tactical`, reusable behaviours. Each is written
//! against a top actuator or an autopilot only, never against a storage, so it runs
//! unchanged at every level of fidelity (the pattern of `vitro`'s `examples/layered.rs`):
//!
//! - [`route`]: visit a list of nodes ([`VisitNodes`](route::VisitNodes)) through any
//!   goal-node actuator, or fly a list of legs ([`FlightMission`](route::FlightMission))
//!   through any autopilot;
//! - [`belief`]: what an agent believes about where the others are, from its own camera and
//!   the radio's position and contact reports, dead-reckoned and aged;
//! - [`formation`]: a squad that walks in formation, its leader and members programmed in
//!   the rule language of `vitro_algo::rules`.
//!
//! The mission-specific controllers (the evacuation's patrol, hunt and cover agents) live in
//! their mission's crate; the algorithms they play (the patrol game, the pursuit search, plan
//! repair) are in `vitro-algo`, where any mission reuses them.
//!
//! ## One behaviour, three levels
//!
//! [`VisitNodes`](route::VisitNodes) drives a car across the town through the discrete, the
//! interpolated and the physical level's `GoToNode`, unchanged; only the level the body is
//! placed at and the actuator it is given differ.
//!
//! ```
//! use vitro::prelude::*;
//! use vitro_behaviour::route::VisitNodes;
//! use vitro_tactical::actuate::MoveError;
//! use vitro_tactical::actuate::ground::{discrete, interpolated, physical};
//! use vitro_tactical::arena::{Arena, Ev};
//! use vitro_tactical::entity::Level;
//! use vitro_tactical::entity::route::Track;
//! use vitro_tactical::model::Tactical;
//! use vitro_tactical::setup::Setup;
//! use vitro_tactical::types::GroundKind;
//!
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
//!     let car = sim.add("car", VisitNodes::new(vec![to], goto)).unwrap();
//!     sim.env_mut().add_vehicle(car.id(), GroundKind::Car, level, from, heading).unwrap();
//!     sim.schedule(SimTime::ZERO, Target::Entity(car.id()), Ev::Start).unwrap();
//!     sim.run_until(SimTime::from_secs(1200));
//!     let brain = sim.agent(&car).unwrap();
//!     brain.log.last().map(|&(t, _)| t.as_secs_f64()).unwrap()
//! }
//!
//! let d = arrival(&setup, Level::Discrete, discrete::GoToNode, from, to);
//! let i = arrival(&setup, Level::Interpolated, interpolated::GoToNode, from, to);
//! let p = arrival(&setup, Level::Physical, physical::GoToNode, from, to);
//! assert!((i - d).abs() <= 0.02 * d + 2.0, "{i} vs {d}");
//! assert!((p - d).abs() <= 0.12 * d + 5.0, "{p} vs {d}");
//! ```

pub mod belief;
pub mod formation;
pub mod route;
