//! The patroller's Markov chain on a support set, with its transition entries laid out flat,
//! and the capture probabilities (and their gradients) as functions of those entries.
//!
//! Targets may move on periodic schedules, so the chain runs on the product state
//! `(vertex, phase)`, `phase = time mod period`. A *stationary* chain has one row of entries per
//! support vertex, shared by every phase; a *timed* (time-dependent) chain has one row per
//! (vertex, phase). For a target `t` with deadline `D` and vertex `pos_t(φ)` at phase `φ`, the
//! capture probability from state `(h, φ)` is the chance that the walk started there stands on
//! the target's vertex at one of the steps `1..=D`:
//! `q_0 = 0`, `q_s(x, φ) = Σ_y α_φ(x, y) · ([y = pos_t(φ+1)] + [y ≠ pos_t(φ+1)] · q_{s-1}(y, φ+1))`,
//! `P(t, h, φ) = q_D(h, φ)`. Unrolled, `P` is a sum over walks of products of entries: a
//! polynomial with non-negative coefficients, hence non-decreasing in every entry — the fact
//! the exact branch and bound relies on (sharing entries across phases keeps it true). The same
//! code evaluates it at non-stochastic entry vectors. With static targets the period is 1 and
//! both kinds of chain are the plain chain on the support.

use crate::graph::{Graph, NodeId};

/// A target as the chain sees it: its vertex at each phase, its deadline and its value.
pub(crate) type Track = (Vec<NodeId>, usize, f64);

/// One attack option's data, in support-local terms.
#[derive(Clone, Debug)]
pub(crate) struct ChainTarget {
    /// The target's local vertex at each phase, `None` where it lies outside the support.
    pub(crate) local: Vec<Option<usize>>,
    /// Attack duration in steps (at least 1).
    pub(crate) deadline: usize,
    /// The attacker's gain if the attack succeeds.
    pub(crate) value: f64,
}

impl ChainTarget {
    /// Whether the target is ever inside the support.
    pub(crate) fn reachable(&self) -> bool {
        self.local.iter().any(Option::is_some)
    }
}

/// A Markov chain restricted to a support set of vertices, over `period` phases.
#[derive(Clone, Debug)]
pub(crate) struct Chain {
    /// The support, ascending; local index `i` is vertex `nodes[i]`.
    pub(crate) nodes: Vec<NodeId>,
    /// Base entries of local vertex `i` are `row_start[i]..row_start[i + 1]`.
    pub(crate) row_start: Vec<usize>,
    /// Local successor of each base entry (rows list the closed neighbourhood within the
    /// support, ascending, the vertex itself included).
    pub(crate) to: Vec<usize>,
    /// Local source of each base entry.
    pub(crate) from: Vec<usize>,
    /// Phases of the targets' schedules (1 when every target is static).
    pub(crate) period: usize,
    /// Whether each phase has its own rows (a time-dependent policy).
    pub(crate) timed: bool,
    pub(crate) targets: Vec<ChainTarget>,
}

impl Chain {
    /// The chain on `support` (sorted, distinct vertices of `graph`), attacked at `targets`
    /// given as `(vertex per phase, deadline, value)` (each vertex list `period` long).
    pub(crate) fn new(
        graph: &Graph,
        support: &[NodeId],
        targets: &[Track],
        period: usize,
        timed: bool,
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
            .map(|(nodes, deadline, value)| ChainTarget {
                local: nodes.iter().map(|&v| local(v)).collect(),
                deadline: *deadline,
                value: *value,
            })
            .collect();
        Chain {
            nodes: support.to_vec(),
            row_start,
            to,
            from,
            period: period.max(1),
            timed,
            targets,
        }
    }

    /// Number of support vertices.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Number of product states `(vertex, phase)`; state `φ · len() + x`.
    pub(crate) fn states(&self) -> usize {
        self.nodes.len() * self.period
    }

