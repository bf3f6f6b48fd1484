//! What a rigid-body vehicle's driver does when the way on is not straight ahead. Turned off
//! its track with room ahead (started across or facing away from it, or the route leaves
//! backwards), it swings round forwards on its ordinary steering, as a driver who can would:
//! that swing is progress as long as it turns the vehicle towards its track. It recovers
//! only when the swing fails: its track lies behind it and the way ahead is blocked (started
//! facing into a dead end), or it stops making progress, neither along its track nor towards
//! it (blocked, or circling). It backs off straight, then at full lock, then turns forwards, changing direction
//! when the room behind or ahead runs out (a K-turn where the street is narrow; backing off
//! where something blocks the way), until it faces its track with room ahead; then it
//! drives on. The effort
//! is bounded by the arena's [`Recovery`](crate::arena::Recovery): moves per recovery,
//! recoveries per trip; a trip that needs more is given up
//! ([`StallReason::RecoverySpent`](crate::arena::StallReason::RecoverySpent)).

use super::wheels::{STOPPED, SteerAndAccelerate, speed_controls};
use crate::arena::{Arena, Ev};
use crate::entity::ground::physical::Manoeuvre;
use crate::entity::route::{Track, wrap_angle};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects};
use vitro::time::SimTime;
use vitro_site::geo::dist;

/// Bearing of the track ahead beyond which it counts as behind the vehicle, radians (100°).
const BEHIND: f64 = 1.75;
/// Bearing of the track within which a manoeuvring vehicle faces it again, radians (20°).
const ALIGNED: f64 = 0.35;
/// Bearing at which a manoeuvre steers to full lock, radians; less, proportionally less.
const FULL_LOCK_FROM: f64 = 0.5;
/// Speed of a manoeuvre's moves, m/s (backwards: at most the type's reverse speed).
const MANOEUVRE_SPEED: f64 = 2.0;
/// Room a manoeuvring vehicle keeps free ahead of or behind it, metres.
const ROOM: f64 = 0.5;
/// Room ahead a vehicle swinging round forwards onto its track keeps; with less, and its
/// track behind it, it backs instead, metres.
const SWING_ROOM: f64 = 3.0;
/// How far a manoeuvre looks for room, metres.
const ROOM_RANGE: f64 = 8.0;
/// A move lasting this long at under 0.1 m/s is blocked, seconds.
const BLOCKED_AFTER: f64 = 2.0;
/// How far a recovery's first move backs straight before it turns, metres: a vehicle
/// wedged against a wall by its side would press its nose into it backing at full lock.
const BACK_OFF: f64 = 1.0;

/// What the vehicle does this step.
pub(super) enum Outcome {
    /// Follows its track (no recovery, or one just finished).
    Driving,
    /// A manoeuvre has set its controls.
    Manoeuvring,
    /// It needs a recovery the trip no longer allows.
    Spent,
}

