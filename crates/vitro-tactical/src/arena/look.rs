//! What vision asks the arena: the body of an entity, the bodies near a point (from the
//! arena's grid) and line of sight (through the arena's memo of answers).

use super::Arena;
use super::grid::{Bodies, Mark, SOURCES};
use crate::condition::Status;
use crate::world::Body;
use vitro::entity::EntityId;
use vitro::env::EntityStorage;

impl Arena {
    /// What vision sees of `id`: its pose, side and height, if it has a condition and is
    /// active (not aboard, down, hidden, ...).
    pub fn body(&self, id: EntityId) -> Option<Body> {
        let c = self.conditions.get(id)?;
        if c.status != Status::Active {
            return None;
        }
        let p = self.pose(id)?;
        Some(Body::new(p.pos, p.heading, c.side, c.height))
    }

    /// The active bodies ([`body`](Self::body)) within `radius` metres of `(x, y)`
    /// horizontally, perhaps with a few more but never fewer, in id order: what a sensor of
    /// that range needs to examine. Answered from a grid kept in step with the storages, so
    /// a look costs what is near, not what is in the arena.
    pub fn bodies_near(&self, x: f64, y: f64, radius: f64) -> Vec<(EntityId, Body)> {
        let mut near = self.bodies_within(x, y, radius);
        near.sort_unstable_by_key(|(id, _)| *id);
        near
    }

    /// [`bodies_near`](Self::bodies_near) in no particular order (for a sensor that sorts
    /// only what it keeps).
    pub fn bodies_within(&self, x: f64, y: f64, radius: f64) -> Vec<(EntityId, Body)> {
        match self.vision.lock() {
            Ok(mut v) => v.grid.near(self, x, y, radius),
            // A panic elsewhere poisoned the lock: examine everything.
            Err(_) => self.all(),
        }
    }

    /// The active bodies of aircraft (by role: [`Role::is_aircraft`]) within `radius` metres
    /// of `(x, y)` horizontally, perhaps with a few more but never fewer, in no particular
    /// order: a query of [`bodies_within`](Self::bodies_within) for aircraft only, from a
    /// grid of their own (a few aircraft among thousands of bodies).
    ///
    /// [`Role::is_aircraft`]: crate::condition::Role::is_aircraft
    pub fn aircraft_within(&self, x: f64, y: f64, radius: f64) -> Vec<(EntityId, Body)> {
        let air = Aircraft(self);
        match self.vision.lock() {
            Ok(mut v) => v.air.near(&air, x, y, radius),
            Err(_) => air.all(),
        }
    }

    /// Whether `b` is in line of sight from `a` (against terrain and buildings): the site's
    /// answer, kept in a memo of this arena, so asking again about the same two points costs
    /// a lookup instead of a ray cast.
    pub fn visible(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        match self.sight.lock() {
            Ok(mut m) => m.visible(a, b, |p, q| self.site.los.visible(p, q)),
            Err(_) => self.site.los.visible(a, b),
        }
    }

    /// Line-of-sight questions answered from the memo and by a ray cast so far.
    pub fn sight_counts(&self) -> (u64, u64) {
        self.sight.lock().map_or((0, 0), |m| (m.hits, m.misses))
    }
}

/// The entities written in `s` since it had made `since` writes.
fn taken<T>(s: &EntityStorage<T>, since: u64) -> Option<Vec<EntityId>> {
    s.written_since(since).map(Iterator::collect)
}

impl Bodies for Arena {
    fn marks(&self) -> [Mark; SOURCES] {
        [
            Mark::of(&self.at_node),
            Mark::of(&self.on_ground),
            Mark::of(&self.chassis),
            Mark::of(&self.walkers),
            Mark::of(&self.lattice),
            Mark::of(&self.ctol),
            Mark::of(&self.vtol),
            Mark::of(&self.conditions),
        ]
    }
    fn written(&self, i: usize, since: u64) -> Option<Vec<EntityId>> {
        match i {
            0 => taken(&self.at_node, since),
            1 => taken(&self.on_ground, since),
            2 => taken(&self.chassis, since),
            3 => taken(&self.walkers, since),
            4 => taken(&self.lattice, since),
            5 => taken(&self.ctol, since),
            6 => taken(&self.vtol, since),
            _ => taken(&self.conditions, since),
        }
    }
    fn body(&self, id: EntityId) -> Option<Body> {
        Arena::body(self, id)
    }
    fn all(&self) -> Vec<(EntityId, Body)> {
        self.conditions
            .iter()
            .filter_map(|(id, _)| Arena::body(self, id).map(|b| (id, b)))
            .collect()
    }
    fn each(&self, f: &mut dyn FnMut(EntityId, Body)) {
        for (id, _) in self.conditions.iter() {
            if let Some(b) = Arena::body(self, id) {
                f(id, b);
            }
        }
    }
}

/// The arena's aircraft: its bodies of entities whose role is an aircraft's.
struct Aircraft<'a>(&'a Arena);

impl Aircraft<'_> {
    fn flies(&self, id: EntityId) -> bool {
        self.0
            .conditions
            .get(id)
            .is_some_and(|c| c.role.is_aircraft())
    }
}

impl Bodies for Aircraft<'_> {
    fn marks(&self) -> [Mark; SOURCES] {
        self.0.marks()
    }
    fn written(&self, i: usize, since: u64) -> Option<Vec<EntityId>> {
        self.0.written(i, since)
    }
    fn body(&self, id: EntityId) -> Option<Body> {
        Arena::body(self.0, id).filter(|_| self.flies(id))
    }
    fn all(&self) -> Vec<(EntityId, Body)> {
        self.0
            .conditions
            .iter()
            .filter(|(_, c)| c.role.is_aircraft())
            .filter_map(|(id, _)| Arena::body(self.0, id).map(|b| (id, b)))
            .collect()
    }
}
