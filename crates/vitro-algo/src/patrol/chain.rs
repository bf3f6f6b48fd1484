//! The patroller's Markov chain on a support set, with its transition entries laid out flat,
//! and the capture probabilities (and their gradients) as functions of those entries.
//!
//! Targets may move on periodic schedules, so the chain runs on the product state
//! `(vertex, phase)`, `phase = time mod period`. A *stationary* chain has one row of entries per
//! support vertex, shared by every phase; a *timed* (time-dependent) chain has one row per
//! (vertex, phase). A timed chain may also be *phase-locked*: only some product states are
//! *active* (the patroller is at some vertices only at some phases, e.g. near a convoy), rows
//! exist for active states only and their moves lead to active states of the next phase.
//!
//! For a target `t` with deadline `D` and vertex `pos_t(φ)` at phase `φ`, the capture
//! probability from state `(h, φ)` is the chance that the walk started there stands on the
//! target's vertex at one of the steps `1..=D`:
//! `q_0 = 0`, `q_s(x, φ) = Σ_y α_φ(x, y) · ([y = pos_t(φ+1)] + [y ≠ pos_t(φ+1)] · q_{s-1}(y, φ+1))`,
//! `P(t, h, φ) = q_D(h, φ)`. Unrolled, `P` is a sum over walks of products of entries: a
//! polynomial with non-negative coefficients, hence non-decreasing in every entry — the fact
//! the exact branch and bound relies on (sharing entries across phases keeps it true). The same
//! code evaluates it at non-stochastic entry vectors. With static targets the period is 1 and
//! both kinds of chain are the plain chain on the support.

use crate::graph::{Graph, NodeId};

/// A target as the chain sees it: its vertex at each phase, its deadline and its value.
pub(crate) type Track = (Vec<NodeId>, usize, f64);

/// No row (an inactive state).
const NONE: usize = usize::MAX;

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

/// Sparse gradients of one target's capture probabilities: for every start state, the entries
/// with a non-zero partial derivative (ascending) and the derivatives.
#[derive(Clone, Debug, Default)]
pub(crate) struct Gradients {
    /// State `s` owns `offsets[s]..offsets[s + 1]` of `entries` and `values`.
    offsets: Vec<usize>,
    entries: Vec<usize>,
    values: Vec<f64>,
}

impl Gradients {
    /// The non-zero partial derivatives of `P(t, state)`: `(entries, values)`, entries
    /// ascending (empty for an inactive state or an unreachable target).
    pub(crate) fn at(&self, state: usize) -> (&[usize], &[f64]) {
        match (self.offsets.get(state), self.offsets.get(state + 1)) {
            (Some(&a), Some(&b)) => (&self.entries[a..b], &self.values[a..b]),
            _ => (&[], &[]),
        }
    }
}

/// A Markov chain restricted to a support set of vertices, over `period` phases.
#[derive(Clone, Debug)]
pub(crate) struct Chain {
    /// The support, ascending; local index `i` is vertex `nodes[i]`.
    pub(crate) nodes: Vec<NodeId>,
    /// Entries of row `r` are `row_start[r]..row_start[r + 1]`.
    row_start: Vec<usize>,
    /// The row used at each product state `φ · len() + x` ([`NONE`] for an inactive state).
    state_row: Vec<usize>,
    /// The product state of each row of a timed chain (row `x` of a stationary chain serves
    /// vertex `x` at every phase).
    row_state: Vec<usize>,
    /// Local successor of each entry (rows list their successors ascending, the vertex itself
    /// included when allowed).
    pub(crate) to: Vec<usize>,
    /// Phases of the targets' schedules (1 when every target is static).
    pub(crate) period: usize,
    /// Whether each phase has its own rows (a time-dependent policy).
    pub(crate) timed: bool,
    /// Whether each product state is one the patroller may occupy (and be attacked from).
    active: Vec<bool>,
    pub(crate) targets: Vec<ChainTarget>,
}

impl Chain {
    /// The chain on `support` (sorted, distinct vertices of `graph`), attacked at `targets`
    /// given as `(vertex per phase, deadline, value)` (each vertex list `period` long); every
    /// (support vertex, phase) is active.
    pub(crate) fn new(
        graph: &Graph,
        support: &[NodeId],
        targets: &[Track],
        period: usize,
        timed: bool,
    ) -> Chain {
        let period = period.max(1);
        let active = vec![true; support.len() * period];
        Chain::build(graph, support, targets, period, timed, active)
    }

