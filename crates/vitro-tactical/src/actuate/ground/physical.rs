//! The physical level: GoToNode plans the route and, at every physics step, hands
//! MoveInDirection a point ahead on the street polyline and the profile's speed;
//! MoveInDirection is a pure-pursuit steering law and a speed controller (proportional and
//! integral, with feed-forward of rolling resistance, drag and grade) that drive
//! SteerAndAccelerate, which sets the wheels of the rigid body.
//!
//! Under way, the driver keeps to traffic rules read off the other vehicles on its track
//! ahead: it keeps a gap to one in its lane, keeps right of an oncoming one (both do, so they
//! pass on a street wide enough) and passes one at rest on the side that needs the smaller
//! swerve; swinging round onto its track, it drives no faster than it can stop short of a
//! wall or body straight ahead; held up behind a moving vehicle it is waiting, not stuck. Started turned off its
//! way with room ahead, it swings round forwards (pure pursuit at full lock), and turning
//! towards its track counts as progress. Only when that fails (its track behind it and the
//! way ahead blocked, as facing into a dead end, or no progress along its track or towards
//! it) does it recover as a driver would: backs at full lock, then turns forwards, changing
//! direction when the room runs out (a K-turn), then drives on, within the arena's bounded
//! [`Recovery`](crate::arena::Recovery); a trip that needs more is given up with its
//! [`StallReason`].

pub use super::wheels::SteerAndAccelerate;
use super::wheels::{STOPPED, project, speed_controls};
use super::{recover, traffic};
use crate::actuate::{MoveError, arrived, plan, stalled};
use crate::arena::{Arena, Clock, Ev, STALL_PROGRESS_M, StallReason};
use crate::entity::discrete::NodeKind;
use crate::entity::ground::interpolated::MoveCmd;
use crate::entity::route::{Follow, wrap_angle};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects, NodeId};

/// Speed kept until the end of a trip is near, m/s.
const CREEP: f64 = 1.0;
/// Distance from the end of the track at which the vehicle brakes to a stop, metres.
const STOP_WITHIN: f64 = 1.5;
/// Horizontal speed below which an idle vehicle is parked, m/s.
const PARK_BELOW: f64 = 0.05;
/// Turn towards the track ahead that counts as progress, radians (6°).
const TURNED: f64 = 0.1;
/// How far ahead of its nose the driver watches for walls and bodies, metres.
const WATCH: f64 = 10.0;
/// Room kept to a wall or body straight ahead, metres.
const SHORT_OF: f64 = 1.0;
/// Bearing of the track ahead beyond which the vehicle is swinging round onto it, radians
/// (30°).
const SWINGING: f64 = 0.5;
/// Share of the type's braking used to stop short of something straight ahead.
const WALL_BRAKING: f64 = 0.5;
/// MoveInDirection at the physical level: steers for the point by pure pursuit (the arc
/// through it, `δ = atan(2 L sin α / d)`; for a point more than 90° off the nose, where that
/// arc would straighten out, as for a point right behind, `sin α` is taken as ±1, the
/// tightest turn towards it) and controls the speed, through
/// [`SteerAndAccelerate`]. A negative speed backs the vehicle towards the point, rear first
/// (pure pursuit of the rear: `δ = −atan(2 L sin α_r / d)` with `α_r` the point's bearing
/// from the rear), at most the type's reverse speed.
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
        let steer = if cmd.speed < 0.0 {
            let alpha = wrap_angle(libm::atan2(dy, dx) - row.heading() - std::f64::consts::PI);
            -libm::atan(2.0 * ty.wheelbase * pursuit(alpha) / d)
        } else {
            let alpha = wrap_angle(libm::atan2(dy, dx) - row.heading());
            libm::atan(2.0 * ty.wheelbase * pursuit(alpha) / d)
        };
        let (controls, integral) = speed_controls(&row, ty, cmd.speed, steer, dt);
        w.chassis.update(me, |r| r.integral = integral);
        SteerAndAccelerate.actuate(w, me, controls, fx)
    }
}

