//! The mission's sensors over the arena: friend-or-foe vision against every active body,
//! an entity's own condition, and the umpire's full view (for the metrics only).

use crate::arena::Arena;
use crate::condition::{Condition, Status};
use crate::entity::Pose;
use crate::sensor::{FriendFoeVision, Sighting};
use crate::world::{Body, Side};
use rand::Rng;
use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};

/// The body that vision looks at: pose, side and height of an active entity.
fn body_of(w: &Arena, id: EntityId) -> Option<Body> {
    let c = w.conditions.get(id)?;
    if c.status != Status::Active {
        return None;
    }
    let p = w.pose(id)?;
    Some(Body::new(p.pos, p.heading, c.side, c.height))
}

/// Friend-or-foe vision ([`FriendFoeVision`]) over the arena's active bodies: range, field
/// of view, line of sight against terrain and buildings, a detection draw and an
/// identification draw from the observer's `"fof"` stream. Bodies are examined in id order.
#[derive(Copy, Clone, Debug)]
pub struct Vision(pub FriendFoeVision);

impl Sensor<Arena> for Vision {
    type Reading = Vec<Sighting>;
    fn read(&self, w: &Arena, me: EntityId, probe: &mut Probe<'_>) -> Vec<Sighting> {
        let Some(mine) = body_of(w, me) else {
            return Vec::new();
        };
        let v = &self.0;
        let mut out = Vec::new();
        for (id, _) in w.conditions.iter() {
            if id == me {
                continue;
            }
            let Some(b) = body_of(w, id) else { continue };
            if !v.can_see(&w.site, &mine, &b) {
                continue;
            }
            let d = dist(mine.pos, b.pos);
            let rng = probe.rng("fof");
            if rng.random::<f64>() >= v.detection_probability(d) {
                continue;
            }
            let seen_as = if rng.random::<f64>() < v.misidentification {
                let others: Vec<Side> = Side::ALL.into_iter().filter(|s| *s != b.side).collect();
                others[rng.random_range(0..others.len())]
            } else {
                b.side
            };
            out.push(Sighting {
                id,
                pos: b.pos,
                distance: d,
                bearing: libm::atan2(b.pos[1] - mine.pos[1], b.pos[0] - mine.pos[0]),
                seen_as,
            });
        }
        out
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    libm::sqrt((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2))
}

/// The entity's own condition and pose (a soldier knows whether he is aboard or down).
#[derive(Copy, Clone, Debug, Default)]
pub struct Myself;

impl Sensor<Arena> for Myself {
    type Reading = Option<(Condition, Option<Pose>)>;
    fn read(&self, w: &Arena, me: EntityId, _: &mut Probe<'_>) -> Self::Reading {
        Some((*w.conditions.get(me)?, w.pose(me)))
    }
}

/// Every entity's condition and pose, in id order: the umpire's view for the metrics
/// (no player reads it).
#[derive(Copy, Clone, Debug, Default)]
pub struct Situation;

impl Sensor<Arena> for Situation {
    type Reading = Vec<(EntityId, Condition, Option<Pose>)>;
    fn read(&self, w: &Arena, _: EntityId, _: &mut Probe<'_>) -> Self::Reading {
        w.conditions
            .iter()
            .map(|(id, c)| (id, *c, w.pose(id)))
            .collect()
    }
}

/// Whether a friendly aircraft watches over `target`: some active aircraft of the target's
/// side within `radius` metres (horizontally). Adversaries hear and see the drones overhead
/// and hold their fire.
#[derive(Copy, Clone, Debug)]
pub struct Watched {
    /// The entity looked at.
    pub target: EntityId,
    /// Cover radius, metres.
    pub radius: f64,
}

impl Sensor<Arena> for Watched {
    type Reading = bool;
    fn read(&self, w: &Arena, _: EntityId, _: &mut Probe<'_>) -> bool {
        covered(w, self.target, self.radius)
    }
}

/// True if an active aircraft of `target`'s side is within `radius` metres of it
/// (horizontally).
pub fn covered(w: &Arena, target: EntityId, radius: f64) -> bool {
    let (Some(c), Some(p)) = (w.conditions.get(target), w.pose(target)) else {
        return false;
    };
    w.conditions.iter().any(|(id, a)| {
        a.role.is_aircraft()
            && a.side == c.side
            && a.status == Status::Active
            && w.pose(id)
                .is_some_and(|q| libm::hypot(q.pos[0] - p.pos[0], q.pos[1] - p.pos[1]) <= radius)
    })
}
