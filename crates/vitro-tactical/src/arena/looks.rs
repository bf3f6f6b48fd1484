//! The memo of looks: per looker, what its last look could see (see [`super::seen`] for how
//! a look uses it).

use super::grid::BodyGrid;
use crate::sensor::{FriendFoeVision, InSight};
use crate::world::Body;
use std::sync::Arc;

/// The grids of bodies and the memo of looks, behind one lock of the arena.
#[derive(Debug, Default)]
pub(crate) struct Looks {
    /// The active bodies on a grid.
    pub(crate) grid: BodyGrid,
    /// The active aircraft on a grid of their own ([`Arena::aircraft_within`]).
    pub(crate) air: BodyGrid,
    /// Per looker's entity index: its last look.
    pub(super) memos: Vec<Option<Memo>>,
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

/// One looker's last look.
#[derive(Debug)]
pub(super) struct Memo {
    /// The looker's body and the vision, as bits.
    pub(super) key: Key,
    /// The grid's generation and clock when it was computed.
    pub(super) at: (u64, u64),
    /// What it could see, in id order (shared with the sensor that asked; changed in place
    /// once the sensor let go of it).
    pub(super) seen: Arc<Vec<InSight>>,
}

/// The looker's body (position, heading, height) and every parameter of the vision, as
/// exact bits.
pub(super) type Key = [u64; 10];

pub(super) fn key(mine: &Body, v: &FriendFoeVision) -> Key {
    [
        mine.pos[0].to_bits(),
        mine.pos[1].to_bits(),
        mine.pos[2].to_bits(),
        mine.heading.to_bits(),
        mine.height.to_bits(),
        v.range.to_bits(),
        v.half_fov.to_bits(),
        v.p0.to_bits(),
        v.k.to_bits(),
        v.misidentification.to_bits(),
    ]
}

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
