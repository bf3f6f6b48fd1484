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
//! is computed afresh.

use super::Arena;
use super::grid::Bodies;
use super::looks::{LookCounts, Memo, SCAN_MAX, key, update};
use crate::sensor::{FriendFoeVision, InSight};
use crate::world::Body;
use std::sync::Arc;
use vitro::entity::EntityId;

/// What a look of `v` from `me` (body `mine`) at the bodies `near` can see, in id order.
fn compute(
    arena: &Arena,
    me: EntityId,
    mine: &Body,
    v: &FriendFoeVision,
    mut near: Vec<(EntityId, Body)>,
) -> Vec<InSight> {
    near.retain(|(id, b)| *id != me && v.can_see_by(mine, b, |p, q| arena.visible(p, q)));
    near.sort_unstable_by_key(|(id, _)| *id);
    near.iter()
        .map(|(id, b)| v.in_sight(mine, *id, b))
        .collect()
}

impl Arena {
    /// What a look of `vision` from `me`, whose body is `mine`, can see
    /// ([`FriendFoeVision::can_see`]: range, field of view, line of sight), in id order; a
    /// sensor then draws for them ([`FriendFoeVision::draw`]). The same answer as examining
    /// every active body; remembered per looker and brought up to date with what changed.
    pub fn in_sight(
        &self,
        me: EntityId,
        mine: &Body,
        vision: &FriendFoeVision,
    ) -> Arc<Vec<InSight>> {
        let Ok(mut guard) = self.vision.lock() else {
            // A panic elsewhere poisoned the lock: examine everything.
            return Arc::new(compute(self, me, mine, vision, Bodies::all(self)));
        };
        let looks = &mut *guard;
        looks.grid.sync(self);
        let (x, y, r) = (mine.pos[0], mine.pos[1], vision.range);
        let k = key(mine, vision);
        let i = me.index();
        if looks.memos.len() <= i {
            looks.memos.resize_with(i + 1, || None);
        }
        let now = looks.grid.now();
        let grid = &looks.grid;
        let fresh = looks.memos[i]
            .take()
            .filter(|m| m.key == k && m.at.0 == now.0)
            .and_then(|m| {
                let changes = grid.changes_since(m.at.1)?;
                (changes.len() <= SCAN_MAX).then_some((m, changes))
            });
        let seen = match fresh {
            Some((m, [])) => {
                looks.counts.remembered += 1;
                m.seen
            }
            Some((mut m, changes)) => {
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
                    update(Arc::make_mut(&mut m.seen), ids, now_seen);
                }
                m.seen
            }
            None => {
                looks.counts.computed += 1;
                Arc::new(compute(self, me, mine, vision, grid.query(x, y, r)))
            }
        };
        looks.counts.in_sight += seen.len() as u64;
        looks.memos[i] = Some(Memo {
            key: k,
            at: now,
            seen: seen.clone(),
        });
        seen
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
