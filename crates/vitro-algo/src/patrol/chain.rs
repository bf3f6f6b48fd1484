//! The patroller's Markov chain on a support set, with its transition entries laid out flat,
//! and the capture probabilities (and their gradients) as functions of those entries.
//!
//! For a target `t` with deadline `D`, the capture probability from vertex `h` is the chance
//! that the walk started at `h` stands on `t` at one of the steps `1..=D`:
//! `q_0 = 0`, `q_s(x) = Σ_y α(x, y) · ([y = t] + [y ≠ t] · q_{s-1}(y))`, `P(t, h) = q_D(h)`.
//! Unrolled, `P(t, h)` is a sum over walks of products of entries: a polynomial with
//! non-negative coefficients, hence non-decreasing in every entry — the fact the exact
//! branch and bound relies on. The same code evaluates it at non-stochastic entry vectors.

use crate::graph::{Graph, NodeId};

/// One attack option's data, in support-local terms.
#[derive(Clone, Debug)]
pub(crate) struct ChainTarget {
    /// The target's local index, or `None` if the target lies outside the support.
    pub(crate) local: Option<usize>,
    /// Attack duration in steps (at least 1).
    pub(crate) deadline: usize,
    /// The attacker's gain if the attack succeeds.
    pub(crate) value: f64,
}

/// A Markov chain restricted to a support set of vertices.
#[derive(Clone, Debug)]
pub(crate) struct Chain {
    /// The support, ascending; local index `i` is vertex `nodes[i]`.
    pub(crate) nodes: Vec<NodeId>,
    /// Entries of local row `i` are `row_start[i]..row_start[i + 1]`.
    pub(crate) row_start: Vec<usize>,
    /// Local successor of each entry (rows list the closed neighbourhood within the support,
    /// ascending, the vertex itself included).
    pub(crate) to: Vec<usize>,
    /// Local source of each entry.
    pub(crate) from: Vec<usize>,
    pub(crate) targets: Vec<ChainTarget>,
}

impl Chain {
    /// The chain on `support` (sorted, distinct vertices of `graph`), attacked at `targets`
    /// given as `(vertex, deadline, value)`.
    pub(crate) fn new(
        graph: &Graph,
        support: &[NodeId],
        targets: &[(NodeId, usize, f64)],
    ) -> Chain {
        let local = |v: NodeId| support.binary_search(&v).ok();
        let mut row_start = vec![0];
        let mut to = Vec::new();
        let mut from = Vec::new();
        for (i, &v) in support.iter().enumerate() {
            let mut row: Vec<usize> = graph
                .neighbors(v)
                .iter()
                .filter_map(|&w| local(w))
                .collect();
            row.push(i);
            row.sort_unstable();
            from.extend(std::iter::repeat_n(i, row.len()));
            to.extend(row);
            row_start.push(to.len());
        }
        let targets = targets
            .iter()
            .map(|&(node, deadline, value)| ChainTarget {
                local: local(node),
                deadline,
                value,
            })
            .collect();
        Chain {
            nodes: support.to_vec(),
            row_start,
            to,
            from,
            targets,
        }
    }

    /// Number of support vertices.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Number of transition entries.
    pub(crate) fn entries(&self) -> usize {
        self.to.len()
    }

