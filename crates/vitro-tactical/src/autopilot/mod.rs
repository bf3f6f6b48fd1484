//! Autopilots: straight flight and waypoint following, for both aircraft types at both
//! levels. Each level's `Autopilot` takes the same [`FlightCommand`] and answers with
//! [`Ev::Waypoint`] as each waypoint is reached, so one mission (e.g.
//! [`FlightMission`](crate::mission::FlightMission)) flies any of them unchanged.
//!
//! | aircraft | level | chain |
//! |---|---|---|
//! | fixed-wing | discrete | [`lattice::Autopilot`] → maneuvers planned by A* on the lattice |
//! | fixed-wing | kinematic | [`ctol::Autopilot`] → [`ctol::FlyKinematic`] (yaw rate, flight path, airspeed) |
//! | helicopter | discrete | [`lattice::Autopilot`] → moves to neighbouring cells, or hover |
//! | helicopter | dynamic | [`vtol::Autopilot`] → [`vtol::HoldVelocity`] → [`vtol::RotorControls`] |
//!
//! The continuous levels advance on the arena's flight clock ([`tick_flight`]); a
//! helicopter's inner loops and dynamics run several sub-steps per flight step.

pub mod ctol;
pub mod lattice;
pub mod vtol;

use crate::arena::{Arena, Clock, Ev};
use crate::entity::air::{FlightCommand, Pilot};
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::Effects;
use vitro::event::Target;
use vitro::time::SimDuration;

pub use crate::entity::air::FlightCommand as Command;

/// Why an autopilot refused a command.
#[derive(Clone, Debug, PartialEq, thiserror::Error, Serialize, Deserialize)]
pub enum FlyError {
    /// The entity has no aircraft this autopilot flies.
    #[error("entity {0:?} has no aircraft this autopilot flies")]
    NoBody(EntityId),
    /// A waypoint command without waypoints.
    #[error("a waypoint command needs at least one waypoint")]
    NoWaypoints,
    /// A number is not finite.
    #[error("the command holds a value that is not a finite number")]
    NotFinite,
}

/// Checks a command before an autopilot takes it.
pub(crate) fn validate(cmd: &FlightCommand) -> Result<(), FlyError> {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    match cmd {
        FlightCommand::Straight {
            heading,
            altitude,
            speed,
        } => {
            if !finite(&[*heading, *altitude, speed.unwrap_or(0.0)]) {
                return Err(FlyError::NotFinite);
            }
        }
        FlightCommand::Waypoints { points, speed } => {
            if points.is_empty() {
                return Err(FlyError::NoWaypoints);
            }
            if !points.iter().all(|p| finite(p)) || !speed.unwrap_or(0.0).is_finite() {
                return Err(FlyError::NotFinite);
            }
        }
    }
    Ok(())
}

/// Stores the command as the aircraft's pilot state.
pub(crate) fn engage(w: &mut Arena, me: EntityId, cmd: FlightCommand) {
    w.pilots.insert(
        me,
        Pilot {
            cmd,
            next: 0,
            plan: Vec::new(),
        },
    );
}

/// Tells `who` it reached waypoint `i`, now.
pub(crate) fn reached(who: EntityId, i: usize, fx: &mut Effects<'_, Ev>) {
    fx.schedule_in(
        SimDuration::ZERO,
        Target::Entity(who),
        Ev::Waypoint(i as u32),
    );
}

/// One step of the flight clock: every kinematic fixed-wing aircraft and every dynamic
/// helicopter. The clock keeps running while there is any (they cannot stop flying).
pub fn tick_flight(w: &mut Arena, fx: &mut Effects<'_, Ev>) {
    let dt = w.steps.flight.as_secs_f64();
    ctol::step_all(w, dt, fx);
    vtol::step_all(w, dt, fx);
    let busy = !w.ctol.is_empty() || !w.vtol.is_empty();
    w.keep(Clock::Flight, busy, fx);
}

/// The environment's side of a lattice maneuver: the aircraft reaches its next cell and
/// starts the next maneuver.
pub fn on_maneuver(w: &mut Arena, who: EntityId, fx: &mut Effects<'_, Ev>) {
    lattice::arrive(w, who, fx);
}
