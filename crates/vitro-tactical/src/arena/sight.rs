//! A memo of line-of-sight answers between exact points.
//!
//! Line of sight is a pure function of its two end points (the site does not change during
//! a run), and vision asks the same questions again and again: a hidden trooper at a street
//! node looks every second at the same neighbours at their nodes. The memo keeps the answer
//! per pair of points, keyed by the points' exact bits, so an answer from the memo is the
//! answer the ray cast gives, whatever the memo forgot before: forgetting costs only casts.
//!
//! The table is set-associative: a pair's hash picks a set of [`WAYS`] slots, each slot one
//! 64-byte cache line holding the key (six words) and the answer, so a question answered by
//! the set's most recent pair reads one line (a hash map with its control bytes apart reads
//! two, and one of two generations four). A set keeps its pairs most recent first; a new
//! pair goes in front and, when the set is full, the least recent is forgotten. The table
//! starts small and doubles when a set overflows while at least half of the slots are used,
//! up to [`CAPACITY`] slots (64 MiB); from then on it only forgets within a set. (Doubling
//! at a quarter instead forgot fewer pairs, 84 against 923 more casts than the hash maps'
//! 75,575 at 2,020 entities in 600 s, for 16 MiB more; at three quarters 3,619.)

/// Most pairs kept: 2^20 slots of 64 bytes, 64 MiB (the two generations of hash maps before
/// kept up to 2 x 2^19 pairs in about as many bytes again).
pub(crate) const CAPACITY: usize = 1 << 20;

/// Slots in a set.
const WAYS: usize = 4;

/// Sets of a new table.
const FIRST_SETS: usize = 1 << 8;

/// Two points as exact bits (fields, not an array: compared inline, not by `memcmp`).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
struct Key(u64, u64, u64, u64, u64, u64);

impl Key {
    /// A well mixed hash of the six words.
    #[inline]
    fn hash(&self) -> u64 {
        let mut h = 0u64;
        for x in [self.0, self.1, self.2, self.3, self.4, self.5] {
            let m = u128::from(h ^ x) * 0x9E37_79B9_7F4A_7C15u128;
            h = (m as u64) ^ ((m >> 64) as u64);
        }
        h ^= h >> 33;
        h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        h ^ (h >> 33)
    }
}

/// No pair in the slot.
const EMPTY: u8 = 0;
/// The pair's answer is "not visible".
const HIDDEN: u8 = 1;
/// The pair's answer is "visible".
const SEEN: u8 = 2;

/// One pair and its answer: one cache line.
#[derive(Copy, Clone, Debug, Default)]
#[repr(C, align(64))]
struct Slot {
    key: Key,
    /// [`EMPTY`], [`HIDDEN`] or [`SEEN`].
    state: u8,
}

/// The slots of one hash, most recent first, the empty ones last.
#[derive(Copy, Clone, Debug, Default)]
#[repr(C, align(256))]
struct Set([Slot; WAYS]);

impl Set {
    /// Puts `key` in front with its answer; true when the least recent pair was forgotten.
    #[inline]
    fn push_front(&mut self, key: Key, seen: bool) -> bool {
        let forgot = self.0[WAYS - 1].state != EMPTY;
        self.0.rotate_right(1);
        self.0[0] = Slot {
            key,
            state: if seen { SEEN } else { HIDDEN },
        };
        forgot
    }
}

/// The memo (see the module documentation).
#[derive(Debug)]
pub(crate) struct SightMemo {
    /// A power of two of sets (none before the first question).
    sets: Vec<Set>,
    /// Pairs kept.
    len: usize,
    /// Most slots.
    capacity: usize,
    /// Answers looked up and found (for benchmarks).
    pub(crate) hits: u64,
    /// Answers computed.
    pub(crate) misses: u64,
}

impl Default for SightMemo {
    fn default() -> Self {
        SightMemo::with_capacity(CAPACITY)
    }
}

impl SightMemo {
    /// A memo of at most `capacity` slots (rounded up to whole sets of a power of two).
    pub(crate) fn with_capacity(capacity: usize) -> Self {
        SightMemo {
            sets: Vec::new(),
            len: 0,
            capacity: capacity.max(WAYS),
            hits: 0,
            misses: 0,
        }
    }

    /// Whether `b` is visible from `a`: from the memo, or from `cast` (then kept).
    #[inline]
    pub(crate) fn visible(
        &mut self,
        a: [f64; 3],
        b: [f64; 3],
        cast: impl FnOnce([f64; 3], [f64; 3]) -> bool,
    ) -> bool {
        let key = Key(
            a[0].to_bits(),
            a[1].to_bits(),
            a[2].to_bits(),
            b[0].to_bits(),
            b[1].to_bits(),
            b[2].to_bits(),
        );
        let h = key.hash();
        let mask = self.sets.len().wrapping_sub(1);
        if let Some(set) = self.sets.get_mut(h as usize & mask) {
            for w in 0..WAYS {
                let state = set.0[w].state;
                if state == EMPTY {
                    break;
                }
                if set.0[w].key == key {
                    self.hits += 1;
                    if w > 0 {
                        set.0[..=w].rotate_right(1);
                    }
                    return state == SEEN;
                }
            }
        }
        self.misses += 1;
        let v = cast(a, b);
        self.insert(key, h, v);
        v
    }