    /// A phase-locked timed chain: only the product states `φ · support.len() + x` marked in
    /// `active` are occupied. Moves from an active state go to active states of the next phase
    /// only; an active state without such a move is deactivated (repeatedly, so every active
    /// state can move on forever).
    pub(crate) fn phase_locked(
        graph: &Graph,
        support: &[NodeId],
        targets: &[Track],
        period: usize,
        mut active: Vec<bool>,
    ) -> Chain {
        let period = period.max(1);
        let n = support.len();
        active.resize(n * period, false);
        let local = |v: NodeId| support.binary_search(&v).ok();
        loop {
            let mut changed = false;
            for state in 0..n * period {
                let (phase, x) = (state / n, state % n);
                let next = (phase + 1) % period * n;
                let moves_on = active[state]
                    && std::iter::once(x)
                        .chain(graph.neighbors(support[x]).iter().filter_map(|&w| local(w)))
                        .any(|y| active[next + y]);
                if active[state] && !moves_on {
                    active[state] = false;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        Chain::build(graph, support, targets, period, true, active)
    }

    fn build(
        graph: &Graph,
        support: &[NodeId],
        targets: &[Track],
        period: usize,
        timed: bool,
        active: Vec<bool>,
    ) -> Chain {
        let n = support.len();
        let local = |v: NodeId| support.binary_search(&v).ok();
        // The closed neighbourhood of each support vertex within the support, ascending.
        let around: Vec<Vec<usize>> = (0..n)
            .map(|i| {
                let mut row: Vec<usize> = graph
                    .neighbors(support[i])
                    .iter()
                    .filter_map(|&w| local(w))
                    .collect();
                row.push(i);
                row.sort_unstable();
                row
            })
            .collect();
        let mut row_start = vec![0];
        let mut to = Vec::new();
        let mut state_row = vec![NONE; n * period];
        let mut row_state = Vec::new();
        if timed {
            for state in 0..n * period {
                if !active[state] {
                    continue;
                }
                let (phase, x) = (state / n, state % n);
                let next = (phase + 1) % period * n;
                state_row[state] = row_state.len();
                row_state.push(state);
                to.extend(around[x].iter().filter(|&&y| active[next + y]));
                row_start.push(to.len());
            }
        } else {
            for row in &around {
                to.extend(row);
                row_start.push(to.len());
            }
            for (state, r) in state_row.iter_mut().enumerate() {
                if active[state] {
                    *r = state % n;
                }
            }
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
            state_row,
            row_state,
            to,
            period,
            timed,
            active,
            targets,
        }
    }

    /// Number of support vertices.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Number of product states `(vertex, phase)`, active or not; state `φ · len() + x`.
    pub(crate) fn states(&self) -> usize {
        self.nodes.len() * self.period
    }

    /// Whether product state `state` is occupied (an attack may start there).
    pub(crate) fn is_active(&self, state: usize) -> bool {
        self.active.get(state).copied().unwrap_or(false)
    }

    /// Number of active product states.
    pub(crate) fn active_states(&self) -> usize {
        self.active.iter().filter(|&&a| a).count()
    }

    /// Phases with their own rows: `period` for a timed chain, else 1.
    pub(crate) fn row_phases(&self) -> usize {
        if self.timed { self.period } else { 1 }
    }

    /// Number of transition entries (the free variables).
    pub(crate) fn entries(&self) -> usize {
        self.to.len()
    }

    /// Number of stochastic rows: one per active state of a timed chain, one per vertex of a
    /// stationary one.
    pub(crate) fn rows(&self) -> usize {
        self.row_start.len() - 1
    }

    /// The entry range of row `i` (see [`Chain::rows`]).
    pub(crate) fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.row_start[i]..self.row_start[i + 1]
    }

    /// The (first) product state row `i` serves: `φ · len() + x` for a timed chain, vertex `x`
    /// (at phase 0) for a stationary one.
    pub(crate) fn row_state(&self, i: usize) -> usize {
        if self.timed { self.row_state[i] } else { i }
    }

    /// The row used at product state `state`, `None` if it is inactive.
    pub(crate) fn state_row(&self, state: usize) -> Option<usize> {
        self.state_row.get(state).copied().filter(|&r| r != NONE)
    }

    /// Local successor of entry `e`.
    pub(crate) fn entry_to(&self, e: usize) -> usize {
        self.to[e]
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
                    let Some(r) = self.state_row(phase * n + x) else {
                        continue;
                    };
                    let mut sum = 0.0;
                    for e in self.row(r) {
                        let y = self.to[e];
                        let onward = if Some(y) == hit {
                            1.0
                        } else {
                            previous[next * n + y]
                        };
                        sum += alpha[e] * onward;
                    }
                    current[phase * n + x] = sum;
                }
            }
        }
    }

    /// Capture probabilities `out[t * states() + state]` for every target and start state
    /// (0 at inactive states).
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
                        let Some(r) = self.state_row(phase * n + x) else {
                            continue;
                        };
                        order.clear();
                        let mut sum = 0.0;
                        let mut mass = 1.0;
                        for e in self.row(r) {
                            let y = self.to[e];
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

    /// The attacker's best expected gain, `max over (t, active state)` of `value_t · (1 − P)`
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
            for (state, &p) in capture[t * states..(t + 1) * states].iter().enumerate() {
                if self.active[state] {
                    worst = worst.max(target.value * (1.0 - p.min(1.0)));
                }
            }
        }
        worst
    }

    /// Gradients of `P(t, state)` with respect to every entry, for every active start state
    /// (none when the target never enters the support).
    pub(crate) fn gradients(&self, alpha: &[f64], t: usize, out: &mut Gradients) {
        let (n, states) = (self.len(), self.states());
        out.offsets.clear();
        out.entries.clear();
        out.values.clear();
        out.offsets.push(0);
        let target = &self.targets[t];
        if !target.reachable() {
            out.offsets.resize(states + 1, 0);
            return;
        }
        let deadline = target.deadline;
        let mut table = Vec::new();
        self.hitting_tables(alpha, t, &mut table);
        let mut reach = vec![0.0; n];
        let mut next = vec![0.0; n];
        let mut grad = vec![0.0; self.entries()];
        let mut touched = vec![false; self.entries()];
        let mut list: Vec<usize> = Vec::new();
        for start in 0..states {
            if self.active[start] {
                let (start_phase, h) = (start / n, start % n);
                // reach = probability of standing at x after s − 1 steps without having hit
                // t; the phase advances in lockstep, so one phase at a time.
                reach.fill(0.0);
                reach[h] = 1.0;
                for s in 1..=deadline {
                    let phase = (start_phase + s - 1) % self.period;
                    let after = (phase + 1) % self.period;
                    let hit = target.local[after];
                    let left = &table[(deadline - s) * states + after * n..][..n];
                    next.fill(0.0);
                    for (x, &here) in reach.iter().enumerate() {
                        let Some(r) = self.state_row(phase * n + x).filter(|_| here != 0.0) else {
                            continue;
                        };
                        for e in self.row(r) {
                            let y = self.to[e];
                            let onward = if Some(y) == hit { 1.0 } else { left[y] };
                            if !touched[e] {
                                touched[e] = true;
                                list.push(e);
                            }
                            grad[e] += here * onward;
                            if Some(y) != hit {
                                next[y] += here * alpha[e];
                            }
                        }
                    }
                    std::mem::swap(&mut reach, &mut next);
                }
                list.sort_unstable();
                for &e in &list {
                    if grad[e] != 0.0 {
                        out.entries.push(e);
                        out.values.push(grad[e]);
                    }
                    grad[e] = 0.0;
                    touched[e] = false;
                }
                list.clear();
            }
            out.offsets.push(out.entries.len());
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
            let mut grad = Gradients::default();
            chain.gradients(&alpha, t, &mut grad);
            for e in 0..chain.entries() {
                let mut bumped = alpha.clone();
                bumped[e] += 1e-6;
                let mut after = Vec::new();
                chain.capture(&bumped, &mut after);
                for h in 0..4 {
                    let numeric = (after[t * 4 + h] - base[t * 4 + h]) / 1e-6;
                    let (entries, values) = grad.at(h);
                    let exact = entries
                        .iter()
                        .position(|&x| x == e)
                        .map_or(0.0, |i| values[i]);
                    assert!(
                        (numeric - exact).abs() < 1e-4,
                        "t{t} h{h} e{e}: {numeric} vs {exact}"
                    );
                }
            }
        }
    }
}
