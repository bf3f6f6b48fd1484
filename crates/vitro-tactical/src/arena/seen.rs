//! What each looker's friend-or-foe vision can see, remembered between its looks.
//!
//! A look first finds the bodies it can see (in range, in the field of view, in line of
//! sight: no randomness), then draws for them in id order. The first part is a function of
//! the looker's body, the vision's parameters and the bodies within range, and most looks
//! ask it again with little changed: a trooper hiding at a node looks every second at
//! neighbours who mostly do not move. The memo keeps, per looker, what its last look could
//! see. While the looker's body and the vision are the same bit for bit, a look starts from
//! it and goes through the grid's log of the bodies that changed since: a body that changed
//! in (or into, or out of) the cells the range covers is examined again and put in or taken
//! out; no other body can have come into sight or gone out of it. The answer is the set a
//! fresh look finds, in id order, so the draws that follow are the same too. A look whose
//! memo is of another body or vision, or older than the log (or than [`SCAN_MAX`] changes),
//! is computed afresh. The draws of [`Arena::look`] read the remembered list in place (no
//! copy, no shared pointer to follow). The list is kept in two parts ([`Seen`]): the short
//! records the walk and the draws read for every body (id, side, detection probability,
//! distance), and the position and bearing a sighting adds, read only for the sightings a
//! look keeps ([`Arena::look_where`]: a red trooper keeps the blue ones within reach, and
//! makes no sighting of the cars and comrades it draws for).

use super::Arena;
use super::grid::{Bodies, bits_eq};
use super::looks::{LookCounts, Memo, SCAN_MAX, Seen, key, update};
use crate::sensor::{FriendFoeVision, InSight, Sighting};
use crate::world::{Body, Side};
use rand::Rng;
use vitro::entity::EntityId;
use vitro::hint::prefetch;

/// What a look of `v` from `me` (body `mine`) at the bodies `near` can see, in id order.
fn compute(
    arena: &Arena,
    me: EntityId,
    mine: &Body,
    v: &FriendFoeVision,
    mut near: Vec<(EntityId, Body)>,
) -> Seen {
    near.retain(|(id, b)| *id != me && v.can_see_by(mine, b, |p, q| arena.visible(p, q)));
    near.sort_unstable_by_key(|(id, _)| *id);
    Seen::of(near.iter().map(|(id, b)| v.in_sight(mine, *id, b)))
}

/// Short records of a memo loaded ahead of the walk (10 cache lines).
const HEADS_AHEAD: usize = 26;
/// Bytes of a random stream loaded ahead of the draws (a ChaCha stream is 320).
const RNG_AHEAD: usize = 512;

impl Arena {
    /// What a look of `vision` from `me`, whose body is `mine`, can see
    /// ([`FriendFoeVision::can_see`]: range, field of view, line of sight), in id order; a
    /// sensor then draws for them ([`FriendFoeVision::draw`], or all at once:
    /// [`look`](Self::look)). The same answer as examining every active body; remembered per
    /// looker and brought up to date with what changed.
    pub fn in_sight(&self, me: EntityId, mine: &Body, vision: &FriendFoeVision) -> Vec<InSight> {
        self.with_in_sight(me, mine, vision, Seen::to_vec)
    }

    /// One look of `vision` from `me`, whose body is `mine`: the bodies it can see
    /// ([`in_sight`](Self::in_sight)), drawn for in id order from `rng`
    /// ([`FriendFoeVision::draw`]): the sightings a look at every active body in id order
    /// makes, with the same draws. The draws read the looker's remembered list in place.
    pub fn look(
        &self,
        me: EntityId,
        mine: &Body,
        vision: &FriendFoeVision,
        rng: &mut impl Rng,
    ) -> Vec<Sighting> {
        self.look_where(me, mine, vision, rng, |_, _| true)
    }

