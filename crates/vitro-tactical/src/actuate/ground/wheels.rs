//! The physical level's lowest layer, shared by its driving and manoeuvring:
//! SteerAndAccelerate (the wheels of the rigid body), the speed controller that feeds it,
//! and where a vehicle is along its track.

use crate::actuate::MoveError;
use crate::arena::{Arena, Clock, Ev};
use crate::entity::ground::physical::{Chassis, Controls};
use crate::entity::route::Track;
use crate::types::{G, GroundType, RHO_AIR};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects};
use vitro_site::geo::{P2, closest_on_segment, dist};

/// Speed below which a stopping vehicle counts as stopped, m/s.
pub(crate) const STOPPED: f64 = 0.3;
/// Speed controller gains: proportional (1/s) and integral (1/s²).
const KP: f64 = 1.2;
const KI: f64 = 0.4;

/// SteerAndAccelerate: sets the front-wheel angle and the signed engine force and the brake
/// force, limited to the type's steering lock, engine forwards and backwards
/// ([`GroundType::drive_range`](crate::types::GroundType::drive_range)) and brakes.
#[derive(Copy, Clone, Debug, Default)]
pub struct SteerAndAccelerate;

impl Actuator<Arena, Ev> for SteerAndAccelerate {
    type Command = Controls;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        c: Controls,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), MoveError> {
        let row = w.chassis.get(me).ok_or(MoveError::NoBody(me))?;
        let ty = w.types.ground(row.kind);
        let lock = ty.max_steer();
        let (back, ahead) = ty.drive_range(row.speed);
        let c = Controls {
            steer: c.steer.clamp(-lock, lock),
            drive: c.drive.clamp(back, ahead),
            brake: c.brake.clamp(0.0, ty.mass * ty.max_decel),
        };
        if let Some(p) = w.physics.as_mut() {
            p.set_controls(me, c);
        }
        w.chassis.update(me, |r| r.controls = c);
        w.wake(Clock::Physics, fx);
        Ok(())
    }
}

/// The controls that reach the signed `speed` (a proportional and integral controller with
/// feed-forward of rolling resistance, drag and grade) with the wheels at `steer`, and the
/// controller's new integral term. Backwards at most the type's reverse speed; a vehicle
/// still rolling the other way brakes first.
pub(crate) fn speed_controls(
    row: &Chassis,
    ty: &GroundType,
    speed: f64,
    steer: f64,
    dt: f64,
) -> (Controls, f64) {
    let v = row.speed;
    if speed < 0.0 {
        let back = speed.max(-ty.reverse_speed());
        let e = back - v;
        let integral = (row.integral + e * dt).clamp(-3.0, 3.0);
        let a = (KP * e + KI * integral).max(-ty.max_accel);
        // Rolling resistance and drag push forwards while backing; the grade as ever.
        let resist = -(ty.rolling_resistance * ty.mass * G + 0.5 * RHO_AIR * ty.drag_area * v * v)
            + ty.mass * G * libm::sin(row.attitude[1]);
        let force = ty.mass * a + resist;
        let controls = if v > STOPPED {
            // Still rolling forwards: brake.
            Controls {
                steer,
                drive: 0.0,
                brake: ty.mass * ty.max_decel,
            }
        } else if force > 0.0 {
            // Backing too fast: brake.
            Controls {
                steer,
                drive: 0.0,
                brake: force,
            }
        } else {
            Controls {
                steer,
                drive: force,
                brake: 0.0,
            }
        };
        return (controls, integral);
    }
    let e = speed - v;
    let integral = (row.integral + e * dt).clamp(-3.0, 3.0);
    let a = (KP * e + KI * integral).min(ty.max_accel);
    let resist = ty.rolling_resistance * ty.mass * G
        + 0.5 * RHO_AIR * ty.drag_area * v * v
        + ty.mass * G * libm::sin(row.attitude[1]);
    let force = ty.mass * a + resist;
    let hold = speed <= 0.0 && v.abs() < STOPPED;
    let controls = if hold {
        Controls {
            steer,
            drive: 0.0,
            brake: ty.mass * ty.max_decel,
        }
    } else if force >= 0.0 {
        Controls {
            steer,
            drive: force,
            brake: 0.0,
        }
    } else {
        Controls {
            steer,
            drive: 0.0,
            brake: -force,
        }
    };
    (controls, integral)
}

/// The distance along `tr` of the point nearest to `p`, searched from `s0` back 5 m and
/// ahead 40 m (the vehicle moves less than that in a step).
pub(crate) fn project(tr: &Track, s0: f64, p: P2) -> f64 {
    let n = tr.pts.len();
    if n < 2 {
        return 0.0;
    }
    let i0 = tr.index_at((s0 - 5.0).max(0.0));
    let i1 = (tr.index_at(s0 + 40.0) + 1).min(n - 1);
    let mut best = (f64::INFINITY, s0);
    for i in i0..i1 {
        let (a, b) = (
            [tr.pts[i][0], tr.pts[i][1]],
            [tr.pts[i + 1][0], tr.pts[i + 1][1]],
        );
        let q = closest_on_segment(p, a, b);
        let d = dist(p, q);
        if d < best.0 {
            let run = dist(a, b);
            let f = if run > 0.0 { dist(a, q) / run } else { 0.0 };
            best = (d, tr.s[i] + f * (tr.s[i + 1] - tr.s[i]));
        }
    }
    best.1
}