/// The recovery's step for vehicle `id` at distance `s` along `tr`, its last progress at
/// `since`: starts a manoeuvre when one is needed and drives it.
pub(super) fn step(
    w: &mut Arena,
    id: EntityId,
    tr: &Track,
    s: f64,
    since: SimTime,
    fx: &mut Effects<'_, Ev>,
) -> Outcome {
    let rec = w.steps.recovery;
    let Some(row) = w.chassis.get(id).cloned() else {
        return Outcome::Driving;
    };
    if rec.max_attempts == 0 {
        return Outcome::Driving;
    }
    let ty = w.types.ground(row.kind).clone();
    let now = fx.now();
    let g = row.ground_point();
    let bearing = |p: [f64; 3]| wrap_angle(libm::atan2(p[1] - g[1], p[0] - g[0]) - row.heading());
    let alpha = bearing(tr.point_at(s + ty.turning_radius.max(6.0)));
    let side = |a: f64| if a >= 0.0 { 1.0 } else { -1.0 };
    let m = match row.manoeuvre {
        Some(m) => m,
        None => {
            let look = (2.0 + 0.6 * row.speed.abs()).clamp(3.0, 12.0);
            let behind = bearing(tr.point_at(s + look)).abs() > BEHIND && row.speed.abs() < 1.5;
            let stuck = now.saturating_since(since) >= rec.stuck_after;
            if !(behind || stuck) {
                return Outcome::Driving;
            }
            // The room along the swing the driver is making.
            let ahead = w
                .physics
                .as_ref()
                .and_then(|p| p.clearance_steered(id, false, row.controls.steer, ROOM_RANGE, false))
                .unwrap_or(0.0);
            // With its track behind it but room ahead, the driver swings round forwards
            // (the way on's own steering does that); only a blocked swing needs a manoeuvre.
            if !stuck && ahead >= SWING_ROOM {
                return Outcome::Driving;
            }
            if row.recoveries >= rec.max_attempts {
                return Outcome::Spent;
            }
            let m = Manoeuvre {
                reverse: true,
                moves: 0,
                from: [g[0], g[1]],
                since: now,
                side: side(alpha),
            };
            w.chassis.update(id, |r| {
                r.recoveries += 1;
                r.manoeuvre = Some(m);
                r.integral = 0.0;
            });
            m
        }
    };
    let moved = dist(m.from, [g[0], g[1]]);
    // Facing the track again with room to drive on it: the manoeuvre is over.
    let clear_ahead = || {
        w.physics
            .as_ref()
            .and_then(|p| p.clearance(id, false, ROOM_RANGE, false))
            .unwrap_or(0.0)
            >= SWING_ROOM
    };
    if (m.moves >= 1 || moved >= 0.5 * ty.length) && alpha.abs() < ALIGNED && clear_ahead() {
        // Facing the track again: drive on.
        w.chassis.update(id, |r| {
            r.manoeuvre = None;
            r.integral = 0.0;
            r.progress.1 = now;
        });
        return Outcome::Driving;
    }
    let elapsed = now.saturating_since(m.since).as_secs_f64();
    let v = row.speed;
    // The room along the way the move is going: its corners' arcs at its steering.
    let room = w
        .physics
        .as_ref()
        .and_then(|p| p.clearance_steered(id, m.reverse, row.controls.steer, ROOM_RANGE, false))
        .unwrap_or(0.0);
    let stopping = v * v / (2.0 * ty.max_decel) + ROOM;
    // A move backwards goes a fifth of a turn at most; forwards, round if it has room.
    let longest = if m.reverse {
        1.2 * ty.turning_radius
    } else {
        std::f64::consts::PI * ty.turning_radius
    };
    let over = moved >= longest
        || room <= stopping
        || elapsed >= rec.move_time.as_secs_f64()
        || (elapsed >= BLOCKED_AFTER && v.abs() < 0.1);
    let mut m = m;
    let mut speed = if m.reverse {
        -MANOEUVRE_SPEED.min(ty.reverse_speed())
    } else {
        MANOEUVRE_SPEED
    };
    if over {
        if v.abs() > STOPPED {
            speed = 0.0;
        } else {
            m.moves += 1;
            if m.moves >= rec.max_moves {
                // This recovery did not free it: drive on; the stuck time counts afresh.
                w.chassis.update(id, |r| {
                    r.manoeuvre = None;
                    r.integral = 0.0;
                    r.progress.1 = now;
                });
                return Outcome::Driving;
            }
            m.reverse = !m.reverse;
            m.from = [g[0], g[1]];
            m.since = now;
            m.side = side(alpha);
            speed = -speed.signum() * MANOEUVRE_SPEED;
            if m.reverse {
                speed = speed.max(-ty.reverse_speed());
            }
        }
    }
    let turn = if m.reverse && m.moves == 0 && moved < BACK_OFF {
        0.0
    } else {
        (alpha.abs() / FULL_LOCK_FROM).min(1.0) * ty.max_steer()
    };
    let steer = if m.reverse {
        -m.side * turn
    } else {
        m.side * turn
    };
    let dt = w.steps.physics.as_secs_f64();
    let mut row = row;
    if over && m.moves > 0 && m.since == now {
        row.integral = 0.0;
    }
    let (controls, integral) = speed_controls(&row, &ty, speed, steer, dt);
    w.chassis.update(id, |r| {
        r.manoeuvre = Some(m);
        r.integral = integral;
    });
    let _ = SteerAndAccelerate.actuate(w, id, controls, fx);
    Outcome::Manoeuvring
}