    /// [`look`](Self::look), keeping only the sightings for which `keep(seen_as, distance)`
    /// holds: the same draws (for every body it can see, in id order), fewer sightings made.
    /// The draws read what they need of each body; the rest is read for the kept ones.
    pub fn look_where(
        &self,
        me: EntityId,
        mine: &Body,
        vision: &FriendFoeVision,
        rng: &mut impl Rng,
        mut keep: impl FnMut(Side, f64) -> bool,
    ) -> Vec<Sighting> {
        // The draws read the looker's random stream after the look: start loading it.
        prefetch(std::ptr::from_ref(&*rng), size_of_val(&*rng).min(RNG_AHEAD));
        self.with_in_sight(me, mine, vision, |seen| {
            let mut sightings = Vec::new();
            for (k, h) in seen.heads.iter().enumerate() {
                if let Some(seen_as) = vision.identify(h.p_detect, h.side, &mut *rng)
                    && keep(seen_as, h.distance)
                {
                    sightings.push(seen.sighting(k, seen_as));
                }
            }
            sightings
        })
    }

    /// Calls `f` with what [`in_sight`](Self::in_sight) answers, read in place (under the
    /// arena's lock of vision: `f` must not look again).
    fn with_in_sight<R>(
        &self,
        me: EntityId,
        mine: &Body,
        vision: &FriendFoeVision,
        f: impl FnOnce(&Seen) -> R,
    ) -> R {
        let Ok(mut guard) = self.vision.lock() else {
            // A panic elsewhere poisoned the lock: examine everything.
            return f(&compute(self, me, mine, vision, Bodies::all(self)));
        };
        let looks = &mut *guard;
        // The looker's memo is read below, after the grid catches up: start loading it.
        prefetch(
            looks.memos.as_ptr().wrapping_add(me.index()),
            size_of::<Option<Memo>>(),
        );
        looks.grid.sync(self);
        let (generation, now) = looks.grid.now();
        if generation != looks.generation {
            // A rebuilt grid: its clock and cells mean nothing to the memos.
            looks.memos.clear();
            looks.generation = generation;
        }
        let (x, y, r) = (mine.pos[0], mine.pos[1], vision.range);
        let (k, v) = (key(mine), looks.vision_index(vision));
        let i = me.index();
        if looks.memos.len() <= i {
            looks.memos.resize_with(i + 1, || None);
        }
        let grid = &looks.grid;
        let fresh = looks.memos[i]
            .take()
            .filter(|m| bits_eq(&m.key, &k) && m.vision == v)
            .and_then(|m| {
                // The walk and the draws read the short records after the changes are gone
                // through: start loading the first ones.
                let heads = &m.seen.heads;
                prefetch(
                    heads.as_ptr(),
                    size_of_val(&heads[..heads.len().min(HEADS_AHEAD)]),
                );
                let changes = grid.changes_since(m.at)?;
                (changes.len() <= SCAN_MAX).then_some((m.seen, changes))
            });
        let seen = match fresh {
            Some((seen, [])) => {
                looks.counts.remembered += 1;
                seen
            }
            Some((mut seen, changes)) => {
                looks.counts.updated += 1;
                looks.counts.scanned += changes.len() as u64;
                // Only the bodies that changed in the cells the look covers can have come into
                // sight or gone out of it.
                let area = grid.area(x, y, r);
                let ids = &mut looks.scratch;
                ids.clear();
                ids.extend(changes.iter().filter(|c| area.touches(c)).map(|c| c.id));
                if !ids.is_empty() {
                    ids.sort_unstable();
                    ids.dedup();
                    looks.counts.examined += ids.len() as u64;
                    let now_seen = |e: u32| {
                        let b = grid.returned(&area, e)?;
                        let id = EntityId(e);
                        (id != me && vision.can_see_by(mine, &b, |p, q| self.visible(p, q)))
                            .then(|| vision.in_sight(mine, id, &b))
                    };
                    update(&mut seen, ids, now_seen);
                }
                seen
            }
            None => {
                looks.counts.computed += 1;
                compute(self, me, mine, vision, grid.query(x, y, r))
            }
        };
        looks.counts.in_sight += seen.len() as u64;
        let out = f(&seen);
        looks.memos[i] = Some(Memo {
            key: k,
            vision: v,
            at: now,
            seen,
        });
        out
    }

    /// How looks ([`in_sight`](Self::in_sight)) were answered so far.
    pub fn look_counts(&self) -> LookCounts {
        self.vision
            .lock()
            .map_or(LookCounts::default(), |l| LookCounts {
                resyncs: l.grid.resyncs,
                ..l.counts
            })
    }
}
