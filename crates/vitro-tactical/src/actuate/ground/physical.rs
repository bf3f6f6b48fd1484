//! The physical level: GoToNode plans the route and, at every physics step, hands
//! MoveInDirection a point ahead on the street polyline and the profile's speed;
//! MoveInDirection is a pure-pursuit steering law and a speed controller (proportional and
//! integral, with feed-forward of rolling resistance, drag and grade) that drive
//! SteerAndAccelerate, which sets the wheels of the rigid body.

use crate::actuate::{MoveError, arrived, plan, stalled};
use crate::arena::{Arena, Clock, Ev, STALL_PROGRESS_M};
use crate::entity::discrete::NodeKind;
use crate::entity::ground::interpolated::MoveCmd;
use crate::entity::ground::physical::Controls;
use crate::entity::route::{Follow, Track, wrap_angle};
use crate::types::{G, RHO_AIR};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects, NodeId};
use vitro_site::geo::{P2, closest_on_segment, dist};

/// Speed kept until the end of a trip is near, m/s.
const CREEP: f64 = 1.0;
/// Distance from the end of the track at which the vehicle brakes to a stop, metres.
const STOP_WITHIN: f64 = 1.5;
/// Speed below which a stopping vehicle counts as stopped, m/s.
const STOPPED: f64 = 0.3;
/// Horizontal speed below which an idle vehicle is parked, m/s.
const PARK_BELOW: f64 = 0.05;
/// Speed controller gains: proportional (1/s) and integral (1/s²).
const KP: f64 = 1.2;
const KI: f64 = 0.4;

/// SteerAndAccelerate: sets the front-wheel angle and the engine and brake forces, limited
/// to the type's steering lock, engine ([`GroundType::drive_limit`](crate::types::GroundType::drive_limit)) and brakes.
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
        let c = Controls {
            steer: c.steer.clamp(-lock, lock),
            drive: c.drive.clamp(0.0, ty.drive_limit(row.speed)),
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

/// MoveInDirection at the physical level: steers for the point by pure pursuit (the arc
/// through it, `δ = atan(2 L sin α / d)`) and controls the speed, through
/// [`SteerAndAccelerate`].
#[derive(Copy, Clone, Debug, Default)]
pub struct MoveInDirection;

impl Actuator<Arena, Ev> for MoveInDirection {
    type Command = MoveCmd;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: MoveCmd,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), MoveError> {
        let row = w.chassis.get(me).ok_or(MoveError::NoBody(me))?.clone();
        let ty = w.types.ground(row.kind);
        let dt = w.steps.physics.as_secs_f64();
        let p = row.ground_point();
        let (dx, dy) = (cmd.toward[0] - p[0], cmd.toward[1] - p[1]);
        let d = libm::sqrt(dx * dx + dy * dy).max(1.0);
        let alpha = wrap_angle(libm::atan2(dy, dx) - row.heading());
        let steer = libm::atan(2.0 * ty.wheelbase * libm::sin(alpha) / d);
        let e = cmd.speed - row.speed;
        let integral = (row.integral + e * dt).clamp(-3.0, 3.0);
        let a = (KP * e + KI * integral).min(ty.max_accel);
        let v = row.speed;
        let resist = ty.rolling_resistance * ty.mass * G
            + 0.5 * RHO_AIR * ty.drag_area * v * v
            + ty.mass * G * libm::sin(row.attitude[1]);
        let force = ty.mass * a + resist;
        let hold = cmd.speed <= 0.0 && v.abs() < STOPPED;
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
        w.chassis.update(me, |r| r.integral = integral);
        SteerAndAccelerate.actuate(w, me, controls, fx)
    }
}

/// GoToNode at the physical level: plans the route on the free drive graph (the same track
/// and speed profile as the other levels), then at every physics step drives
/// [`MoveInDirection`] to a point ahead on it.
#[derive(Copy, Clone, Debug, Default)]
pub struct GoToNode;

impl Actuator<Arena, Ev> for GoToNode {
    type Command = NodeId;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        goal: NodeId,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), MoveError> {
        let b = w.chassis.get(me).ok_or(MoveError::NoBody(me))?;
        if w.follow.contains(me) {
            return Err(MoveError::UnderWay(me));
        }
        if b.node == goal {
            arrived(me, goal, fx);
            return Ok(());
        }
        let (kind, from) = (NodeKind::Ground(b.kind), b.node);
        let track = plan(w, kind, crate::entity::Level::Physical, from, goal, 0.0)?;
        if let Some(p) = w.physics.as_mut() {
            p.park(me, false);
        }
        let now = fx.now();
        w.chassis.update(me, |r| {
            r.parked = false;
            r.progress = (0.0, now);
        });
        w.follow.insert(
            me,
            Follow {
                goal,
                s: 0.0,
                next: 1,
                track,
            },
        );
        w.wake(Clock::Physics, fx);
        Ok(())
    }
}

