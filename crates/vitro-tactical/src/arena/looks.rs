//! The memo of looks: per looker, what its last look could see (see [`super::seen`] for how
//! a look uses it).

use super::grid::BodyGrid;
use crate::sensor::{FriendFoeVision, InSight};
use crate::world::Body;

/// The grids of bodies and the memo of looks, behind one lock of the arena.
#[derive(Debug, Default)]
pub(crate) struct Looks {
    /// The active bodies on a grid.
    pub(crate) grid: BodyGrid,
    /// The active aircraft on a grid of their own ([`Arena::aircraft_within`]).
    pub(crate) air: BodyGrid,
    /// Per looker's entity index: its last look.
    pub(super) memos: Vec<Option<Memo>>,
    /// The grid's generation the memos were made in (a rebuilt grid's clock and cells mean
    /// nothing to them: they are dropped).
    pub(super) generation: u64,
    /// The visions looked with so far, as exact bits ([`Memo::vision`] is an index here).
    pub(super) visions: Vec<VisionBits>,
    /// Entity indices to examine again (kept to save an allocation per look).
    pub(super) scratch: Vec<u32>,
    /// How looks were answered so far (for benchmarks).
    pub(super) counts: LookCounts,
}

/// How looks were answered ([`Arena::look_counts`](crate::arena::Arena::look_counts)).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct LookCounts {
    /// From the memo, nothing having changed in the looker's range.
    pub remembered: u64,
    /// From the memo brought up to date with the bodies that changed in range.
    pub updated: u64,
    /// Computed afresh (a first look, a looker that moved or turned, another vision).
    pub computed: u64,
    /// Changes of bodies gone through to bring memos up to date.
    pub scanned: u64,
    /// Bodies examined again for that.
    pub examined: u64,
    /// Bodies in sight, summed over the looks.
    pub in_sight: u64,
    /// Times the grid of bodies looked every body up again (a storage had more writes than
    /// its log holds since the grid last caught up).
    pub resyncs: u64,
}

/// One looker's last look: small (its body's bits, an index for the vision, the grid's
/// clock and the list), so the memos of many lookers, each read once a second, take few
/// cache lines.
#[derive(Debug)]
pub(super) struct Memo {
    /// The looker's body, as bits.
    pub(super) key: Key,
    /// The vision, as an index in [`Looks::visions`].
    pub(super) vision: u32,
    /// The grid's clock when it was computed (in the generation [`Looks::generation`]).
    pub(super) at: u64,
    /// What it could see, in id order (changed in place; the sensor reads it under the lock).
    pub(super) seen: Vec<InSight>,
}

/// The looker's body (position, heading, height), as exact bits.
pub(super) type Key = [u64; 5];

/// Every parameter of a vision, as exact bits.
pub(super) type VisionBits = [u64; 5];

pub(super) fn key(mine: &Body) -> Key {
    [
        mine.pos[0].to_bits(),
        mine.pos[1].to_bits(),
        mine.pos[2].to_bits(),
        mine.heading.to_bits(),
        mine.height.to_bits(),
    ]
}

pub(super) fn vision_bits(v: &FriendFoeVision) -> VisionBits {
    [
        v.range.to_bits(),
        v.half_fov.to_bits(),
        v.p0.to_bits(),
        v.k.to_bits(),
        v.misidentification.to_bits(),
    ]
}

impl Looks {
    /// The index of vision `v` in [`visions`](Self::visions), added if new (a run has a few).
    pub(super) fn vision_index(&mut self, v: &FriendFoeVision) -> u32 {
        let bits = vision_bits(v);
        let at = match self.visions.iter().position(|b| *b == bits) {
            Some(at) => at,
            None => {
                if self.visions.len() >= VISIONS_MAX {
                    // Visions that change all the time: start over (the memos name them).
                    self.visions.clear();
                    self.memos.clear();
                }
                self.visions.push(bits);
                self.visions.len() - 1
            }
        };
        // A run has a handful of visions; u32 is plenty.
        at as u32
    }
}

/// Most visions remembered at once.
const VISIONS_MAX: usize = 64;

/// Most changes a look goes through to bring its memo up to date; after more it looks
/// afresh (cheaper than going through them).
pub(super) const SCAN_MAX: usize = 4096;

/// Takes the bodies of the entity indices `ids` (in order) out of `seen` (in id order) and
/// puts them back where `now_seen` sees them.
pub(super) fn update(
    seen: &mut Vec<InSight>,
    ids: &[u32],
    mut now_seen: impl FnMut(u32) -> Option<InSight>,
) {
    // One pass along the list (short, and read right after by the draws).
    let mut at = 0;
    for &e in ids {
        at += seen[at..].iter().take_while(|s| s.id.0 < e).count();
        let was = seen.get(at).is_some_and(|s| s.id.0 == e);
        match (was, now_seen(e)) {
            (true, Some(s)) => seen[at] = s,
            (true, None) => {
                seen.remove(at);
            }
            (false, Some(s)) => seen.insert(at, s),
            (false, None) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_memo_is_small() {
        // The body's bits, the vision's index, the clock and the list (it was 104 bytes and
        // an `Arc` of 40 more before the vision was named by an index).
        assert!(std::mem::size_of::<Option<Memo>>() <= 80);
    }
}
