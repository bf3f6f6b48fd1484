//! Traffic rules of the physical level's driver, from the other vehicles on its track
//! ahead (their place along the track and across it):
//!
//! - **keep a gap** to a vehicle ahead in its lane: the speed from which it stops [`GAP`]
//!   short of it with part of its braking;
//! - **keep right** of an oncoming vehicle (both do, so they pass on a street wide enough);
//! - **pass** a vehicle at rest in its lane (parked, or given up) on the side that needs
//!   the smaller swerve.
//!
//! A vehicle held up behind one that is moving is waiting, not stuck: its recovery does not
//! start.
//!
//! Sources: the gap is the braking part of Gipps' car-following model (P. G. Gipps, "A
//! behavioural car-following model for computer simulation", *Transportation Research Part
//! B* 15(2), 1981, pp. 105–111), simplified to no reaction time and a vehicle ahead taken to
//! stop at once: the follower drives no faster than it can stop from short of it. Keeping
//! right of oncoming traffic is the rule of the road of the Vienna Convention on Road Traffic
//! (1968), Articles 10 and 12; passing a vehicle at rest on whichever side needs the smaller
//! swerve is this driver's own rule (the convention overtakes on the left). The
//! reciprocal methods for many agents (ORCA: J. van den Berg, S. J. Guy, M. Lin and
//! D. Manocha, "Reciprocal n-body collision avoidance", *Robotics Research*, Springer Tracts
//! in Advanced Robotics 70, 2011) assume agents that can take any velocity near their own;
//! a car-like body on a street cannot, which is why the rules here follow the track.

use super::wheels::project;
use crate::arena::Arena;
use crate::entity::route::{Track, wrap_angle};
use vitro::entity::EntityId;

/// Gap kept to a vehicle ahead at rest, metres.
const GAP: f64 = 3.0;
/// Share of the type's braking used to keep the gap.
const FOLLOW_BRAKING: f64 = 0.5;
/// How far ahead along its track the driver looks at traffic beyond its stopping distance,
/// metres.
const LOOK: f64 = 25.0;
/// Farthest across its track a vehicle still counts as on it, metres.
const ON_TRACK: f64 = 6.0;
/// Lateral room kept to a vehicle passed or met, metres.
const CLEAR: f64 = 0.5;
/// Heading difference beyond which a vehicle is oncoming, radians (120°).
const ONCOMING: f64 = 2.1;
/// Speed below which a vehicle counts as at rest, m/s.
const AT_REST: f64 = 0.3;

/// What the traffic asks of one vehicle this step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct Give {
    /// The speed it may drive at most, m/s.
    pub speed: f64,
    /// How far to the left of its track to drive, metres (negative: to the right).
    pub offset: f64,
    /// It is held up behind a vehicle that is moving.
    pub waiting: bool,
}

/// The traffic's demands on vehicle `id`, at `s` along `tr` at speed `v`.
pub(super) fn give(w: &Arena, id: EntityId, tr: &Track, s: f64, v: f64) -> Give {
    let mut out = Give {
        speed: f64::INFINITY,
        offset: 0.0,
        waiting: false,
    };
    let Some(me) = w.chassis.get(id) else {
        return out;
    };
    let ty = w.types.ground(me.kind);
    let a = FOLLOW_BRAKING * ty.max_decel;
    let reach = v * v / (2.0 * a) + GAP + LOOK;
    let here = me.ground_point();
    // Others on the track ahead: (distance ahead, across, width, length, at rest, oncoming).
    let mut seen = Vec::new();
    for (oid, o) in w.chassis.iter() {
        if oid == id {
            continue;
        }
        let p = o.ground_point();
        let oty = w.types.ground(o.kind);
        let behind_ok = 0.5 * (ty.length + oty.length) + 1.0;
        if libm::hypot(p[0] - here[0], p[1] - here[1]) > reach + behind_ok + 2.0 * ON_TRACK {
            // Too far to be on the reach of track ahead or alongside.
            continue;
        }
        let so = project(tr, s, [p[0], p[1]]);
        if so < s - behind_ok || so > s + reach {
            continue;
        }
        let q = tr.point_at(so);
        let h = tr.heading_at(so);
        let (dx, dy) = (p[0] - q[0], p[1] - q[1]);
        let across = libm::cos(h) * dy - libm::sin(h) * dx;
        if libm::hypot(dx, dy) > ON_TRACK {
            continue;
        }
        let rest = o.parked || (o.speed.abs() < AT_REST && !w.follow.contains(oid));
        let oncoming = wrap_angle(o.heading() - h).abs() > ONCOMING && !rest;
        seen.push((
            so - s,
            across,
            oty.width,
            oty.length,
            rest,
            oncoming,
            o.speed,
        ));
    }
    for &(_, across, width, _, rest, oncoming, _) in &seen {
        let need = 0.5 * (ty.width + width) + CLEAR;
        if oncoming {
            let keep = -(0.5 * ty.width + CLEAR);
            if keep.abs() > out.offset.abs() {
                out.offset = keep;
            }
        } else if rest && (across - out.offset).abs() < need {
            let (left, right) = (across + need, across - need);
            let pass = if left.abs() < right.abs() {
                left
            } else {
                right
            };
            if pass.abs() > out.offset.abs() {
                out.offset = pass;
            }
        }
    }
    for &(ahead, across, width, length, _, _, speed) in &seen {
        let need = 0.5 * (ty.width + width) + CLEAR;
        if ahead <= 0.0 || (across - out.offset).abs() >= need {
            continue;
        }
        let free = ahead - 0.5 * (ty.length + length);
        let cap = libm::sqrt(2.0 * a * (free - GAP).max(0.0));
        if cap < out.speed {
            out.speed = cap;
            out.waiting = speed.abs() > AT_REST;
        }
    }
    out
}