    /// Phases with their own rows: `period` for a timed chain, else 1.
    pub(crate) fn row_phases(&self) -> usize {
        if self.timed { self.period } else { 1 }
    }

    /// Number of transition entries (the free variables).
    pub(crate) fn entries(&self) -> usize {
        self.to.len() * self.row_phases()
    }

    /// Number of stochastic rows: row `φ · len() + x` for a timed chain, row `x` otherwise.
    pub(crate) fn rows(&self) -> usize {
        self.nodes.len() * self.row_phases()
    }

    /// The entry range of row `i` (see [`Chain::rows`]).
    pub(crate) fn row(&self, i: usize) -> std::ops::Range<usize> {
        let (phase, x) = (i / self.len(), i % self.len());
        let offset = phase * self.to.len();
        self.row_start[x] + offset..self.row_start[x + 1] + offset
    }

    /// The entry used by base entry `e` at phase `phase`.
    fn entry(&self, e: usize, phase: usize) -> usize {
        if self.timed {
            e + phase * self.to.len()
        } else {
            e
        }
    }

    /// Local successor of entry `e`.
    pub(crate) fn entry_to(&self, e: usize) -> usize {
        self.to[e % self.to.len()]
    }

    /// `q_s` for `s = 0..=deadline` (flattened, `states()` values each) for target `t`.
    fn hitting_tables(&self, alpha: &[f64], t: usize, out: &mut Vec<f64>) {
        let (n, states) = (self.len(), self.states());
        let target = &self.targets[t];
        out.clear();
        out.resize((target.deadline + 1) * states, 0.0);
        for s in 1..=target.deadline {
            let (done, rest) = out.split_at_mut(s * states);
            let previous = &done[(s - 1) * states..];
            let current = &mut rest[..states];
            for phase in 0..self.period {
                let next = (phase + 1) % self.period;
                let hit = target.local[next];
                for x in 0..n {
                    let mut sum = 0.0;
                    for e in self.row_start[x]..self.row_start[x + 1] {
                        let y = self.to[e];
                        let onward = if Some(y) == hit {
                            1.0
                        } else {
                            previous[next * n + y]
                        };
                        sum += alpha[self.entry(e, phase)] * onward;
                    }
                    current[phase * n + x] = sum;
                }
            }
        }
    }

    /// Capture probabilities `out[t * states() + state]` for every target and start state.
    pub(crate) fn capture(&self, alpha: &[f64], out: &mut Vec<f64>) {
        let states = self.states();
        out.clear();
        out.resize(self.targets.len() * states, 0.0);
        let mut table = Vec::new();
        for (t, target) in self.targets.iter().enumerate() {
            if target.reachable() {
                self.hitting_tables(alpha, t, &mut table);
                let last = target.deadline * states;
                out[t * states..(t + 1) * states].copy_from_slice(&table[last..last + states]);
            }
        }
    }

