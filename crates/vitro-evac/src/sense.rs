//! The mission's sensors over the arena: friend-or-foe vision against every active body,
//! an entity's own condition, and the umpire's full view (for the metrics only).

use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};
use vitro_tactical::arena::Arena;
use vitro_tactical::condition::{Condition, Status};
use vitro_tactical::entity::Pose;
use vitro_tactical::sensor::{FriendFoeVision, Sighting};
use vitro_tactical::world::Side;

/// Friend-or-foe vision ([`FriendFoeVision`]) over the arena's active bodies: range, field
/// of view, line of sight against terrain and buildings, a detection draw and an
/// identification draw from the observer's `"fof"` stream. Bodies are examined in id order.
#[derive(Copy, Clone, Debug)]
pub struct Vision(pub FriendFoeVision);

impl Sensor<Arena> for Vision {
    type Reading = Vec<Sighting>;
    fn read(&self, w: &Arena, me: EntityId, probe: &mut Probe<'_>) -> Vec<Sighting> {
        let Some(mine) = w.body(me) else {
            return Vec::new();
        };
        // The bodies it can see, in id order (from the arena's grid and its memo of looks),
        // drawn for in id order, as in a look at every entity in id order.
        w.look(me, &mine, &self.0, probe.rng("fof"))
    }
}

/// [`Vision`] that keeps only the sightings taken for one of `sides` within `within`
/// metres: the same look and the same draws (every body it can see is drawn for, in id
/// order), the other sightings left out (a unit that acts only on some sides makes none
/// for the rest).
#[derive(Copy, Clone, Debug)]
pub struct VisionOf {
    /// The sensor model.
    pub vision: FriendFoeVision,
    /// The sides kept (as the look takes them, rightly or not).
    pub sides: &'static [Side],
    /// The farthest sighting kept, metres.
    pub within: f64,
}

impl VisionOf {
    /// The sightings of `vision` taken for blue or red (the ones a unit notes or reports).
    pub fn armed(vision: FriendFoeVision) -> Self {
        VisionOf {
            vision,
            sides: &[Side::Blue, Side::Red],
            within: f64::INFINITY,
        }
    }
}

impl Sensor<Arena> for VisionOf {
    type Reading = Vec<Sighting>;
    fn read(&self, w: &Arena, me: EntityId, probe: &mut Probe<'_>) -> Vec<Sighting> {
        let Some(mine) = w.body(me) else {
            return Vec::new();
        };
        let keep = |seen_as: Side, d: f64| self.sides.contains(&seen_as) && d <= self.within;
        w.look_where(me, &mine, &self.vision, probe.rng("fof"), keep)
    }
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
    // Only an active aircraft near the target can cover it: the arena's grid of aircraft
    // gives them (and a few more: a metre of slack, the test below decides).
    w.aircraft_within(p.pos[0], p.pos[1], radius + 1.0)
        .iter()
        .any(|(id, q)| {
            w.conditions.get(*id).is_some_and(|a| a.side == c.side)
                && libm::hypot(q.pos[0] - p.pos[0], q.pos[1] - p.pos[1]) <= radius
        })
}

/// Whether the person `who` lies down (hit) within `range` metres of the observer and in
/// its line of sight: a soldier sees a comrade fall. False for an observer without a body.
#[derive(Copy, Clone, Debug)]
pub struct Fallen {
    /// The person looked at.
    pub who: EntityId,
    /// How far the observer sees, metres.
    pub range: f64,
}

impl Sensor<Arena> for Fallen {
    type Reading = bool;
    fn read(&self, w: &Arena, me: EntityId, _: &mut Probe<'_>) -> bool {
        let down = w
            .conditions
            .get(self.who)
            .is_some_and(|c| c.status == Status::Down);
        let (Some(a), Some(b)) = (w.pose(me), w.pose(self.who)) else {
            return false;
        };
        let near = libm::hypot(a.pos[0] - b.pos[0], a.pos[1] - b.pos[1]) <= self.range;
        // Eyes of a standing observer, the body on the ground.
        let eye = [a.pos[0], a.pos[1], a.pos[2] + 1.7];
        let body = [b.pos[0], b.pos[1], b.pos[2] + 0.3];
        down && near && w.site.los.visible(eye, body)
    }
}

