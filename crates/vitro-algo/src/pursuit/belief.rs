//! Information sets: where an unseen piece may be, with a distribution for sampling.

use super::Arena;
use crate::graph::NodeId;
use rand::Rng;

/// The set of vertices an opponent piece may occupy, with a probability for each.
///
/// Invariant: `prob[v] > 0` exactly for members (up to floating-point underflow, which is
/// guarded against by keeping membership separately), and the probabilities sum to 1 when the
/// set is not empty.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Belief {
    member: Vec<bool>,
    prob: Vec<f64>,
    size: usize,
}

impl Belief {
    /// Anywhere among `n` vertices, uniformly.
    pub fn uniform(n: usize) -> Belief {
        let p = if n == 0 { 0.0 } else { 1.0 / n as f64 };
        Belief {
            member: vec![true; n],
            prob: vec![p; n],
            size: n,
        }
    }

    /// Surely at `v` (of `n` vertices).
    pub fn at(n: usize, v: NodeId) -> Belief {
        let mut b = Belief {
            member: vec![false; n],
            prob: vec![0.0; n],
            size: 0,
        };
        b.collapse(v);
        b
    }

    /// Number of possible vertices.
    pub fn size(&self) -> usize {
        self.size
    }

    /// True if the piece may be at `v`.
    pub fn contains(&self, v: NodeId) -> bool {
        self.member.get(v).copied().unwrap_or(false)
    }

    /// The probability of `v` (0 for non-members).
    pub fn prob(&self, v: NodeId) -> f64 {
        if self.contains(v) { self.prob[v] } else { 0.0 }
    }

    /// The possible vertices, ascending.
    pub fn members(&self) -> impl Iterator<Item = NodeId> + '_ {
        self.member
            .iter()
            .enumerate()
            .filter(|(_, m)| **m)
            .map(|(v, _)| v)
    }

    /// The most probable vertex (ties: the smallest id); `None` if the set is empty.
    pub fn most_likely(&self) -> Option<NodeId> {
        let mut best: Option<(NodeId, f64)> = None;
        for v in self.members() {
            if best.is_none_or(|(_, p)| self.prob[v] > p) {
                best = Some((v, self.prob[v]));
            }
        }
        best.map(|(v, _)| v)
    }

    /// A vertex drawn from the distribution; `None` if the set is empty.
    pub fn sample(&self, rng: &mut impl Rng) -> Option<NodeId> {
        let mut last = None;
        let mut x = rng.random::<f64>();
        for v in self.members() {
            last = Some(v);
            x -= self.prob[v];
            if x < 0.0 {
                return Some(v);
            }
        }
        last
    }

    /// A sampler of the distribution as it stands: draws in `O(log size)` instead of
    /// [`Belief::sample`]'s linear scan, for searches that sample many times per decision.
    pub fn sampler(&self) -> Sampler {
        let mut verts = Vec::with_capacity(self.size);
        let mut cumulative = Vec::with_capacity(self.size);
        let mut total = 0.0;
        for v in self.members() {
            total += self.prob[v];
            verts.push(v);
            cumulative.push(total);
        }
        Sampler { verts, cumulative }
    }

    /// The piece moved one step or stayed: every member spreads to its closed neighbourhood,
    /// its probability shared equally (a random-walk model).
    pub fn predict(&mut self, arena: &Arena) {
        let n = self.member.len();
        let mut member = vec![false; n];
        let mut prob = vec![0.0; n];
        for v in 0..n {
            if !self.member[v] {
                continue;
            }
            let moves = arena.moves(v);
            let share = self.prob[v] / moves.len() as f64;
            for &w in moves {
                member[w] = true;
                prob[w] += share;
            }
        }
        self.member = member;
        self.prob = prob;
        self.size = self.member.iter().filter(|m| **m).count();
        self.normalize();
    }

    /// The piece was seen at `v`.
    pub fn collapse(&mut self, v: NodeId) {
        self.member.fill(false);
        self.prob.fill(0.0);
        if v < self.member.len() {
            self.member[v] = true;
            self.prob[v] = 1.0;
            self.size = 1;
        } else {
            self.size = 0;
        }
    }

    /// Observers at `observers` did not see the piece: every vertex they see is removed.
    /// The set becomes empty only if the observations contradict each other.
    pub fn exclude_seen_by(&mut self, arena: &Arena, observers: &[NodeId]) {
        for &o in observers {
            for &v in arena.visible_from(o) {
                if self.member[v] {
                    self.member[v] = false;
                    self.prob[v] = 0.0;
                    self.size -= 1;
                }
            }
        }
        self.normalize();
    }

    /// The piece is at none of `vertices` (e.g. the pursuers' own vertices, after a move that
    /// caught nobody). The set becomes empty only if that contradicts it.
    pub fn remove(&mut self, vertices: &[NodeId]) {
        for &v in vertices {
            if self.member.get(v).copied().unwrap_or(false) {
                self.member[v] = false;
                self.prob[v] = 0.0;
                self.size -= 1;
            }
        }
        self.normalize();
    }

    fn normalize(&mut self) {
        let total: f64 = self.members().map(|v| self.prob[v]).sum();
        if total > 0.0 && total.is_finite() {
            for p in &mut self.prob {
                *p /= total;
            }
        } else if self.size > 0 {
            let p = 1.0 / self.size as f64;
            for v in 0..self.member.len() {
                self.prob[v] = if self.member[v] { p } else { 0.0 };
            }
        }
    }
}

/// Draws vertices from a [`Belief`] frozen at [`Belief::sampler`] time.
///
/// ```
/// use rand::SeedableRng;
/// use vitro_algo::pursuit::Belief;
///
/// let b = Belief::uniform(4);
/// let s = b.sampler();
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// assert!(s.sample(&mut rng).is_some_and(|v| v < 4));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sampler {
    verts: Vec<NodeId>,
    /// Running sums of the members' probabilities, in vertex order.
    cumulative: Vec<f64>,
}

impl Sampler {
    /// A vertex drawn from the distribution (one uniform draw, like [`Belief::sample`], and
    /// the same vertex up to rounding); `None` if the set is empty.
    pub fn sample(&self, rng: &mut impl Rng) -> Option<NodeId> {
        let x = rng.random::<f64>();
        let i = self.cumulative.partition_point(|&c| c <= x);
        self.verts
            .get(i.min(self.verts.len().saturating_sub(1)))
            .copied()
    }
}
