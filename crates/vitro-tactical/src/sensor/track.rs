//! Tracking: a lock on a target, held only while the owner's own camera detects it.
//!
//! A tracking sensor is two parts, as on a real gimbal:
//!
//! - [`Look`], the camera: one look of [`FriendFoeVision`] over the arena's active bodies
//!   (range, field of view, line of sight against terrain and buildings, a detection draw
//!   and an identification draw from the owner's `"fof"` stream). It is a plain
//!   [`Sensor`]: stateless, read through the agent's `Context`.
//! - [`Tracker`], the lock memory the agent keeps: each look refreshes the locks whose
//!   target was detected, counts a miss for the others, and drops a lock after
//!   [`TrackConfig::misses_to_lose`] missed looks in a row (occluded, out of range, out of
//!   the field of view, or a failed detection draw). A new lock is taken only on a body the
//!   camera detects and identifies as [`TrackConfig::side`] in
//!   [`TrackConfig::confirm_looks`] looks in a row, and dropped when that many looks in a
//!   row take it for another side (identification errors do not make locks for long); a
//!   lost target is re-acquired by looking again (search), never by asking the world where
//!   it went.
//!
//! A lock gives what the camera last saw: the position, when ([`Lock::age`]), and a
//! velocity estimated from the last two fixes for dead reckoning ([`Lock::predicted`]).
//!
//! ```
//! use vitro::entity::EntityId;
//! use vitro::time::SimTime;
//! use vitro_tactical::sensor::Sighting;
//! use vitro_tactical::sensor::track::{TrackConfig, TrackEvent, Tracker};
//! use vitro_tactical::world::Side;
//!
//! let red = EntityId(7);
//! let seen = |x: f64| Sighting { id: red, pos: [x, 0.0, 0.0], distance: 100.0, bearing: 0.0,
//!                                seen_as: Side::Red };
//! let config = TrackConfig { misses_to_lose: 2, ..TrackConfig::default() };
//! let mut tracker = Tracker::new(config);
//! let t = SimTime::from_secs;
//!
//! // First look: the target is detected and taken for red: a lock.
//! assert_eq!(tracker.update(t(0), &[seen(0.0)]), [TrackEvent::Acquired(red)]);
//! // It moved 5 m in a second: the lock follows and estimates its velocity.
//! tracker.update(t(1), &[seen(5.0)]);
//! let lock = tracker.get(red).unwrap();
//! assert_eq!(lock.velocity, [5.0, 0.0]);
//! // It steps behind a house: one missed look keeps the lock, aging...
//! assert!(tracker.update(t(2), &[]).is_empty());
//! let lock = tracker.get(red).unwrap();
//! assert_eq!(lock.age(t(2)).as_secs_f64(), 1.0);
//! assert_eq!(lock.predicted(t(2))[0], 10.0); // dead reckoning from the last fix
//! // ...the second loses it.
//! assert_eq!(tracker.update(t(3), &[]), [TrackEvent::Lost(red)]);
//! assert!(tracker.get(red).is_none());
//! ```

use super::{FriendFoeVision, Sighting};
use crate::arena::Arena;
use crate::world::Side;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};
use vitro::sim::{Context, Model};
use vitro::time::{SimDuration, SimTime};

/// One look of a camera over the arena: [`FriendFoeVision`] against every other active
/// body, in entity-id order, drawing from the owner's `"fof"` stream. An owner that is not
/// active (down, aboard) sees nothing.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Look(pub FriendFoeVision);

impl Sensor<Arena> for Look {
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

/// How a [`Tracker`] takes and keeps locks.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrackConfig {
    /// The camera.
    pub vision: FriendFoeVision,
    /// Missed looks in a row that lose a lock (1: lost at the first miss). 0 counts as 1.
    pub misses_to_lose: u32,
    /// The side a new lock is taken on, as the camera identifies it.
    pub side: Side,
    /// Looks in a row that must identify a new target as `side` before it is locked, and
    /// that must take a locked target for another side before the lock is dropped (1: a
    /// single look). 0 counts as 1.
    pub confirm_looks: u32,
    /// Most locks held at once; the nearest new targets are taken first.
    pub max_locks: usize,
}