/// The distance along `tr` of the point nearest to `p`, searched from `s0` back 5 m and
/// ahead 40 m (the vehicle moves less than that in a step).
fn project(tr: &Track, s0: f64, p: P2) -> f64 {
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

/// GoToNode's step for one vehicle: progress, arrival, and the command to MoveInDirection.
fn drive(w: &mut Arena, id: EntityId, fx: &mut Effects<'_, Ev>) {
    let (Some(f), Some(row)) = (w.follow.get(id).cloned(), w.chassis.get(id).cloned()) else {
        return;
    };
    let tr = &f.track;
    let g = row.ground_point();
    let s = project(tr, f.s, [g[0], g[1]]);
    let node = tr.node_at(s).unwrap_or(row.node);
    let left = tr.length() - s;
    let v = row.speed;
    let now = fx.now();
    let (best, since) = row.progress;
    if s > best + STALL_PROGRESS_M {
        w.chassis.update(id, |r| r.progress = (s, now));
    } else if left > STOP_WITHIN && now.saturating_since(since) >= w.steps.stall_after {
        // No progress for too long: give the trip up, stop, and say so.
        w.follow.remove(id);
        w.chassis.update(id, |r| {
            r.node = node;
            r.integral = 0.0;
        });
        stalled(id, f.goal, fx);
        let stop = MoveCmd {
            toward: tr.point_at(s),
            speed: 0.0,
        };
        let _ = MoveInDirection.actuate(w, id, stop, fx);
        return;
    }
    let cmd = if left <= STOP_WITHIN {
        if v.abs() < STOPPED {
            w.follow.remove(id);
            w.chassis.update(id, |r| {
                r.node = f.goal;
                r.integral = 0.0;
            });
            arrived(id, f.goal, fx);
        }
        MoveCmd {
            toward: tr.point_at(tr.length() + 5.0),
            speed: 0.0,
        }
    } else {
        let look = (2.0 + 0.6 * v.abs()).clamp(3.0, 12.0);
        let mut speed = tr.speed_at(s).min(tr.speed_at(s + v.abs() + 2.0));
        speed = speed.max(CREEP);
        MoveCmd {
            toward: tr.point_at(s + look),
            speed,
        }
    };
    if w.follow.contains(id) {
        w.follow.update(id, |f| f.s = s);
        if node != row.node {
            w.chassis.update(id, |r| r.node = node);
        }
    }
    let _ = MoveInDirection.actuate(w, id, cmd, fx);
}

/// One physics step of every vehicle; true if any is under way or still moving.
pub(crate) fn step_all(w: &mut Arena, fx: &mut Effects<'_, Ev>) -> bool {
    let ids: Vec<EntityId> = w.chassis.iter().map(|(id, _)| id).collect();
    for &id in &ids {
        if w.follow.contains(id) {
            drive(w, id, fx);
        } else if w.chassis.get(id).is_some_and(|r| r.controls.drive > 0.0) {
            // Nothing to do: release the engine and hold the brakes.
            let _ = MoveInDirection.actuate(
                w,
                id,
                MoveCmd {
                    toward: [0.0; 3],
                    speed: 0.0,
                },
                fx,
            );
        }
    }
    let Some(physics) = w.physics.as_mut() else {
        return false;
    };
    physics.step();
    let mut busy = false;
    for &id in &ids {
        let Some(mut row) = w.chassis.get(id).cloned() else {
            continue;
        };
        if row.parked || !physics.read(id, &mut row) {
            continue;
        }
        let moving = libm::hypot(row.vel[0], row.vel[1]) > PARK_BELOW;
        if !w.follow.contains(id) && !moving {
            // Stopped with nothing to do: park it (and stop stepping it).
            physics.park(id, true);
            row.parked = true;
            row.vel = [0.0; 3];
            row.acc = [0.0; 3];
            row.rates = [0.0; 3];
            row.speed = 0.0;
        }
        busy |= !row.parked;
        w.chassis.insert(id, row);
    }
    busy
}