/// Pure pursuit's `sin α` for a point at bearing `alpha`: ±1 beyond 90°, so a point behind
/// turns the vehicle at the tightest towards it rather than not at all.
fn pursuit(alpha: f64) -> f64 {
    if alpha.abs() > std::f64::consts::FRAC_PI_2 {
        alpha.signum()
    } else {
        libm::sin(alpha)
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
            r.facing = std::f64::consts::PI;
            r.manoeuvre = None;
            r.recoveries = 0;
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

/// GoToNode's step for one vehicle: progress, recovery, arrival, and the command to
/// MoveInDirection.
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
    let (best, mut since) = row.progress;
    // The bearing of the track ahead: a vehicle swinging round towards it (started turned
    // off its way) is making its way, though not yet along the track.
    let ahead = tr.point_at(s + w.types.ground(row.kind).turning_radius.max(6.0));
    let facing = wrap_angle(libm::atan2(ahead[1] - g[1], ahead[0] - g[0]) - row.heading()).abs();
    if s > best + STALL_PROGRESS_M {
        w.chassis.update(id, |r| {
            r.progress = (s, now);
            r.facing = facing;
        });
        since = now;
    } else if facing < row.facing - TURNED {
        w.chassis.update(id, |r| {
            r.progress.1 = now;
            r.facing = facing;
        });
        since = now;
    } else if left > STOP_WITHIN && now.saturating_since(since) >= w.steps.stall_after {
        give_up(w, id, f.goal, s, node, StallReason::NoProgress, fx);
        return;
    }
    if w.follow.contains(id) {
        w.follow.update(id, |f| f.s = s);
        if node != row.node {
            w.chassis.update(id, |r| r.node = node);
        }
    }
    let give = traffic::give(w, id, tr, s, v);
    if give.waiting {
        // Held up behind a moving vehicle: waiting, not stuck.
        w.chassis.update(id, |r| r.progress.1 = now);
        since = now;
    }
    if left > STOP_WITHIN {
        match recover::step(w, id, tr, s, since, fx) {
            recover::Outcome::Driving => {}
            recover::Outcome::Manoeuvring => return,
            recover::Outcome::Spent => {
                give_up(w, id, f.goal, s, node, StallReason::RecoverySpent, fx);
                return;
            }
        }
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
        speed = speed.max(CREEP).min(give.speed);
        // Swinging round onto its track (started across it, or after a manoeuvre), the
        // vehicle is off the street the track keeps to: it drives no faster than it can stop
        // short of whatever is straight ahead. On its track it needs no such care (the track
        // keeps clear of buildings, and the rays would meet the rising ground of a slope).
        if facing > SWINGING
            && let Some(free) = w
                .physics
                .as_ref()
                .and_then(|p| p.clearance_steered(id, false, row.controls.steer, WATCH, false))
        {
            let a = WALL_BRAKING * w.types.ground(row.kind).max_decel;
            speed = speed.min(libm::sqrt(2.0 * a * (free - SHORT_OF).max(0.0)));
        }
        let mut toward = tr.point_at(s + look);
        if give.offset != 0.0 {
            let h = tr.heading_at(s + look);
            toward[0] -= give.offset * libm::sin(h);
            toward[1] += give.offset * libm::cos(h);
        }
        MoveCmd { toward, speed }
    };
    let _ = MoveInDirection.actuate(w, id, cmd, fx);
}

/// Gives the trip up: stops the vehicle where it is and tells its controller why.
fn give_up(
    w: &mut Arena,
    id: EntityId,
    goal: NodeId,
    s: f64,
    node: NodeId,
    why: StallReason,
    fx: &mut Effects<'_, Ev>,
) {
    let Some(tr) = w.follow.remove(id).map(|f| f.track) else {
        return;
    };
    w.chassis.update(id, |r| {
        r.node = node;
        r.integral = 0.0;
        r.manoeuvre = None;
    });
    stalled(id, goal, why, fx);
    let stop = MoveCmd {
        toward: tr.point_at(s),
        speed: 0.0,
    };
    let _ = MoveInDirection.actuate(w, id, stop, fx);
}

/// One physics step of every vehicle; true if any is under way or still moving.
pub(crate) fn step_all(w: &mut Arena, fx: &mut Effects<'_, Ev>) -> bool {
    let ids: Vec<EntityId> = w.chassis.iter().map(|(id, _)| id).collect();
    for &id in &ids {
        if w.follow.contains(id) {
            drive(w, id, fx);
        } else if w.chassis.get(id).is_some_and(|r| r.controls.drive != 0.0) {
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
