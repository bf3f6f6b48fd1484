//! Discrete trips: the track a body follows from node to goal (planned once per arena, then
//! shared), the hop events along it, and the answer when it has arrived.

use crate::arena::{Arena, Ev, StallReason};
use crate::entity::Level;
use crate::entity::discrete::{NodeKind, Trip};
use crate::entity::roads::RouteError;
use crate::entity::route::Track;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::{Effects, NodeId};
use vitro::event::Target;
use vitro::time::SimDuration;

/// Why an actuator refused a command.
#[derive(Clone, Debug, PartialEq, thiserror::Error, Serialize, Deserialize)]
pub enum MoveError {
    /// The entity has no body this actuator can move.
    #[error("entity {0:?} has no body this actuator moves")]
    NoBody(EntityId),
    /// The body is on a trip; it takes a new goal once it has arrived.
    #[error("entity {0:?} is under way")]
    UnderWay(EntityId),
    /// No route.
    #[error(transparent)]
    Route(#[from] RouteError),
    /// The body gave its trip to the node up, for the reason given ([`Ev::Stalled`]).
    #[error("entity {0:?} stalled on its way to node {1:?}: {2}")]
    Stalled(EntityId, NodeId, StallReason),
    /// The actuator was built for a level its family has not (e.g. a vehicle driven at the
    /// directed level).
    #[error("entity {0:?}: this actuator moves no body at the {level} level", level = .1.name())]
    NoSuchLevel(EntityId, Level),
}

/// Tells `who` it gave up its trip to `goal`, now, and why ([`Ev::Stalled`]).
pub(crate) fn stalled(who: EntityId, goal: NodeId, why: StallReason, fx: &mut Effects<'_, Ev>) {
    fx.schedule_in(
        SimDuration::ZERO,
        Target::Entity(who),
        Ev::Stalled(goal, why),
    );
}

/// Tells `who` it reached `goal`, now.
pub(crate) fn arrived(who: EntityId, goal: NodeId, fx: &mut Effects<'_, Ev>) {
    fx.schedule_in(SimDuration::ZERO, Target::Entity(who), Ev::Arrived(goal));
}

/// The track from `from` to `goal` for a body of `kind` at `level` heading `heading`
/// (planned once per arena, then shared). At an abstract level (discrete, interpolated)
/// with a fit in the arena's [`calibration`](Arena::calibration), the profile is stretched
/// to the predicted concrete time for a start at that heading ([`crate::calibration`]);
/// otherwise it is the plan itself.
pub(crate) fn plan(
    w: &mut Arena,
    kind: NodeKind,
    level: Level,
    from: NodeId,
    goal: NodeId,
    heading: f64,
) -> Result<Arc<Track>, MoveError> {
    let cal = w.calibration.clone().filter(|c| {
        c.fit(&crate::calibration::entity_key(kind), level)
            .is_some()
    });
    let Some(cal) = cal else {
        return plan_raw(w, kind, from, goal);
    };
    let raw = plan_raw(w, kind, from, goal)?;
    let k = cal.stretch(kind, level, &raw, heading).unwrap_or(1.0);
    Ok(Arc::new(crate::calibration::stretched(&raw, k)))
}

/// The planned track, uncalibrated.
fn plan_raw(
    w: &mut Arena,
    kind: NodeKind,
    from: NodeId,
    goal: NodeId,
) -> Result<Arc<Track>, MoveError> {
    let (site, roads, types) = (&w.site, &w.roads, &w.types);
    w.tracks.get_or_plan((kind, from, goal, None), || {
        let roads = roads.of(kind.mode());
        let path = roads.path(from, goal)?;
        Ok(match kind {
            NodeKind::Ground(k) => {
                Track::plan_vehicle(site, roads, &path, types.ground(k), &types.speed_limits)?
            }
            NodeKind::Troop(k) => {
                Track::plan_walk(site, roads, &path, &types.troops, types.troops.of(k).load)?
            }
        })
    })
}

/// The discrete level's GoToNode / WalkToNode: plans the trip and schedules the first hop.
/// `accepts` says which bodies this actuator moves.
pub(crate) fn start_trip(
    w: &mut Arena,
    me: EntityId,
    goal: NodeId,
    accepts: fn(NodeKind) -> bool,
    fx: &mut Effects<'_, Ev>,
) -> Result<(), MoveError> {
    start_paced_trip(w, me, goal, accepts, None, fx)
}

/// [`start_trip`] with the profile stretched by `pace` (a squad leader's pace from the
/// arena's calibration, `vitro_calibrate::squad`); `None` or 1: as planned.
pub(crate) fn start_paced_trip(
    w: &mut Arena,
    me: EntityId,
    goal: NodeId,
    accepts: fn(NodeKind) -> bool,
    pace: Option<f64>,
    fx: &mut Effects<'_, Ev>,
) -> Result<(), MoveError> {
    let b = w
        .at_node
        .get(me)
        .filter(|b| accepts(b.kind))
        .ok_or(MoveError::NoBody(me))?;
    if b.trip.is_some() {
        return Err(MoveError::UnderWay(me));
    }
    if b.node == goal {
        arrived(me, goal, fx);
        return Ok(());
    }
    let (kind, from, heading) = (b.kind, b.node, b.heading);
    let mut track = plan(w, kind, Level::Discrete, from, goal, heading)?;
    if let Some(k) = pace.filter(|&k| k != 1.0) {
        track = Arc::new(crate::calibration::stretched(&track, k));
    }
    let trip = Trip {
        goal,
        next: 1,
        pending: None,
        track,
    };
    schedule_hop(w, me, trip, fx);
    Ok(())
}

/// Schedules the hop to the trip's next node and records it in the body.
fn schedule_hop(w: &mut Arena, me: EntityId, mut trip: Trip, fx: &mut Effects<'_, Ev>) {
    let Some((next, secs)) = trip.next_hop() else {
        return;
    };
    let id = fx.schedule_in(SimDuration::from_secs_f64(secs), Target::Env, Ev::Hop(me));
    trip.pending = Some(id);
    let (from, to) = {
        let b = w.at_node.get(me);
        let mode = b.map(|b| b.kind.mode());
        let node = b.map(|b| b.node);
        (
            mode.zip(node).and_then(|(m, n)| w.node_point(m, n)),
            mode.and_then(|m| w.node_point(m, next)),
        )
    };
    w.at_node.update(me, |b| {
        if let (Some(a), Some(c)) = (from, to) {
            let d = vitro_site::geo::dist([a[0], a[1]], [c[0], c[1]]);
            if d > 0.0 {
                b.heading = libm::atan2(c[1] - a[1], c[0] - a[0]);
            }
            b.speed = if secs > 0.0 { d / secs } else { 0.0 };
        }
        b.trip = Some(trip);
    });
}

/// The environment's side of a discrete hop: the body reaches its next node.
pub fn on_hop(w: &mut Arena, who: EntityId, fx: &mut Effects<'_, Ev>) {
    let Some(mut trip) = w.at_node.get(who).and_then(|b| b.trip.clone()) else {
        return;
    };
    if fx.fired().is_some() && trip.pending != fx.fired() {
        return; // not the hop this trip waits for (stale or forged)
    }
    let Some((node, _)) = trip.next_hop() else {
        return;
    };
    trip.next += 1;
    trip.pending = None;
    let done = trip.next >= trip.track.nodes.len();
    let goal = trip.goal;
    w.at_node.update(who, |b| {
        b.node = node;
        if done {
            b.trip = None;
            b.speed = 0.0;
        }
    });
    if done {
        arrived(who, goal, fx);
    } else {
        schedule_hop(w, who, trip, fx);
    }
}