    /// The entry range of local row `i`.
    pub(crate) fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.row_start[i]..self.row_start[i + 1]
    }

    /// `q_s` for `s = 0..=deadline` (flattened, `len()` values each) for target `t`.
    fn hitting_tables(&self, alpha: &[f64], t: usize, local: usize, out: &mut Vec<f64>) {
        let n = self.len();
        let deadline = self.targets[t].deadline;
        out.clear();
        out.resize((deadline + 1) * n, 0.0);
        for s in 1..=deadline {
            let (done, rest) = out.split_at_mut(s * n);
            let previous = &done[(s - 1) * n..];
            let current = &mut rest[..n];
            for (x, slot) in current.iter_mut().enumerate() {
                let mut sum = 0.0;
                for e in self.row(x) {
                    let y = self.to[e];
                    let onward = if y == local { 1.0 } else { previous[y] };
                    sum += alpha[e] * onward;
                }
                *slot = sum;
            }
        }
    }

    /// Capture probabilities `out[t * len() + h]` for every target and local start `h`.
    pub(crate) fn capture(&self, alpha: &[f64], out: &mut Vec<f64>) {
        let n = self.len();
        out.clear();
        out.resize(self.targets.len() * n, 0.0);
        let mut table = Vec::new();
        for (t, target) in self.targets.iter().enumerate() {
            if let Some(local) = target.local {
                self.hitting_tables(alpha, t, local, &mut table);
                let last = target.deadline * n;
                out[t * n..t * n + n].copy_from_slice(&table[last..last + n]);
            }
        }
    }

    /// Upper bounds on the capture probabilities of every policy whose entries lie in the
    /// box `lo ≤ α ≤ hi` (rows stochastic), in the layout of [`Chain::capture`].
    ///
    /// The recursion is the one of [`Chain::capture`] with each step's row maximised on its
    /// own: `q̄_s(x) = max over stochastic rows α_x in the box of Σ_y α(x, y) · w̄_{s−1}(y)`,
    /// a fractional knapsack solved greedily (fill `lo`, then pour the remaining mass into the
    /// entries with the largest onward value). Each step may pick a different row, so this
    /// relaxes the true recursion and bounds it from above; it is exact when the box is a point.
    pub(crate) fn capture_upper(&self, lo: &[f64], hi: &[f64], out: &mut Vec<f64>) {
        let n = self.len();
        out.clear();
        out.resize(self.targets.len() * n, 0.0);
        let mut previous = vec![0.0; n];
        let mut current = vec![0.0; n];
        let mut order: Vec<(f64, usize)> = Vec::new();
        for (t, target) in self.targets.iter().enumerate() {
            let Some(local) = target.local else {
                continue;
            };
            previous.fill(0.0);
            for _ in 0..target.deadline {
                for (x, slot) in current.iter_mut().enumerate() {
                    order.clear();
                    let mut sum = 0.0;
                    let mut mass = 1.0;
                    for e in self.row(x) {
                        let y = self.to[e];
                        let onward = if y == local { 1.0 } else { previous[y] };
                        sum += lo[e] * onward;
                        mass -= lo[e];
                        order.push((onward, e));
                    }
                    order.sort_by(|a, b| b.0.total_cmp(&a.0));
                    for &(onward, e) in &order {
                        if mass <= 0.0 {
                            break;
                        }
                        let add = (hi[e] - lo[e]).min(mass);
                        sum += add * onward;
                        mass -= add;
                    }
                    *slot = sum.min(1.0);
                }
                std::mem::swap(&mut previous, &mut current);
            }
            out[t * n..t * n + n].copy_from_slice(&previous);
        }
    }

    /// The attacker's best expected gain, `max over (t, h)` of `value_t · (1 − P(t, h))`
    /// (probabilities above 1, possible at non-stochastic entries, count as 1).
    pub(crate) fn loss(&self, alpha: &[f64], scratch: &mut Vec<f64>) -> f64 {
        self.capture(alpha, scratch);
        self.loss_from(scratch)
    }

    /// As [`Chain::loss`], from capture probabilities already computed.
    pub(crate) fn loss_from(&self, capture: &[f64]) -> f64 {
        let n = self.len();
        let mut worst: f64 = 0.0;
        for (t, target) in self.targets.iter().enumerate() {
            for &p in &capture[t * n..t * n + n] {
                worst = worst.max(target.value * (1.0 - p.min(1.0)));
            }
        }
        worst
    }

    /// Gradients of `P(t, h)` with respect to every entry, for every local start `h`:
    /// `out[h * entries() + e]`. Zero when the target lies outside the support.
    pub(crate) fn gradients(&self, alpha: &[f64], t: usize, out: &mut Vec<f64>) {
        let n = self.len();
        let m = self.entries();
        out.clear();
        out.resize(n * m, 0.0);
        let Some(local) = self.targets[t].local else {
            return;
        };
        let deadline = self.targets[t].deadline;
        let mut table = Vec::new();
        self.hitting_tables(alpha, t, local, &mut table);
        // onward(j, y): value of stepping onto y with j steps left afterwards.
        let onward = |j: usize, y: usize| if y == local { 1.0 } else { table[j * n + y] };
        let mut reach = vec![0.0; n];
        let mut next = vec![0.0; n];
        for h in 0..n {
            // reach = probability of standing at x after s − 1 steps without having hit t.
            reach.fill(0.0);
            reach[h] = 1.0;
            let grad = &mut out[h * m..(h + 1) * m];
            for s in 1..=deadline {
                next.fill(0.0);
                for e in 0..m {
                    let (x, y) = (self.from[e], self.to[e]);
                    if reach[x] == 0.0 {
                        continue;
                    }
                    grad[e] += reach[x] * onward(deadline - s, y);
                    if y != local {
                        next[y] += reach[x] * alpha[e];
                    }
                }
                std::mem::swap(&mut reach, &mut next);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;

    #[test]
    fn box_bounds_contain_every_policy_in_the_box() {
        let g = graph::cycle(4).unwrap();
        let chain = Chain::new(&g, &[0, 1, 2, 3], &[(0, 3, 1.0), (2, 2, 2.0)]);
        let m = chain.entries();
        // A box around a policy, and policies at its corners (renormalised into the box).
        let centre: Vec<f64> = (0..m).map(|e| [0.5, 0.3, 0.2][e % 3]).collect();
        let lo: Vec<f64> = centre.iter().map(|c| (c - 0.05f64).max(0.0)).collect();
        let hi: Vec<f64> = centre.iter().map(|c| (c + 0.05f64).min(1.0)).collect();
        let mut upper = Vec::new();
        chain.capture_upper(&lo, &hi, &mut upper);
        let mut exact = Vec::new();
        chain.capture(&centre, &mut exact);
        for (u, p) in upper.iter().zip(&exact) {
            assert!(u >= p && *u <= p + 0.2, "{u} vs {p}");
        }
        // A point box gives the exact values.
        chain.capture_upper(&centre, &centre, &mut upper);
        for (u, p) in upper.iter().zip(&exact) {
            assert!((u - p).abs() < 1e-12);
        }
    }

    #[test]
    fn path_of_three_hand_computed() {
        // 0 - 1 - 2, targets at both ends with deadline 2.
        let g = graph::path(3).unwrap();
        let chain = Chain::new(&g, &[0, 1, 2], &[(0, 2, 1.0), (2, 2, 1.0)]);
        // Rows: 0 -> {0, 1}; 1 -> {0, 1, 2}; 2 -> {1, 2}.
        assert_eq!(chain.to, vec![0, 1, 0, 1, 2, 1, 2]);
        let alpha = [0.0, 1.0, 0.5, 0.0, 0.5, 1.0, 0.0];
        let mut capture = Vec::new();
        chain.capture(&alpha, &mut capture);
        // From 0: return to 0 within 2 steps = 0 -> 1 -> 0 = 1/2; reach 2 = 0 -> 1 -> 2 = 1/2.
        assert_eq!(capture, vec![0.5, 0.5, 0.5, 0.5, 0.5, 0.5]);
        assert!((chain.loss(&alpha, &mut capture) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn gradients_match_finite_differences() {
        let g = graph::cycle(4).unwrap();
        let chain = Chain::new(&g, &[0, 1, 2, 3], &[(0, 3, 1.0), (2, 2, 2.0)]);
        let alpha: Vec<f64> = (0..chain.entries())
            .map(|e| 0.2 + 0.1 * (e % 3) as f64)
            .collect();
        let mut base = Vec::new();
        chain.capture(&alpha, &mut base);
        for t in 0..2 {
            let mut grad = Vec::new();
            chain.gradients(&alpha, t, &mut grad);
            for e in 0..chain.entries() {
                let mut bumped = alpha.clone();
                bumped[e] += 1e-6;
                let mut after = Vec::new();
                chain.capture(&bumped, &mut after);
                for h in 0..4 {
                    let numeric = (after[t * 4 + h] - base[t * 4 + h]) / 1e-6;
                    let exact = grad[h * chain.entries() + e];
                    assert!(
                        (numeric - exact).abs() < 1e-4,
                        "t{t} h{h} e{e}: {numeric} vs {exact}"
                    );
                }
            }
        }
    }
}