impl Default for TrackConfig {
    /// The default camera, three missed looks, red targets confirmed by one look, up to
    /// eight locks.
    fn default() -> Self {
        TrackConfig {
            vision: FriendFoeVision::default(),
            misses_to_lose: 3,
            side: Side::Red,
            confirm_looks: 1,
            max_locks: 8,
        }
    }
}

/// A lock on one target: what the owner's camera last saw of it.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lock {
    /// The target.
    pub target: EntityId,
    /// Where it was last seen, world metres.
    pub pos: [f64; 3],
    /// When it was last seen.
    pub seen_at: SimTime,
    /// When the lock was taken.
    pub acquired_at: SimTime,
    /// Missed looks since it was last seen.
    pub misses: u32,
    /// Horizontal velocity from the last two fixes, m/s (zero after a single fix).
    pub velocity: [f64; 2],
    /// The side the camera took it for at the last fix.
    pub seen_as: Side,
    /// Fixes in a row that took it for another side than the tracker's.
    pub contrary: u32,
}

impl Lock {
    /// How long ago the target was last seen.
    pub fn age(&self, now: SimTime) -> SimDuration {
        now.saturating_since(self.seen_at)
    }

    /// Where the target would be now if it kept its last velocity (dead reckoning).
    pub fn predicted(&self, now: SimTime) -> [f64; 3] {
        let dt = self.age(now).as_secs_f64();
        [
            self.pos[0] + self.velocity[0] * dt,
            self.pos[1] + self.velocity[1] * dt,
            self.pos[2],
        ]
    }
}

/// A change of the locks after a look.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum TrackEvent {
    /// A new lock on this target.
    Acquired(EntityId),
    /// The lock on this target was lost (too many missed looks, or taken for another side
    /// too many times in a row).
    Lost(EntityId),
}

/// A target seen but not yet locked: looks in a row that identified it as the side wanted.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Candidate {
    looks: u32,
}

/// The locks an agent holds, updated look by look from its own camera only.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tracker {
    config: TrackConfig,
    locks: BTreeMap<EntityId, Lock>,
    candidates: BTreeMap<EntityId, Candidate>,
}

impl Tracker {
    /// A tracker with no lock.
    pub fn new(config: TrackConfig) -> Self {
        Tracker {
            config,
            locks: BTreeMap::new(),
            candidates: BTreeMap::new(),
        }
    }

    /// Its settings.
    pub fn config(&self) -> &TrackConfig {
        &self.config
    }

    /// Looks once through the owner's camera ([`Look`]) and updates the locks: the
    /// changes, in target order (losses first).
    pub fn sense<M: Model<Env = Arena>>(&mut self, cx: &mut Context<'_, M>) -> Vec<TrackEvent> {
        let now = cx.now();
        let seen = cx.sense(&Look(self.config.vision));
        self.update(now, &seen)
    }

