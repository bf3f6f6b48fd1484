//! The memo of looks: per looker, what its last look could see (see [`super::seen`] for how
//! a look uses it).

use super::grid::{BodyGrid, bits_eq, body_bits};
use crate::sensor::{FriendFoeVision, InSight, Sighting};
use crate::world::{Body, Side};
use vitro::entity::EntityId;

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
    pub(super) seen: Seen,
}

/// What a look can see, in id order, split in two parallel lists: what the draws read of
/// every body (its id, side, detection probability and distance: 24 bytes), and what only a
/// sighting kept reads (position and bearing). A look walks and draws along the short
/// records and reads the rest only for the sightings it keeps.
#[derive(Debug, Default, Clone, PartialEq)]
pub(crate) struct Seen {
    /// Per body: id, side, detection probability, distance.
    pub(super) heads: Vec<Head>,
    /// Per body (same order): position and bearing.
    pub(super) tails: Vec<Tail>,
}

/// What the draws of a look read of a body it can see.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct Head {
    /// The entity index.
    pub(super) id: u32,
    /// Its true side.
    pub(super) side: Side,
    /// Its detection probability.
    pub(super) p_detect: f64,
    /// How far, metres.
    pub(super) distance: f64,
}

/// The rest of what a look knows of a body it can see.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct Tail {
    /// Its true position.
    pub(super) pos: [f64; 3],
    /// Direction, radians counter-clockwise from east.
    pub(super) bearing: f64,
}

impl Seen {
    /// The bodies of `list` (in id order), split.
    pub(super) fn of(list: impl Iterator<Item = InSight>) -> Seen {
        let (heads, tails) = list.map(split).unzip();
        Seen { heads, tails }
    }

    /// How many bodies.
    pub(super) fn len(&self) -> usize {
        self.heads.len()
    }

    /// Body `k`, whole.
    pub(super) fn get(&self, k: usize) -> InSight {
        let (h, t) = (self.heads[k], self.tails[k]);
        InSight {
            id: EntityId(h.id),
            pos: t.pos,
            side: h.side,
            distance: h.distance,
            p_detect: h.p_detect,
            bearing: t.bearing,
        }
    }

    /// Every body, whole, in id order.
    pub(super) fn to_vec(&self) -> Vec<InSight> {
        (0..self.len()).map(|k| self.get(k)).collect()
    }

    /// The sighting of body `k` taken for `seen_as`.
    pub(super) fn sighting(&self, k: usize, seen_as: Side) -> Sighting {
        let (h, t) = (self.heads[k], self.tails[k]);
        Sighting {
            id: EntityId(h.id),
            pos: t.pos,
            distance: h.distance,
            bearing: t.bearing,
            seen_as,
        }
    }
}

/// A body a look can see, in its two parts.
fn split(s: InSight) -> (Head, Tail) {
    let head = Head {
        id: s.id.0,
        side: s.side,
        p_detect: s.p_detect,
        distance: s.distance,
    };
    let tail = Tail {
        pos: s.pos,
        bearing: s.bearing,
    };
    (head, tail)
}

/// The looker's body (position, heading, height), as exact bits.
pub(super) type Key = [u64; 5];

/// Every parameter of a vision, as exact bits.
pub(super) type VisionBits = [u64; 5];

pub(super) fn key(mine: &Body) -> Key {
    body_bits(mine)
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
        let at = match self.visions.iter().position(|b| bits_eq(b, &bits)) {
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
    seen: &mut Seen,
    ids: &[u32],
    mut now_seen: impl FnMut(u32) -> Option<InSight>,
) {
    // One pass along the short records (read right after by the draws).
    let Seen { heads, tails } = seen;
    let mut at = 0;
    for &e in ids {
        at += heads[at..].iter().take_while(|s| s.id < e).count();
        let was = heads.get(at).is_some_and(|s| s.id == e);
        match (was, now_seen(e).map(split)) {
            (true, Some((h, t))) => (heads[at], tails[at]) = (h, t),
            (true, None) => {
                heads.remove(at);
                tails.remove(at);
            }
            (false, Some((h, t))) => {
                heads.insert(at, h);
                tails.insert(at, t);
            }
            (false, None) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_memo_is_small() {
        // The body's bits, the vision's index, the clock and the two lists (it was 104
        // bytes and an `Arc` of 40 more before the vision was named by an index).
        assert!(std::mem::size_of::<Option<Memo>>() <= 112);
        // What the draws read of a body is 24 bytes (the whole record is 56).
        assert_eq!(std::mem::size_of::<Head>(), 24);
    }

    fn body(id: u32, x: f64) -> InSight {
        InSight {
            id: EntityId(id),
            pos: [x, -x, 0.5 * x],
            side: Side::ALL[id as usize % 3],
            distance: 2.0 * x,
            p_detect: 1.0 / (1.0 + x),
            bearing: 0.1 * x,
        }
    }

    #[test]
    fn the_split_lists_update_as_the_whole_records_did() {
        // The records as one plain list of whole records, updated alongside the split lists.
        let mut whole: Vec<InSight> = [1, 4, 6, 9, 12]
            .iter()
            .map(|&i| body(i, f64::from(i)))
            .collect();
        let mut seen = Seen::of(whole.iter().copied());
        // 4 moves, 6 leaves, 7 and 13 come in, 2 stays out, 12 stays.
        let now = |e: u32| match e {
            4 => Some(body(4, 40.0)),
            7 => Some(body(7, 7.0)),
            12 => Some(body(12, 12.0)),
            13 => Some(body(13, 1.0)),
            _ => None,
        };
        let ids = [2, 4, 6, 7, 12, 13];
        update(&mut seen, &ids, now);
        for &e in &ids {
            let at = whole
                .iter()
                .position(|s| s.id.0 >= e)
                .unwrap_or(whole.len());
            let was = whole.get(at).is_some_and(|s| s.id.0 == e);
            match (was, now(e)) {
                (true, Some(s)) => whole[at] = s,
                (true, None) => drop(whole.remove(at)),
                (false, Some(s)) => whole.insert(at, s),
                (false, None) => {}
            }
        }
        assert_eq!(seen.to_vec(), whole);
        let ids: Vec<u32> = whole.iter().map(|s| s.id.0).collect();
        assert_eq!(ids, [1, 4, 7, 9, 12, 13]);
        assert_eq!(seen.get(1).pos, [40.0, -40.0, 20.0]);
    }
}