    /// Keeps a new pair, growing the table or forgetting a pair of its set.
    #[cold]
    #[inline(never)]
    fn insert(&mut self, key: Key, h: u64, seen: bool) {
        let slots = self.sets.len() * WAYS;
        if self.sets.is_empty() {
            self.grow((FIRST_SETS * WAYS).min(self.capacity).div_ceil(WAYS));
        } else if self.sets[h as usize & (self.sets.len() - 1)].0[WAYS - 1].state != EMPTY
            && 2 * slots <= self.capacity
            && 2 * self.len >= slots
        {
            self.grow(2 * self.sets.len());
        }
        let i = h as usize & (self.sets.len() - 1);
        if !self.sets[i].push_front(key, seen) {
            self.len += 1;
        }
    }

    /// Moves the pairs into a table of `n` sets (a power of two, at least as many as now):
    /// a set's pairs go to two sets of the new table, in the same order.
    fn grow(&mut self, n: usize) {
        let n = n.next_power_of_two();
        let old = std::mem::replace(&mut self.sets, vec![Set::default(); n]);
        for set in old {
            for s in set.0.iter().rev().filter(|s| s.state != EMPTY) {
                let i = s.key.hash() as usize & (n - 1);
                self.sets[i].push_front(s.key, s.state == SEEN);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Point `i` of a line of distinct points.
    fn p(i: usize) -> [f64; 3] {
        [i as f64, 0.5, 1.0]
    }

    /// A pure stand-in for the ray cast.
    fn truth(a: [f64; 3], b: [f64; 3]) -> bool {
        (a[0] as usize * 7 + b[0] as usize).is_multiple_of(3)
    }

    #[test]
    fn answers_come_from_the_cast_then_from_the_memo() {
        assert_eq!(std::mem::size_of::<Slot>(), 64);
        let mut m = SightMemo::default();
        let (a, b) = ([0.0, 0.0, 1.0], [5.0, 0.0, 1.0]);
        assert!(!m.visible(a, b, |_, _| false));
        // The memo answers, whatever a second cast would say.
        assert!(!m.visible(a, b, |_, _| true));
        assert_eq!((m.hits, m.misses), (1, 1));
        // Another point (one bit apart) is another question.
        let b2 = [f64::from_bits(5.0f64.to_bits() + 1), 0.0, 1.0];
        assert!(m.visible(a, b2, |_, _| true));
        assert_eq!(m.misses, 2);
        // The origin's pair (all bits zero) is a pair like any other.
        assert!(m.visible([0.0; 3], [0.0; 3], |_, _| true));
        assert!(m.visible([0.0; 3], [0.0; 3], |_, _| false));
        assert_eq!((m.hits, m.misses), (2, 3));
    }

    #[test]
    fn the_table_grows_and_forgets_little_below_its_capacity() {
        let mut m = SightMemo::default();
        let n = 20_000;
        for i in 0..n {
            m.visible(p(i), p(i + 1), truth);
        }
        assert_eq!(m.misses, n as u64);
        assert!(
            4 * m.len <= 3 * m.sets.len() * WAYS,
            "{} sets",
            m.sets.len()
        );
        for i in 0..n {
            // A cast that lies: a hit gives the kept answer, a miss the lie.
            let misses = m.misses;
            let v = m.visible(p(i), p(i + 1), |a, b| !truth(a, b));
            assert_eq!(v, truth(p(i), p(i + 1)) ^ (m.misses > misses));
        }
        let forgot = m.misses - n as u64;
        // About 8 %: a set that overflows below half full forgets its least recent pair.
        assert!(forgot * 10 <= n as u64, "{forgot} of {n} pairs forgotten");
    }

    #[test]
    fn a_full_table_keeps_its_bound_and_answers_as_the_cast() {
        let cap = 64;
        let mut m = SightMemo::with_capacity(cap);
        for round in 0..3 {
            for i in 0..1000 {
                let (a, b) = (p(i), p(i % 37));
                assert_eq!(
                    m.visible(a, b, truth),
                    truth(a, b),
                    "round {round}, pair {i}"
                );
                assert!(m.sets.len() * WAYS <= cap && m.len <= cap);
                // The pair just asked is the front of its set: asked again, a hit.
                let hits = m.hits;
                assert_eq!(m.visible(a, b, |_, _| unreachable!()), truth(a, b));
                assert_eq!(m.hits, hits + 1);
            }
        }
        assert_eq!(m.len, cap, "full");
        assert_eq!(m.hits + m.misses, 6000);
    }
}
