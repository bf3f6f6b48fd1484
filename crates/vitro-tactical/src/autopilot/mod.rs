//! Autopilots: straight flight and waypoint following, for both aircraft types at both
//! levels. Each level's `Autopilot` takes the same [`FlightCommand`](crate::entity::air::FlightCommand) and answers with
//! [`Ev::Waypoint`] as each waypoint is reached, so one mission (e.g.
//! `vitro_behaviour::route::FlightMission`) flies any of them unchanged.
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
mod engage;
pub mod lattice;
pub mod plan;
pub mod vtol;

use crate::arena::{Arena, Clock, Ev};
use vitro::entity::EntityId;
use vitro::env::Effects;

pub use crate::entity::air::FlightCommand as Command;
pub use engage::FlyError;
pub(crate) use engage::{engage, reached, validate};

/// One step of the flight clock: every kinematic fixed-wing aircraft and every dynamic
/// helicopter. The clock keeps running while there is any (they cannot stop flying).
pub fn tick_flight(w: &mut Arena, fx: &mut Effects<'_, Ev>) {
    let dt = w.steps.flight.as_secs_f64();
    ctol::step_all(w, dt, fx);
    vtol::step_all(w, dt, fx);
    crash(w);
    let busy = !w.ctol.is_empty() || !w.vtol.is_empty();
    w.keep(Clock::Flight, busy, fx);
}

/// How far above an aircraft a roof is looked for, metres.
const ROOF_SEARCH_M: f64 = 300.0;

/// Aircraft at a continuous level whose body went below the ground or into a building (a
/// roof right above it) crash: the body leaves the flight storages (its autopilot with it)
/// and, if it has a condition, it is [`Status::Down`](crate::condition::Status::Down) —
/// an outcome the mission's referee counts. In id order.
fn crash(w: &mut Arena) {
    let below = |p: [f64; 3]| {
        w.site.ground([p[0], p[1]]).is_some_and(|g| p[2] < g)
            || !w.site.los.visible(p, [p[0], p[1], p[2] + ROOF_SEARCH_M])
    };
    let mut down: Vec<EntityId> = w
        .ctol
        .iter()
        .filter(|(_, b)| below(b.pos))
        .map(|(id, _)| id)
        .collect();
    down.extend(
        w.vtol
            .iter()
            .filter(|(_, b)| below(b.pos))
            .map(|(id, _)| id),
    );
    down.sort();
    for id in down {
        w.ctol.remove(id);
        w.vtol.remove(id);
        w.pilots.remove(id);
        w.conditions
            .update(id, |c| c.status = crate::condition::Status::Down);
    }
}

/// The environment's side of a lattice maneuver: the aircraft reaches its next cell and
/// starts the next maneuver.
pub fn on_maneuver(w: &mut Arena, who: EntityId, fx: &mut Effects<'_, Ev>) {
    lattice::arrive(w, who, fx);
}
