//! The helicopter dynamic level's autopilot: guidance → velocity hold → rotor controls.
//!
//! - [`Autopilot`] (guidance, every flight step): for waypoints, a velocity towards the next
//!   one whose size lets the helicopter brake to the speed the turn at the waypoint allows
//!   (to a stop at the last one), at the waypoint's altitude, nose along the track; for
//!   straight flight, the commanded course and speed. It drives [`HoldVelocity`].
//! - [`HoldVelocity`] → [`hold`] (every rotor sub-step): a cascaded controller.
//!   Vertical: altitude error → climb rate (limited to the type's) → vertical acceleration
//!   (proportional + integral) → collective (with the tilt compensated).
//!   Horizontal: velocity error → acceleration (proportional + integral, limited to what the
//!   tilt limit gives) → roll and pitch angles → body rates → cyclic, the moments computed
//!   from the airframe's hub and inertia. Yaw: heading error → yaw rate → tail rotor pitch,
//!   with the main rotor's reaction torque fed forward.
//! - [`RotorControls`]: the lowest actuator, the rotor controls themselves.
//!
//! A waypoint counts as reached within [`ACCEPT`] metres: in plan for a waypoint the
//! helicopter flies through, in 3D for the last one, where it stops.

use super::{FlyError, engage, reached, validate};
use crate::arena::{Arena, Clock, Ev};
use crate::entity::air::FlightCommand;
use crate::entity::air::vtol::{Airframe, HoldState, HoldTarget, Rotor, VtolBody};
use crate::entity::route::wrap_angle;
use crate::types::{G, VtolType};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects};

/// Waypoint acceptance radius, metres.
pub const ACCEPT: f64 = 5.0;
/// Altitude → climb rate, 1/s.
const K_Z: f64 = 1.0;
/// Climb-rate error → vertical acceleration, 1/s; and its integral, 1/s².
const K_VZ: f64 = 3.0;
const KI_VZ: f64 = 1.0;
/// Velocity error → acceleration, 1/s; and its integral, 1/s².
const K_V: f64 = 1.2;
const KI_V: f64 = 0.3;
/// Attitude error → body rate, 1/s.
const K_ATT: f64 = 4.0;
/// Body-rate error → angular acceleration, 1/s.
const K_RATE: f64 = 12.0;
/// Heading error → yaw rate, 1/s; largest yaw rate commanded, rad/s.
const K_YAW: f64 = 1.5;
const MAX_YAW_RATE: f64 = 1.0;
/// Rotor damping the airframe model applies (its RATE_DAMPING), compensated here.
const DAMPING: [f64; 3] = [2.0, 2.0, 1.0];

/// RotorControls: sets collective, cyclic and tail rotor pitch.
#[derive(Copy, Clone, Debug, Default)]
pub struct RotorControls;

impl Actuator<Arena, Ev> for RotorControls {
    type Command = Rotor;
    type Error = FlyError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: Rotor,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), FlyError> {
        if !w.vtol.update(me, |b| b.rotor = cmd.clamped()) {
            return Err(FlyError::NoBody(me));
        }
        w.wake(Clock::Flight, fx);
        Ok(())
    }
}

/// HoldVelocity: sets what the inner loops hold (horizontal velocity, altitude, heading);
/// [`hold`] turns it into rotor controls at every sub-step.
#[derive(Copy, Clone, Debug, Default)]
pub struct HoldVelocity;

impl Actuator<Arena, Ev> for HoldVelocity {
    type Command = HoldTarget;
    type Error = FlyError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: HoldTarget,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), FlyError> {
        if !w.vtol.update(me, |b| b.target = cmd) {
            return Err(FlyError::NoBody(me));
        }
        w.wake(Clock::Flight, fx);
        Ok(())
    }
}

/// The dynamic-level autopilot: straight flight and waypoints through [`HoldVelocity`].
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
        if !w.vtol.contains(me) {
            return Err(FlyError::NoBody(me));
        }
        engage(w, me, cmd);
        w.wake(Clock::Flight, fx);
        Ok(())
    }
}