    /// Updates the locks with one look's sightings taken at `now`: the changes, in target
    /// order (losses first, then acquisitions).
    pub fn update(&mut self, now: SimTime, sightings: &[Sighting]) -> Vec<TrackEvent> {
        let mut events = Vec::new();
        let limit = self.config.misses_to_lose.max(1);
        let confirm = self.config.confirm_looks.max(1);
        let side = self.config.side;
        let mut lost = Vec::new();
        for (id, lock) in &mut self.locks {
            match sightings.iter().find(|s| s.id == *id) {
                Some(s) => {
                    let dt = now.saturating_since(lock.seen_at).as_secs_f64();
                    if dt > 0.0 {
                        lock.velocity =
                            [(s.pos[0] - lock.pos[0]) / dt, (s.pos[1] - lock.pos[1]) / dt];
                    }
                    lock.pos = s.pos;
                    lock.seen_at = now;
                    lock.misses = 0;
                    lock.seen_as = s.seen_as;
                    lock.contrary = if s.seen_as == side {
                        0
                    } else {
                        lock.contrary + 1
                    };
                    if lock.contrary >= confirm {
                        lost.push(*id);
                    }
                }
                None => {
                    lock.misses += 1;
                    if lock.misses >= limit {
                        lost.push(*id);
                    }
                }
            }
        }
        for id in lost {
            self.locks.remove(&id);
            events.push(TrackEvent::Lost(id));
        }
        // Candidates: looks in a row identifying each unlocked target as the side wanted.
        let mut next = BTreeMap::new();
        for s in sightings {
            if s.seen_as == side && !self.locks.contains_key(&s.id) {
                let looks = self.candidates.get(&s.id).map_or(0, |c| c.looks) + 1;
                next.insert(s.id, Candidate { looks });
            }
        }
        self.candidates = next;
        let mut fresh: Vec<&Sighting> = sightings
            .iter()
            .filter(|s| (self.candidates.get(&s.id)).is_some_and(|c| c.looks >= confirm))
            .collect();
        fresh.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.id.cmp(&b.id)));
        let room = self.config.max_locks.saturating_sub(self.locks.len());
        let mut taken: Vec<EntityId> = Vec::new();
        for s in fresh.into_iter().take(room) {
            self.candidates.remove(&s.id);
            self.locks.insert(
                s.id,
                Lock {
                    target: s.id,
                    pos: s.pos,
                    seen_at: now,
                    acquired_at: now,
                    misses: 0,
                    velocity: [0.0, 0.0],
                    seen_as: s.seen_as,
                    contrary: 0,
                },
            );
            taken.push(s.id);
        }
        taken.sort_unstable();
        events.extend(taken.into_iter().map(TrackEvent::Acquired));
        events
    }

    /// The lock on `target`, if held.
    pub fn get(&self, target: EntityId) -> Option<&Lock> {
        self.locks.get(&target)
    }

    /// Every lock held, in target order.
    pub fn locks(&self) -> impl Iterator<Item = &Lock> + '_ {
        self.locks.values()
    }

    /// Number of locks held.
    pub fn len(&self) -> usize {
        self.locks.len()
    }

    /// True if no lock is held.
    pub fn is_empty(&self) -> bool {
        self.locks.is_empty()
    }

    /// Drops every lock and candidate (the owner's camera is gone): the targets that were
    /// locked.
    pub fn clear(&mut self) -> Vec<EntityId> {
        let ids = self.locks.keys().copied().collect();
        self.locks.clear();
        self.candidates.clear();
        ids
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sighting(id: u32, x: f64, d: f64, side: Side) -> Sighting {
        Sighting {
            id: EntityId(id),
            pos: [x, 0.0, 0.0],
            distance: d,
            bearing: 0.0,
            seen_as: side,
        }
    }

    fn tracker(misses: u32, max: usize) -> Tracker {
        Tracker::new(TrackConfig {
            misses_to_lose: misses,
            max_locks: max,
            ..TrackConfig::default()
        })
    }

    #[test]
    fn a_lock_is_taken_only_on_the_side_asked_for() {
        let mut t = tracker(1, 8);
        let ev = t.update(
            SimTime::ZERO,
            &[
                sighting(1, 0.0, 10.0, Side::Blue),
                sighting(2, 0.0, 10.0, Side::Neutral),
            ],
        );
        assert!(ev.is_empty());
        assert!(t.is_empty());
        let ev = t.update(SimTime::ZERO, &[sighting(3, 0.0, 10.0, Side::Red)]);
        assert_eq!(ev, [TrackEvent::Acquired(EntityId(3))]);
    }

    fn confirming(looks: u32) -> Tracker {
        Tracker::new(TrackConfig {
            misses_to_lose: 1,
            confirm_looks: looks,
            ..TrackConfig::default()
        })
    }

    #[test]
    fn a_lock_needs_its_looks_in_a_row_and_one_wrong_look_starts_again() {
        let mut t = confirming(3);
        let s = SimTime::from_secs;
        let red = |x| sighting(3, x, 10.0, Side::Red);
        assert!(t.update(s(0), &[red(0.0)]).is_empty());
        assert!(t.update(s(1), &[red(1.0)]).is_empty());
        // Taken for a civilian once: the count starts again.
        let civilian = sighting(3, 2.0, 10.0, Side::Neutral);
        assert!(t.update(s(2), &[civilian]).is_empty());
        assert!(t.update(s(3), &[red(3.0)]).is_empty());
        assert!(t.update(s(4), &[red(4.0)]).is_empty());
        let ev = t.update(s(5), &[red(5.0)]);
        assert_eq!(ev, [TrackEvent::Acquired(EntityId(3))]);
        assert_eq!(t.get(EntityId(3)).unwrap().acquired_at, s(5));
    }

    #[test]
    fn a_lock_taken_for_another_side_in_a_row_is_dropped() {
        let mut t = confirming(2);
        let s = SimTime::from_secs;
        t.update(s(0), &[sighting(3, 0.0, 10.0, Side::Red)]);
        t.update(s(1), &[sighting(3, 0.0, 10.0, Side::Red)]);
        assert!(t.get(EntityId(3)).is_some());
        // One contrary look keeps the lock (the object is still followed)...
        let civilian = sighting(3, 2.0, 10.0, Side::Neutral);
        assert!(t.update(s(2), &[civilian]).is_empty());
        let lock = t.get(EntityId(3)).unwrap();
        assert_eq!((lock.misses, lock.contrary), (0, 1));
        assert_eq!((lock.seen_as, lock.pos[0]), (Side::Neutral, 2.0));
        // ...a red one resets the count, two contrary ones in a row drop it.
        t.update(s(3), &[sighting(3, 3.0, 10.0, Side::Red)]);
        t.update(s(4), &[sighting(3, 4.0, 10.0, Side::Blue)]);
        let ev = t.update(s(5), &[sighting(3, 5.0, 10.0, Side::Blue)]);
        assert_eq!(ev, [TrackEvent::Lost(EntityId(3))]);
    }

    #[test]
    fn misses_in_a_row_lose_the_lock_and_a_detection_resets_them() {
        let mut t = tracker(3, 8);
        let s = SimTime::from_secs;
        t.update(s(0), &[sighting(1, 0.0, 10.0, Side::Red)]);
        t.update(s(1), &[]);
        t.update(s(2), &[]);
        t.update(s(3), &[sighting(1, 3.0, 10.0, Side::Red)]);
        let lock = t.get(EntityId(1)).unwrap();
        assert_eq!(lock.misses, 0);
        // Three seconds between fixes: 1 m/s.
        assert_eq!(lock.velocity, [1.0, 0.0]);
        assert!(t.update(s(4), &[]).is_empty());
        assert!(t.update(s(5), &[]).is_empty());
        assert_eq!(t.update(s(6), &[]), [TrackEvent::Lost(EntityId(1))]);
        // Re-acquired by a later look: a new lock.
        let ev = t.update(s(9), &[sighting(1, 9.0, 10.0, Side::Red)]);
        assert_eq!(ev, [TrackEvent::Acquired(EntityId(1))]);
        assert_eq!(t.get(EntityId(1)).unwrap().acquired_at, s(9));
    }

    #[test]
    fn the_nearest_targets_are_locked_first_up_to_the_limit() {
        let mut t = tracker(1, 2);
        let ev = t.update(
            SimTime::ZERO,
            &[
                sighting(1, 0.0, 300.0, Side::Red),
                sighting(2, 0.0, 100.0, Side::Red),
                sighting(3, 0.0, 200.0, Side::Red),
            ],
        );
        assert_eq!(
            ev,
            [
                TrackEvent::Acquired(EntityId(2)),
                TrackEvent::Acquired(EntityId(3))
            ]
        );
        assert_eq!(t.len(), 2);
        assert_eq!(t.clear(), [EntityId(2), EntityId(3)]);
        assert!(t.is_empty());
    }
}
