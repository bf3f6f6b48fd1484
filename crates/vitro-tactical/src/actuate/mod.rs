//! Actuators of ground vehicles and troopers, layered as the design has it:
//!
//! - vehicles: [`ground`] `GoToNode` → `MoveInDirection` → `SteerAndAccelerate`
//!   (the last at the physical level only);
//! - troopers: [`troop`] `WalkToNode` → `MoveAndTurn`.
//!
//! The top actuators take a goal node and answer with [`Ev::Arrived`] when the body is there,
//! at every level, so a controller written against them (e.g.
//! `vitro_behaviour::route::VisitNodes`) runs unchanged whichever storage is underneath.
//! A goal is taken only at rest (between trips): a body under way refuses with
//! [`MoveError::UnderWay`].
//!
//! At the discrete level a trip is a chain of [`Ev::Hop`] events, one per node, at the times
//! the route's speed profile gives; at the continuous levels the top actuator drives the
//! lower ones at every fixed step ([`tick_kinematic`], [`tick_physics`]).

pub mod by_level;
pub mod ground;
mod trip;
pub mod troop;

pub use trip::{MoveError, on_hop};
pub(crate) use trip::{arrived, plan, stalled, start_paced_trip, start_trip};

use crate::arena::{Arena, Clock, Ev};
use vitro::env::Effects;

/// One step of the kinematic clock: interpolated vehicles and directed troopers. Keeps the
/// clock running while any of them is under way.
pub fn tick_kinematic(w: &mut Arena, fx: &mut Effects<'_, Ev>) {
    let dt = w.steps.kinematic.as_secs_f64();
    let busy_v = ground::interpolated::step_all(w, dt, fx);
    let busy_t = troop::directed::step_all(w, dt, fx);
    w.keep(Clock::Kinematic, busy_v || busy_t, fx);
}

/// One step of the physics clock: every physical vehicle's GoToNode and controllers, then
/// the rigid-body step. Keeps the clock running while any vehicle is under way or moving.
pub fn tick_physics(w: &mut Arena, fx: &mut Effects<'_, Ev>) {
    let busy = ground::physical::step_all(w, fx);
    w.keep(Clock::Physics, busy, fx);
}