/// The cascaded hold controller: rotor controls and updated integrators for body `b`
/// aiming at `b.target`, over a sub-step of `dt` seconds.
pub fn hold(af: &Airframe, ty: &VtolType, b: &VtolBody, dt: f64) -> (Rotor, HoldState) {
    let t = b.target;
    let [phi, theta, psi] = b.att;
    let mut st = b.hold;
    // Vertical: altitude → climb rate → acceleration.
    let vz_cmd = (K_Z * (t.altitude - b.pos[2])).clamp(-ty.max_climb, ty.max_climb);
    let ez = vz_cmd - b.vel[2];
    st.iz = (st.iz + KI_VZ * ez * dt).clamp(-3.0, 3.0);
    let az = K_VZ * ez + st.iz;
    // Horizontal: velocity → acceleration, within the tilt limit.
    let tilt = ty.max_tilt_deg.to_radians();
    let amax = G * libm::tan(tilt);
    let e = [t.vel[0] - b.vel[0], t.vel[1] - b.vel[1]];
    for (i, ek) in st.ixy.iter_mut().zip(e) {
        *i = (*i + KI_V * ek * dt).clamp(-2.0, 2.0);
    }
    let mut a = [K_V * e[0] + st.ixy[0], K_V * e[1] + st.ixy[1]];
    let n = libm::hypot(a[0], a[1]);
    if n > amax {
        a = [a[0] * amax / n, a[1] * amax / n];
    }
    // Into the heading frame, then attitude: pitch (nose down) forward, roll right side
    // down to the right.
    let (c, s) = (libm::cos(psi), libm::sin(psi));
    let fwd = a[0] * c + a[1] * s;
    let left = -a[0] * s + a[1] * c;
    let theta_cmd = libm::atan(fwd / G).clamp(-tilt, tilt);
    let phi_cmd = libm::atan(-left * libm::cos(theta_cmd) / G).clamp(-tilt, tilt);
    // Collective: the thrust that gives the vertical acceleration at this attitude.
    let thrust = af.mass * (G + az) / (libm::cos(phi) * libm::cos(theta)).max(0.5);
    let collective = thrust / af.max_thrust;
    let thrust = collective.clamp(0.0, 1.0) * af.max_thrust;
    // Attitude → rates → moments → cyclic and tail.
    let rates_cmd = [
        K_ATT * (phi_cmd - phi),
        K_ATT * (theta_cmd - theta),
        (K_YAW * wrap_angle(t.heading - psi)).clamp(-MAX_YAW_RATE, MAX_YAW_RATE),
    ];
    let m: [f64; 3] = std::array::from_fn(|k| {
        af.inertia[k] * (K_RATE * (rates_cmd[k] - b.rates[k]) + DAMPING[k] * b.rates[k])
    });
    let per_tilt = af.hub * thrust + af.hub_stiffness;
    let lat = m[0] / per_tilt / af.cyclic_tilt;
    let lon = m[1] / per_tilt / af.cyclic_tilt;
    let tail_force = -(m[2] + af.torque_arm * thrust) / af.tail_arm;
    let rotor = Rotor {
        collective,
        lon,
        lat,
        tail: tail_force / af.max_tail,
    }
    .clamped();
    (rotor, st)
}

/// The guidance law: what to hold for body `b` under `cmd` with the next waypoint `next`.
fn guide(b: &VtolBody, ty: &VtolType, cmd: &FlightCommand, next: usize) -> HoldTarget {
    match cmd {
        FlightCommand::Straight {
            heading,
            altitude,
            speed,
        } => {
            let v = speed.unwrap_or(ty.cruise_speed).clamp(0.0, ty.max_speed);
            HoldTarget {
                vel: [v * libm::cos(*heading), v * libm::sin(*heading)],
                altitude: *altitude,
                heading: *heading,
            }
        }
        FlightCommand::Waypoints { points, speed } => {
            let i = next.min(points.len() - 1);
            let p = points[i];
            let d = [p[0] - b.pos[0], p[1] - b.pos[1]];
            let dist = libm::hypot(d[0], d[1]);
            let cruise = speed.unwrap_or(ty.cruise_speed).clamp(0.0, ty.max_speed);
            // The speed to pass the waypoint at: a stop at the last, slower for sharper turns.
            let through = match points.get(i + 1) {
                Some(q) if next < points.len() => {
                    let h0 = libm::atan2(d[1], d[0]);
                    let h1 = libm::atan2(q[1] - p[1], q[0] - p[0]);
                    cruise * libm::cos(wrap_angle(h1 - h0)).max(0.0)
                }
                _ => 0.0,
            };
            let brake = 0.5 * G * libm::tan(ty.max_tilt_deg.to_radians());
            let v = cruise
                .min(libm::sqrt(through * through + 2.0 * brake * dist))
                .min(K_V * dist.max(0.0) + through);
            let (vel, heading) = if dist > 1e-6 {
                let h = libm::atan2(d[1], d[0]);
                (
                    [v * d[0] / dist, v * d[1] / dist],
                    if dist > 10.0 { h } else { b.target.heading },
                )
            } else {
                ([0.0, 0.0], b.target.heading)
            };
            HoldTarget {
                vel,
                altitude: p[2],
                heading,
            }
        }
    }
}

/// One flight step of every dynamic helicopter: guidance, then the sub-steps of the inner
/// loops and the dynamics.
pub(crate) fn step_all(w: &mut Arena, dt: f64, fx: &mut Effects<'_, Ev>) {
    let ids: Vec<EntityId> = w.vtol.iter().map(|(id, _)| id).collect();
    let n = w.steps.rotor_substeps.max(1);
    let h = dt / f64::from(n);
    for id in ids {
        let Some(b) = w.vtol.get(id).cloned() else {
            continue;
        };
        let ty = w.types.vtol(b.kind).clone();
        let af = Airframe::of(&ty);
        if let Some(mut pilot) = w.pilots.get(id).cloned() {
            if let FlightCommand::Waypoints { points, .. } = &pilot.cmd
                && let Some(p) = points.get(pilot.next)
            {
                let last = pilot.next + 1 == points.len();
                let dz = if last { p[2] - b.pos[2] } else { 0.0 };
                let d = [p[0] - b.pos[0], p[1] - b.pos[1], dz];
                if libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= ACCEPT {
                    reached(id, pilot.next, fx);
                    pilot.next += 1;
                    w.pilots.insert(id, pilot.clone());
                }
            }
            let target = guide(&b, &ty, &pilot.cmd, pilot.next);
            let _ = HoldVelocity.actuate(w, id, target, fx);
        }
        for _ in 0..n {
            let Some(b) = w.vtol.get(id).cloned() else {
                break;
            };
            let (rotor, st) = hold(&af, &ty, &b, h);
            let _ = RotorControls.actuate(w, id, rotor, fx);
            w.vtol.update(id, |b| {
                b.hold = st;
                b.step(&af, h);
            });
        }
    }
}
