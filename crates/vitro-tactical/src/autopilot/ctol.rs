//! The fixed-wing kinematic level's autopilot.
//!
//! Guidance, at every flight step:
//! - heading: a yaw rate proportional to the heading error (towards the commanded course, or
//!   the bearing of the next waypoint), limited to what the bank limit gives at the current
//!   speed. When the waypoint lies inside the circle the aircraft would turn on, turning
//!   cannot reach it: it flies straight until the point is outside the circle, then turns.
//! - altitude: a flight-path angle proportional to the altitude error over the speed (a
//!   climb rate of `altitude error / 5 s`), limited by the type;
//! - airspeed: the commanded one, within the envelope.
//!
//! A waypoint counts as reached within [`ACCEPT`] metres in plan. After the last one the
//! aircraft flies on straight along its heading (it cannot stop).

use super::{FlyError, engage, reached, validate};
use crate::arena::{Arena, Clock, Ev};
use crate::entity::air::FlightCommand;
use crate::entity::air::ctol::{CtolBody, FlyCmd};
use crate::entity::route::wrap_angle;
use crate::types::{CtolType, G};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects};

/// Waypoint acceptance radius, metres (in plan).
pub const ACCEPT: f64 = 15.0;
/// Heading gain, 1/s.
const K_HEADING: f64 = 1.0;
/// Altitude gain, 1/s.
const K_ALTITUDE: f64 = 0.2;

/// FlyKinematic: the lower actuator, commands yaw rate, flight-path angle and airspeed.
#[derive(Copy, Clone, Debug, Default)]
pub struct FlyKinematic;

impl Actuator<Arena, Ev> for FlyKinematic {
    type Command = FlyCmd;
    type Error = FlyError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: FlyCmd,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), FlyError> {
        if !w.ctol.update(me, |b| b.cmd = cmd) {
            return Err(FlyError::NoBody(me));
        }
        w.wake(Clock::Flight, fx);
        Ok(())
    }
}

/// The kinematic-level autopilot: straight flight and waypoints through [`FlyKinematic`].
#[derive(Copy, Clone, Debug, Default)]
pub struct Autopilot;

impl Actuator<Arena, Ev> for Autopilot {
    type Command = FlightCommand;
    type Error = FlyError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: FlightCommand,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), FlyError> {
        validate(&cmd)?;
        if !w.ctol.contains(me) {
            return Err(FlyError::NoBody(me));
        }
        engage(w, me, cmd);
        w.wake(Clock::Flight, fx);
        Ok(())
    }
}

/// The guidance law: the kinematic command towards `heading` (or, with `point`, that
/// waypoint) at `altitude` and `speed`.
pub fn guide(
    b: &CtolBody,
    ty: &CtolType,
    course: f64,
    point: Option<[f64; 3]>,
    altitude: f64,
    speed: f64,
) -> FlyCmd {
    let max_rate = b.max_yaw_rate(ty);
    let want = match point {
        Some(p) => libm::atan2(p[1] - b.pos[1], p[0] - b.pos[0]),
        None => course,
    };
    let err = wrap_angle(want - b.heading);
    let mut yaw_rate = (K_HEADING * err).clamp(-max_rate, max_rate);
    if let Some(p) = point {
        // The centre of the circle it would turn on, on the side of the turn.
        let r = b.speed / max_rate;
        let side = if err >= 0.0 { 1.0 } else { -1.0 };
        let n = b.heading + side * std::f64::consts::FRAC_PI_2;
        let c = [b.pos[0] + r * libm::cos(n), b.pos[1] + r * libm::sin(n)];
        if libm::hypot(p[0] - c[0], p[1] - c[1]) < r && err.abs() > 0.1 {
            yaw_rate = 0.0;
        }
    }
    let gmax = ty.max_flight_path_deg.to_radians();
    let climb = K_ALTITUDE * (altitude - b.pos[2]);
    let flight_path = libm::asin((climb / b.speed).clamp(-1.0, 1.0)).clamp(-gmax, gmax);
    FlyCmd {
        yaw_rate,
        flight_path,
        airspeed: speed.clamp(ty.min_speed, ty.max_speed),
    }
}

/// One flight step of every kinematic fixed-wing aircraft.
pub(crate) fn step_all(w: &mut Arena, dt: f64, fx: &mut Effects<'_, Ev>) {
    let ids: Vec<EntityId> = w.ctol.iter().map(|(id, _)| id).collect();
    for id in ids {
        let Some(b) = w.ctol.get(id).cloned() else {
            continue;
        };
        let ty = w.types.ctol(b.kind).clone();
        if let Some(mut pilot) = w.pilots.get(id).cloned() {
            let mut changed = false;
            if let FlightCommand::Waypoints { points, speed } = &pilot.cmd {
                if let Some(p) = points.get(pilot.next)
                    && libm::hypot(p[0] - b.pos[0], p[1] - b.pos[1]) <= ACCEPT
                {
                    reached(id, pilot.next, fx);
                    pilot.next += 1;
                    changed = true;
                }
                if pilot.next >= points.len() {
                    let altitude = points.last().map_or(b.pos[2], |p| p[2]);
                    pilot.cmd = FlightCommand::Straight {
                        heading: b.heading,
                        altitude,
                        speed: *speed,
                    };
                    changed = true;
                }
            }
            let cmd = match &pilot.cmd {
                FlightCommand::Straight {
                    heading,
                    altitude,
                    speed,
                } => guide(
                    &b,
                    &ty,
                    *heading,
                    None,
                    *altitude,
                    speed.unwrap_or(ty.cruise_speed),
                ),
                FlightCommand::Waypoints { points, speed } => {
                    let p = points[pilot.next.min(points.len() - 1)];
                    guide(
                        &b,
                        &ty,
                        b.heading,
                        Some(p),
                        p[2],
                        speed.unwrap_or(ty.cruise_speed),
                    )
                }
            };
            if changed {
                w.pilots.insert(id, pilot);
            }
            let _ = FlyKinematic.actuate(w, id, cmd, fx);
        }
        w.ctol.update(id, |b| b.step(&ty, dt));
    }
}

/// The turn rate a coordinated turn at bank `bank` (radians) and speed `v` gives, rad/s:
/// `g tan(bank) / v`.
pub fn turn_rate(v: f64, bank: f64) -> f64 {
    G * libm::tan(bank) / v
}