    /// Upper bounds on the capture probabilities of every policy whose entries lie in the
    /// box `lo ≤ α ≤ hi` (rows stochastic), in the layout of [`Chain::capture`].
    ///
    /// The recursion is the one of [`Chain::capture`] with each step's row maximised on its
    /// own: `q̄_s(x) = max over stochastic rows α_x in the box of Σ_y α(x, y) · w̄_{s−1}(y)`,
    /// a fractional knapsack solved greedily (fill `lo`, then pour the remaining mass into the
    /// entries with the largest onward value). Each step (and each phase of a stationary chain)
    /// may pick a different row, so this relaxes the true recursion and bounds it from above;
    /// it is exact when the box is a point.
    pub(crate) fn capture_upper(&self, lo: &[f64], hi: &[f64], out: &mut Vec<f64>) {
        let (n, states) = (self.len(), self.states());
        out.clear();
        out.resize(self.targets.len() * states, 0.0);
        let mut previous = vec![0.0; states];
        let mut current = vec![0.0; states];
        let mut order: Vec<(f64, usize)> = Vec::new();
        for (t, target) in self.targets.iter().enumerate() {
            if !target.reachable() {
                continue;
            }
            previous.fill(0.0);
            for _ in 0..target.deadline {
                for phase in 0..self.period {
                    let next = (phase + 1) % self.period;
                    let hit = target.local[next];
                    for x in 0..n {
                        order.clear();
                        let mut sum = 0.0;
                        let mut mass = 1.0;
                        for b in self.row_start[x]..self.row_start[x + 1] {
                            let e = self.entry(b, phase);
                            let y = self.to[b];
                            let onward = if Some(y) == hit {
                                1.0
                            } else {
                                previous[next * n + y]
                            };
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
                        current[phase * n + x] = sum.min(1.0);
                    }
                }
                std::mem::swap(&mut previous, &mut current);
            }
            out[t * states..(t + 1) * states].copy_from_slice(&previous);
        }
    }

    /// The attacker's best expected gain, `max over (t, state)` of `value_t · (1 − P)`
    /// (probabilities above 1, possible at non-stochastic entries, count as 1).
    pub(crate) fn loss(&self, alpha: &[f64], scratch: &mut Vec<f64>) -> f64 {
        self.capture(alpha, scratch);
        self.loss_from(scratch)
    }

    /// As [`Chain::loss`], from capture probabilities already computed.
    pub(crate) fn loss_from(&self, capture: &[f64]) -> f64 {
        let states = self.states();
        let mut worst: f64 = 0.0;
        for (t, target) in self.targets.iter().enumerate() {
            for &p in &capture[t * states..(t + 1) * states] {
                worst = worst.max(target.value * (1.0 - p.min(1.0)));
            }
        }
        worst
    }

    /// Gradients of `P(t, state)` with respect to every entry, for every start state:
    /// `out[state * entries() + e]`. Zero when the target never enters the support.
    pub(crate) fn gradients(&self, alpha: &[f64], t: usize, out: &mut Vec<f64>) {
        let (n, states) = (self.len(), self.states());
        let m = self.entries();
        out.clear();
        out.resize(states * m, 0.0);
        let target = &self.targets[t];
        if !target.reachable() {
            return;
        }
        let deadline = target.deadline;
        let mut table = Vec::new();
        self.hitting_tables(alpha, t, &mut table);
        let mut reach = vec![0.0; n];
        let mut next = vec![0.0; n];
        for start in 0..states {
            let (start_phase, h) = (start / n, start % n);
            // reach = probability of standing at x after s − 1 steps without having hit t;
            // the phase advances in lockstep, so one phase at a time.
            reach.fill(0.0);
            reach[h] = 1.0;
            let grad = &mut out[start * m..(start + 1) * m];
            for s in 1..=deadline {
                let phase = (start_phase + s - 1) % self.period;
                let after = (phase + 1) % self.period;
                let hit = target.local[after];
                let left = &table[(deadline - s) * states + after * n..][..n];
                next.fill(0.0);
                for b in 0..self.to.len() {
                    let (x, y) = (self.from[b], self.to[b]);
                    if reach[x] == 0.0 {
                        continue;
                    }
                    let e = self.entry(b, phase);
                    let onward = if Some(y) == hit { 1.0 } else { left[y] };
                    grad[e] += reach[x] * onward;
                    if Some(y) != hit {
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
        let chain = Chain::new(
            &g,
            &[0, 1, 2, 3],
            &[(vec![0], 3, 1.0), (vec![2], 2, 2.0)],
            1,
            false,
        );
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
        let chain = Chain::new(
            &g,
            &[0, 1, 2],
            &[(vec![0], 2, 1.0), (vec![2], 2, 1.0)],
            1,
            false,
        );
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
        let chain = Chain::new(
            &g,
            &[0, 1, 2, 3],
            &[(vec![0], 3, 1.0), (vec![2], 2, 2.0)],
            1,
            false,
        );
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