/// A camera's look at a ground point: whether the point (1 m above the ground) is within
/// `range` metres of the observer and in its line of sight (terrain and buildings). An
/// observer down, aboard or off the map sees nothing.
#[derive(Copy, Clone, Debug)]
pub struct GroundView {
    /// The point looked at, world metres (its height is taken from the ground).
    pub point: [f64; 3],
    /// Reach of the camera, metres.
    pub range: f64,
}

impl Sensor<Arena> for GroundView {
    type Reading = bool;
    fn read(&self, w: &Arena, me: EntityId, _: &mut Probe<'_>) -> bool {
        let Some(mine) = w.body(me) else {
            return false;
        };
        let [x, y, _] = self.point;
        let Some(g) = w.site.ground([x, y]) else {
            return false;
        };
        let target = [x, y, g + 1.0];
        let d = mine.pos;
        let dist = libm::sqrt(
            (d[0] - x) * (d[0] - x)
                + (d[1] - y) * (d[1] - y)
                + (d[2] - target[2]) * (d[2] - target[2]),
        );
        dist <= self.range && w.visible(mine.pos, target)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::sync::Arc;
    use vitro_site::map::TownMap;
    use vitro_site::site::{Site, SiteConfig};
    use vitro_site::terrain::Terrain;
    use vitro_tactical::condition::Role;
    use vitro_tactical::entity::Level;
    use vitro_tactical::types::VtolKind;
    use vitro_tactical::world::Side;

    /// The cover test as a scan of every entity (the reference).
    fn covered_by_scan(w: &Arena, target: EntityId, radius: f64) -> bool {
        let (Some(c), Some(p)) = (w.conditions.get(target), w.pose(target)) else {
            return false;
        };
        w.conditions.iter().any(|(id, a)| {
            a.role.is_aircraft()
                && a.side == c.side
                && a.status == Status::Active
                && w.pose(id).is_some_and(|q| {
                    libm::hypot(q.pos[0] - p.pos[0], q.pos[1] - p.pos[1]) <= radius
                })
        })
    }

    #[test]
    fn cover_from_the_grid_is_cover_from_a_scan() {
        let site = Site::new(
            TownMap::from_buildings(Vec::new()),
            Terrain::flat(51, 51, 20.0, 0.0).unwrap(),
            &SiteConfig {
                offset: Some([500.0, 500.0]),
                ..SiteConfig::default()
            },
        )
        .unwrap();
        let mut w = Arena::new(Arc::new(site));
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for i in 0..300u32 {
            let pos = [
                rng.random_range(0.0..1000.0),
                rng.random_range(0.0..1000.0),
                20.0,
            ];
            w.add_vtol(EntityId(i), VtolKind::Vidar, Level::Dynamic, pos, 0.0)
                .unwrap();
            // A few aircraft, the others bodies of other roles; some down.
            let role = if i % 10 == 0 {
                Role::Vidar
            } else {
                Role::Trooper
            };
            let mut c = Condition::new(role, Side::ALL[rng.random_range(0..3)], 1.0);
            if rng.random_bool(0.2) {
                c.status = Status::Down;
            }
            w.conditions.insert(EntityId(i), c);
        }
        let mut agree = [0; 2];
        for round in 0..20 {
            for _ in 0..10 {
                let id = EntityId(rng.random_range(0..300));
                let d = rng.random_range(-80.0..80.0);
                w.vtol.update(id, |b| b.pos[0] += d);
            }
            for t in (0..300).step_by(7) {
                let r = rng.random_range(0.0..250.0);
                let want = covered_by_scan(&w, EntityId(t), r);
                assert_eq!(
                    covered(&w, EntityId(t), r),
                    want,
                    "round {round}, target {t}"
                );
                agree[usize::from(want)] += 1;
            }
        }
        assert!(
            agree[0] > 50 && agree[1] > 50,
            "both answers tested: {agree:?}"
        );
    }
}
