//! The interpolated level: GoToNode plans the route and feeds MoveInDirection the street
//! polyline point by point at the profile's speed; MoveInDirection moves the vehicle on the
//! ground mesh under its acceleration limits.

use crate::actuate::{MoveError, arrived, plan};
use crate::arena::{Arena, Clock, Ev};
use crate::entity::discrete::NodeKind;
use crate::entity::ground::interpolated::MoveCmd;
use crate::entity::route::Follow;
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects, NodeId};

/// Speed kept until the last metre of a trip, m/s, so the profile's stop at zero speed is
/// reached in finite time.
const CREEP: f64 = 0.5;

/// MoveInDirection at the interpolated level: head for a point, reach a speed.
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
        if !w.on_ground.update(me, |b| b.cmd = Some(cmd)) {
            return Err(MoveError::NoBody(me));
        }
        w.wake(Clock::Kinematic, fx);
        Ok(())
    }
}

/// GoToNode at the interpolated level: plans the route on the free drive graph, then at every
/// kinematic step drives [`MoveInDirection`] to the next point of the street polyline.
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
        let b = w.on_ground.get(me).ok_or(MoveError::NoBody(me))?;
        if w.follow.contains(me) {
            return Err(MoveError::UnderWay(me));
        }
        if b.node == goal {
            arrived(me, goal, fx);
            return Ok(());
        }
        let (kind, from, heading) = (NodeKind::Ground(b.kind), b.node, b.heading);
        let track = plan(
            w,
            kind,
            crate::entity::Level::Interpolated,
            from,
            goal,
            heading,
        )?;
        w.follow.insert(
            me,
            Follow {
                goal,
                s: 0.0,
                next: 1,
                track,
            },
        );
        w.wake(Clock::Kinematic, fx);
        Ok(())
    }
}

/// One kinematic step of every interpolated vehicle on a trip; true if any is still under
/// way.
pub(crate) fn step_all(w: &mut Arena, dt: f64, fx: &mut Effects<'_, Ev>) -> bool {
    let ids: Vec<EntityId> = w
        .on_ground
        .iter()
        .filter(|(id, _)| w.follow.contains(*id))
        .map(|(id, _)| id)
        .collect();
    let mut busy = false;
    for id in ids {
        busy |= step_one(w, id, dt, fx);
    }
    busy
}

fn step_one(w: &mut Arena, id: EntityId, dt: f64, fx: &mut Effects<'_, Ev>) -> bool {
    let (Some(f), Some(mut b)) = (w.follow.get(id).cloned(), w.on_ground.get(id).cloned()) else {
        return false;
    };
    let tr = f.track.clone();
    let ty = w.types.ground(b.kind).clone();
    let (mut s, mut next) = (f.s, f.next.max(1));
    let left = tr.length() - s;
    // GoToNode: the profile's speed here and one step ahead (to brake in time), kept above a
    // creep until the end is near.
    let mut v = tr.speed_at(s).min(tr.speed_at(s + b.speed * dt));
    if left > 1.0 {
        v = v.max(CREEP);
    }
    let toward = tr.pts[next.min(tr.pts.len() - 1)];
    let cmd = MoveCmd { toward, speed: v };
    let Ok(()) = MoveInDirection.actuate(w, id, cmd, fx) else {
        return false;
    };
    b.cmd = Some(cmd);
    let i = tr.index_at(s).min(tr.pts.len().saturating_sub(2));
    let run = vitro_site::geo::dist(
        [tr.pts[i][0], tr.pts[i][1]],
        [tr.pts[i + 1][0], tr.pts[i + 1][1]],
    );
    let slope = if run > 1e-9 {
        (tr.pts[i + 1][2] - tr.pts[i][2]) / run
    } else {
        0.0
    };
    b.update_speed(&ty, slope, dt);
    // The speed is along the ground; the body moves in plan.
    let len = tr.s[i + 1] - tr.s[i];
    let mut budget = b.speed * dt * if len > 1e-9 { run / len } else { 1.0 };
    let mut node = b.node;
    let mut done = false;
    while let Some(rest) = b.advance(budget, |_| None) {
        if let Some(&(_, n)) = tr.nodes.iter().find(|&&(k, _)| k == next) {
            node = n;
        }
        next += 1;
        if next >= tr.pts.len() {
            done = true;
            break;
        }
        b.cmd = Some(MoveCmd {
            toward: tr.pts[next],
            speed: v,
        });
        budget = rest;
        if budget <= 0.0 {
            break;
        }
    }
    if done {
        s = tr.length();
    } else {
        // Distance along the track: the fraction of the current piece covered in plan.
        let (a, c) = (tr.pts[next - 1], tr.pts[next]);
        let run = vitro_site::geo::dist([a[0], a[1]], [c[0], c[1]]);
        let gone = vitro_site::geo::dist([a[0], a[1]], [b.pos[0], b.pos[1]]);
        let frac = if run > 1e-9 {
            (gone / run).min(1.0)
        } else {
            0.0
        };
        s = tr.s[next - 1] + frac * (tr.s[next] - tr.s[next - 1]);
    }
    b.pos[2] = tr.point_at(s)[2];
    b.node = node;
    if done {
        b.speed = 0.0;
        b.cmd = None;
    }
    w.on_ground.insert(id, b);
    if done {
        w.follow.remove(id);
        arrived(id, f.goal, fx);
        false
    } else {
        w.follow.update(id, |f| {
            f.s = s;
            f.next = next;
        });
        true
    }
}
