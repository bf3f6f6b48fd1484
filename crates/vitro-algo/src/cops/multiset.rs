//! Ranking of cop placements: sorted multisets of `k` vertices out of `n`, numbered densely
//! by the combinatorial number system, so a position of indistinguishable cops is one index.

use super::options::CopsError;

/// All multisets of size `k` over `0..n`, with O(k) ranking and O(1) access by rank.
#[derive(Clone, Debug)]
pub(crate) struct Multisets {
    k: usize,
    /// `binom[a * (k + 1) + b]` = C(a, b) for `a < n + k`, `b <= k`.
    binom: Vec<u64>,
    /// Member `r` occupies `members[r * k .. r * k + k]`, sorted ascending.
    members: Vec<u32>,
    count: usize,
}

impl Multisets {
    /// Enumerates the multisets of size `k` over `0..n`, refusing if there are more than
    /// `limit` of them.
    pub(crate) fn new(n: usize, k: usize, limit: u64) -> Result<Multisets, CopsError> {
        let rows = n + k;
        let mut binom = vec![0u64; rows * (k + 1)];
        for a in 0..rows {
            binom[a * (k + 1)] = 1;
            for b in 1..=k.min(a) {
                let left = binom[(a - 1) * (k + 1) + b - 1];
                let up = if b < a {
                    binom[(a - 1) * (k + 1) + b]
                } else {
                    0
                };
                binom[a * (k + 1) + b] = left.saturating_add(up);
            }
        }
        // C(n + k - 1, k) multisets (1 when k = 0, 0 when n = 0 < k).
        let count = if k == 0 {
            1
        } else if n == 0 {
            0
        } else {
            binom[(n + k - 1) * (k + 1) + k]
        };
        let too_many = CopsError::TooManyStates {
            cops: k,
            states: count.saturating_mul(n as u64).saturating_mul(2),
            limit,
        };
        if count > limit {
            return Err(too_many);
        }
        let count = usize::try_from(count).map_err(|_| too_many)?;
        let mut sets = Multisets {
            k,
            binom,
            members: vec![0; count * k],
            count,
        };
        if k > 0 && n > 0 {
            let mut tuple = vec![0u32; k];
            loop {
                let rank = sets.rank(&tuple);
                sets.members[rank * k..rank * k + k].copy_from_slice(&tuple);
                // Next nondecreasing tuple in lexicographic order.
                let Some(i) = (0..k).rev().find(|&i| (tuple[i] as usize) + 1 < n) else {
                    break;
                };
                let next = tuple[i] + 1;
                tuple[i..].fill(next);
            }
        }
        Ok(sets)
    }

    /// How many multisets there are.
    pub(crate) fn len(&self) -> usize {
        self.count
    }

    /// The rank of a sorted multiset (ascending, each entry `< n`, length `k`).
    pub(crate) fn rank(&self, sorted: &[u32]) -> usize {
        let width = self.k + 1;
        let mut rank = 0u64;
        for (i, &c) in sorted.iter().enumerate() {
            rank += self.binom[(c as usize + i) * width + i + 1];
        }
        rank as usize
    }

    /// The sorted multiset with the given rank.
    pub(crate) fn get(&self, rank: usize) -> &[u32] {
        &self.members[rank * self.k..rank * self.k + self.k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_are_a_bijection() {
        for (n, k) in [(1, 1), (4, 1), (4, 2), (5, 3), (3, 4), (6, 0)] {
            let sets = Multisets::new(n, k, u64::MAX).unwrap();
            // rank(get(r)) == r makes get injective; every entry is a sorted multiset over 0..n.
            for r in 0..sets.len() {
                let m = sets.get(r);
                assert!(m.windows(2).all(|w| w[0] <= w[1]));
                assert!(m.iter().all(|&c| (c as usize) < n));
                assert_eq!(sets.rank(m), r);
            }
        }
        assert_eq!(Multisets::new(30, 3, u64::MAX).unwrap().len(), 4960);
        assert!(Multisets::new(30, 3, 100).is_err());
    }
}
