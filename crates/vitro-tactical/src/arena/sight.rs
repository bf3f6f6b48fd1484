//! A memo of line-of-sight answers between exact points.
//!
//! Line of sight is a pure function of its two end points (the site does not change during
//! a run), and vision asks the same questions again and again: a hidden trooper at a street
//! node looks every second at the same neighbours at their nodes. The memo keeps the answer
//! per pair of points, keyed by the points' exact bits, so an answer from the memo is the
//! answer the ray cast gives. It holds at most [`CAPACITY`] pairs in two generations: when
//! the newer one is full the older one is dropped, and a pair found in the older one moves
//! to the newer.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Most pairs kept in one generation.
pub(crate) const CAPACITY: usize = 1 << 19;

/// Two points as exact bits (fields, not an array: compared inline, not by `memcmp`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
struct Key(u64, u64, u64, u64, u64, u64);

/// A fast hasher for keys of exact float bits (not a source of any iteration order: the
/// memo is only ever looked up).
#[derive(Default)]
pub(crate) struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 33;
        x = x.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        x ^ (x >> 33)
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        let m = u128::from(self.0 ^ x) * 0x9E37_79B9_7F4A_7C15u128;
        self.0 = (m as u64) ^ ((m >> 64) as u64);
    }
}

type Map = HashMap<Key, bool, BuildHasherDefault<BitsHasher>>;

/// The memo (see the module documentation).
#[derive(Debug, Default)]
pub(crate) struct SightMemo {
    new: Map,
    old: Map,
    /// Answers looked up and found (for benchmarks).
    pub(crate) hits: u64,
    /// Answers computed.
    pub(crate) misses: u64,
}

impl SightMemo {
    /// Whether `b` is visible from `a`: from the memo, or from `cast` (then kept).
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
        if let Some(&v) = self.new.get(&key) {
            self.hits += 1;
            return v;
        }
        let v = match self.old.get(&key) {
            Some(&v) => {
                self.hits += 1;
                v
            }
            None => {
                self.misses += 1;
                cast(a, b)
            }
        };
        if self.new.len() >= CAPACITY {
            self.old = std::mem::take(&mut self.new);
        }
        self.new.insert(key, v);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_come_from_the_cast_then_from_the_memo() {
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
    }

    #[test]
    fn a_full_generation_ages_and_old_answers_survive_one_turn() {
        let mut m = SightMemo::default();
        let p = |i: usize| [i as f64, 0.0, 0.0];
        for i in 0..CAPACITY {
            m.visible(p(i), p(0), |_, _| i % 2 == 0);
        }
        // The next new pair turns the generation; the first pairs are then in the old one.
        m.visible(p(CAPACITY), p(0), |_, _| true);
        assert_eq!(m.new.len(), 1);
        assert!(
            m.visible(p(0), p(0), |_, _| false),
            "kept in the old generation"
        );
        assert!(!m.visible(p(1), p(0), |_, _| true));
    }
}
