//! Stationary Markov patrolling policies and their exact evaluation.

use serde::Serialize;

use super::chain::Chain;
use super::{Instance, PatrolError};
use crate::graph::{Graph, NodeId};
use crate::scc::strong_components;

/// A policy's rows: `(vertex, [(next vertex, probability)])`.
pub type Rows = Vec<(NodeId, Vec<(NodeId, f64)>)>;

/// Tolerance on a row of probabilities summing to 1.
const ROW_SUM_TOLERANCE: f64 = 1e-9;

/// A Markov policy for one patroller: on its *support* (the vertices it patrols), each vertex
/// has a distribution over where to be next (itself or a neighbour, inside the support). A
/// *stationary* policy has one distribution per vertex; a *time-dependent* one has one per
/// vertex and phase of the targets' schedule period (`phases` of them, the period).
///
/// The *states* of a policy are the (vertex, phase) pairs it has a distribution for: every
/// (support vertex, phase) for a stationary policy, and for a time-dependent one either the
/// same (a *full-phase* policy) or only some vertices at each phase (a *phase-locked* policy,
/// e.g. one that keeps near a convoy: it is never elsewhere at that phase). The attacker may
/// strike whenever the patroller is in one of its states, so every state counts as an
/// observable start of an attack.
///
/// ```
/// use vitro_algo::graph;
/// use vitro_algo::patrol::Policy;
///
/// let g = graph::path(3)?;
/// let walk = Policy::new(&g, vec![
///     (0, vec![(1, 1.0)]),
///     (1, vec![(0, 0.5), (2, 0.5)]),
///     (2, vec![(1, 1.0)]),
/// ])?;
/// assert_eq!(walk.support(), &[0, 1, 2]);
/// assert_eq!(walk.probability(1, 2), 0.5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Policy {
    support: Vec<NodeId>,
    /// Phases with their own rows (1 for a stationary policy).
    phases: usize,
    /// Per phase, then per support vertex (row `phase · support.len() + i`): `(next vertex,
    /// probability)`, ascending by vertex, positive probabilities only; empty where the
    /// patroller never is at that phase (a phase-locked policy).
    moves: Vec<Vec<(NodeId, f64)>>,
}

/// One attack option and how the policy fares against it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Attack {
    /// Index of the target in [`Instance::targets`].
    pub target: usize,
    /// The phase of the schedule period when the attack starts (0 for static targets).
    pub phase: usize,
    /// The patroller's vertex when the attack starts.
    pub from: NodeId,
    /// Probability that the patroller stands on the target during the attack.
    pub capture_probability: f64,
    /// The attacker's expected gain: the target's value times the escape probability.
    pub expected_loss: f64,
}

impl Policy {
    /// Builds a policy from `(vertex, moves)` rows; every move goes to the vertex itself or a
    /// neighbour, probabilities are non-negative and sum to 1 (rows are renormalised to remove
    /// rounding), and every move stays inside the support (the listed vertices).
    ///
    /// # Errors
    /// [`PatrolError::InvalidPolicy`] naming the offending row.
    pub fn new(
        graph: &Graph,
        rows: Vec<(NodeId, Vec<(NodeId, f64)>)>,
    ) -> Result<Policy, PatrolError> {
        let mut rows = rows;
        rows.sort_by_key(|(v, _)| *v);
        let support: Vec<NodeId> = rows.iter().map(|(v, _)| *v).collect();
        let bad = |message: String| Err(PatrolError::InvalidPolicy(message));
        if support.is_empty() {
            return bad("the support is empty".into());
        }
        if let Some(w) = support.windows(2).find(|w| w[0] == w[1]) {
            return bad(format!("vertex {} has two rows", w[0]));
        }
        let mut moves = Vec::with_capacity(rows.len());
        for (v, row) in rows {
            moves.push(checked_row(graph, v, row, &support)?);
        }
        Ok(Policy {
            support,
            phases: 1,
            moves,
        })
    }

    /// Builds a time-dependent policy from one set of rows per phase (each row as for
    /// [`Policy::new`]). Phases may list different vertices (a phase-locked policy): a move at
    /// phase `φ` must then lead to a vertex listed at phase `φ + 1` (cyclically).
    ///
    /// # Errors
    /// [`PatrolError::InvalidPolicy`] naming the offending phase or row.
    pub fn time_dependent(graph: &Graph, phases: Vec<Rows>) -> Result<Policy, PatrolError> {
        let count = phases.len();
        if count == 0 {
            return Err(PatrolError::InvalidPolicy("no phases".into()));
        }
        let listed: Vec<Vec<NodeId>> = phases
            .iter()
            .map(|rows| {
                let mut v: Vec<NodeId> = rows.iter().map(|(v, _)| *v).collect();
                v.sort_unstable();
                v
            })
            .collect();
        let mut support: Vec<NodeId> = listed.iter().flatten().copied().collect();
        support.sort_unstable();
        support.dedup();
        if support.is_empty() {
            return Err(PatrolError::InvalidPolicy("the support is empty".into()));
        }
        let n = support.len();
        let mut moves = vec![Vec::new(); count * n];
        for (phase, rows) in phases.into_iter().enumerate() {
            let at = |e: PatrolError| PatrolError::InvalidPolicy(format!("phase {phase}: {e}"));
            if listed[phase].is_empty() {
                return Err(at(PatrolError::InvalidPolicy("no vertices".into())));
            }
            if let Some(w) = listed[phase].windows(2).find(|w| w[0] == w[1]) {
                return Err(at(PatrolError::InvalidPolicy(format!(
                    "vertex {} has two rows",
                    w[0]
                ))));
            }
            let next = &listed[(phase + 1) % count];
            for (v, row) in rows {
                let row = checked_row(graph, v, row, next).map_err(at)?;
                let i = support.binary_search(&v).unwrap_or(0);
                moves[phase * n + i] = row;
            }
        }
        Ok(Policy {
            support,
            phases: count,
            moves,
        })
    }

    /// The policy that stands still on `v` forever.
    pub fn stay(v: NodeId) -> Policy {
        Policy {
            support: vec![v],
            phases: 1,
            moves: vec![vec![(v, 1.0)]],
        }
    }

    /// Builds the policy from a chain's entry vector (rows already stochastic up to rounding).
    pub(crate) fn from_chain(chain: &Chain, alpha: &[f64]) -> Policy {
        let n = chain.len();
        let phases = chain.row_phases();
        let mut moves = vec![Vec::new(); phases * n];
        for i in 0..chain.rows() {
            let row = chain.row(i);
            let sum: f64 = row.clone().map(|e| alpha[e].max(0.0)).sum();
            moves[chain.row_state(i)] = row
                .filter(|&e| alpha[e] > 0.0)
                .map(|e| (chain.nodes[chain.entry_to(e)], alpha[e] / sum))
                .collect();
        }
        Policy {
            support: chain.nodes.clone(),
            phases,
            moves,
        }
    }

    /// The entry vector of this policy on `chain` (whose support must be this policy's; a
    /// stationary policy fills every phase of a timed chain).
    pub(crate) fn to_chain_entries(&self, chain: &Chain) -> Vec<f64> {
        let mut alpha = vec![0.0; chain.entries()];
        let n = self.support.len();
        for i in 0..chain.rows() {
            let state = chain.row_state(i);
            let source = ((state / n) % self.phases) * n + state % n;
            for &(w, p) in &self.moves[source] {
                if let Some(e) = chain.row(i).find(|&e| chain.nodes[chain.entry_to(e)] == w) {
                    alpha[e] = p;
                }
            }
        }
        alpha
    }

    /// Phases with their own rows: 1 for a stationary policy, the period for a time-dependent
    /// one.
    pub fn phases(&self) -> usize {
        self.phases
    }

    /// The vertices the patroller visits, ascending.
    pub fn support(&self) -> &[NodeId] {
        &self.support
    }

    /// The moves from `v` (at phase 0) as `(next vertex, probability)`, or `None` outside the
    /// support.
    pub fn moves(&self, v: NodeId) -> Option<&[(NodeId, f64)]> {
        self.moves_at(v, 0)
    }

    /// The moves from `v` at `phase` (taken modulo [`Policy::phases`]), or `None` if `v` is not
    /// one of the policy's states at that phase.
    pub fn moves_at(&self, v: NodeId, phase: usize) -> Option<&[(NodeId, f64)]> {
        let i = self.support.binary_search(&v).ok()?;
        let row = (phase % self.phases) * self.support.len() + i;
        self.moves
            .get(row)
            .filter(|m| !m.is_empty())
            .map(Vec::as_slice)
    }

    /// The vertices where the patroller may be at `phase` (taken modulo [`Policy::phases`]),
    /// ascending: the whole support unless the policy is phase-locked.
    pub fn states_at(&self, phase: usize) -> Vec<NodeId> {
        let n = self.support.len();
        let start = (phase % self.phases) * n;
        self.support
            .iter()
            .zip(&self.moves[start..start + n])
            .filter(|(_, m)| !m.is_empty())
            .map(|(&v, _)| v)
            .collect()
    }

    /// Whether some vertex has no moves at some phase (the patroller is never there then).
    pub fn is_phase_locked(&self) -> bool {
        self.moves.iter().any(Vec::is_empty)
    }

    /// The probability of moving from `from` to `to` at phase 0 (0 outside the support).
    pub fn probability(&self, from: NodeId, to: NodeId) -> f64 {
        self.moves(from)
            .and_then(|row| row.iter().find(|(w, _)| *w == to))
            .map_or(0.0, |&(_, p)| p)
    }

    /// The next vertex from `from` at phase 0 for a uniform draw `u` in `[0, 1)` (inverse
    /// transform sampling); `None` outside the support.
    pub fn next(&self, from: NodeId, u: f64) -> Option<NodeId> {
        self.next_at(from, 0, u)
    }

    /// The next vertex from `from` at `phase` for a uniform draw `u` in `[0, 1)`; `None`
    /// outside the support.
    pub fn next_at(&self, from: NodeId, phase: usize, u: f64) -> Option<NodeId> {
        let row = self.moves_at(from, phase)?;
        let mut acc = 0.0;
        for &(w, p) in row {
            acc += p;
            if u < acc {
                return Some(w);
            }
        }
        row.last().map(|&(w, _)| w)
    }

    /// The chain of this policy's support for `instance`'s targets.
    pub(crate) fn chain(&self, instance: &Instance) -> Result<Chain, PatrolError> {
        let (period, targets) = instance.timeline()?;
        if self.phases != 1 && self.phases != period {
            return Err(PatrolError::InvalidPolicy(format!(
                "the policy has {} phases, the instance's schedules a period of {period}",
                self.phases
            )));
        }
        if self.is_phase_locked() {
            // Phase-locked policies have a row per (vertex, phase) of the period.
            if self.phases != period {
                return Err(PatrolError::InvalidPolicy(format!(
                    "the phase-locked policy has {} phases, the instance's schedules a period of {period}",
                    self.phases
                )));
            }
            let active = self.moves.iter().map(|m| !m.is_empty()).collect();
            return Ok(Chain::phase_locked(
                &instance.graph,
                &self.support,
                &targets,
                period,
                active,
            ));
        }
        Ok(Chain::new(
            &instance.graph,
            &self.support,
            &targets,
            period,
            self.phases > 1,
        ))
    }

    /// The exact outcome of every attack option: each target, started while the patroller is
    /// in each of its states (each support vertex at each phase of the schedule period, or
    /// only its phase's vertices for a phase-locked policy), by target, then phase, then
    /// vertex.
    ///
    /// # Errors
    /// [`PatrolError::InvalidPolicy`] if the policy does not fit the instance's graph or
    /// period, [`PatrolError::Unsupported`] for a period above
    /// [`MAX_PERIOD`](super::MAX_PERIOD).
    pub fn attacks(&self, instance: &Instance) -> Result<Vec<Attack>, PatrolError> {
        self.check_graph(&instance.graph)?;
        let chain = self.chain(instance)?;
        let alpha = self.to_chain_entries(&chain);
        let mut capture = Vec::new();
        chain.capture(&alpha, &mut capture);
        let (n, states) = (chain.len(), chain.states());
        let mut attacks = Vec::with_capacity(capture.len());
        for (t, target) in chain.targets.iter().enumerate() {
            for (s, &p) in capture[t * states..(t + 1) * states].iter().enumerate() {
                if !chain.is_active(s) {
                    continue;
                }
                let p = p.min(1.0);
                attacks.push(Attack {
                    target: t,
                    phase: s / n,
                    from: chain.nodes[s % n],
                    capture_probability: p,
                    expected_loss: target.value * (1.0 - p),
                });
            }
        }
        Ok(attacks)
    }

    /// The attacker's best expected gain against this policy (the policy's value; lower is
    /// better for the patroller).
    ///
    /// # Errors
    /// As for [`Policy::attacks`].
    pub fn value(&self, instance: &Instance) -> Result<f64, PatrolError> {
        Ok(self
            .attacks(instance)?
            .iter()
            .map(|a| a.expected_loss)
            .fold(0.0, f64::max))
    }

    fn check_graph(&self, graph: &Graph) -> Result<(), PatrolError> {
        for (&v, row) in self.support.iter().cycle().zip(&self.moves) {
            for &(w, _) in row {
                if v >= graph.node_count() || (w != v && !graph.has_edge(v, w)) {
                    return Err(PatrolError::InvalidPolicy(format!(
                        "move {v} -> {w} does not follow an edge of the instance's graph"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The closed communicating classes of the policy, all phases' moves together (the sets the patroller can end up
    /// circling in forever), each ascending, ordered by smallest vertex.
    pub fn recurrent_classes(&self) -> Vec<Vec<NodeId>> {
        let n = self.support.len();
        let index = |w: NodeId| self.support.binary_search(&w).ok();
        let reach: Vec<Vec<bool>> = (0..n)
            .map(|start| {
                let mut seen = vec![false; n];
                seen[start] = true;
                let mut stack = vec![start];
                while let Some(i) = stack.pop() {
                    let rows = (0..self.phases).map(|p| &self.moves[p * n + i]);
                    for &(w, _) in rows.flatten() {
                        if let Some(j) = index(w).filter(|&j| !seen[j]) {
                            seen[j] = true;
                            stack.push(j);
                        }
                    }
                }
                seen
            })
            .collect();
        let mut classes = Vec::new();
        let mut taken = vec![false; n];
        for i in 0..n {
            if taken[i] {
                continue;
            }
            // i is recurrent iff everything it reaches reaches it back.
            let recurrent = (0..n).all(|j| !reach[i][j] || reach[j][i]);
            if recurrent {
                let class: Vec<usize> = (0..n).filter(|&j| reach[i][j]).collect();
                for &j in &class {
                    taken[j] = true;
                }
                classes.push(class.into_iter().map(|j| self.support[j]).collect());
            }
        }
        classes
    }

    /// This policy restricted to a closed set of its support vertices.
    pub(crate) fn restricted(&self, class: &[NodeId]) -> Policy {
        let moves = (0..self.phases)
            .flat_map(|phase| {
                class.iter().map(move |&v| {
                    self.moves_at(v, phase)
                        .map(<[_]>::to_vec)
                        .unwrap_or_default()
                })
            })
            .collect();
        Policy {
            support: class.to_vec(),
            phases: self.phases,
            moves,
        }
    }

    /// The closed communicating classes of the policy's states `(phase, vertex)`, phase by
    /// phase in turn (the sets of states the patroller can end up cycling through forever;
    /// with one phase, the vertex sets of [`Policy::recurrent_classes`]). Each class is
    /// ascending by phase, then vertex; classes are ordered by their first state.
    pub fn recurrent_states(&self) -> Vec<Vec<(usize, NodeId)>> {
        let n = self.support.len();
        let count = self.moves.len();
        let index = |w: NodeId| self.support.binary_search(&w).ok();
        let successors = |s: usize| -> Vec<usize> {
            let next = (s / n + 1) % self.phases * n;
            self.moves[s]
                .iter()
                .filter_map(|&(w, _)| index(w).map(|j| next + j))
                .collect()
        };
        let component = strong_components(
            count,
            (0..count).flat_map(|s| successors(s).into_iter().map(move |t| (s, t))),
        );
        // A component is closed when no move leaves it; empty rows are no states.
        let components = component.iter().copied().max().map_or(0, |c| c + 1);
        let mut closed = vec![true; components];
        for s in (0..count).filter(|&s| !self.moves[s].is_empty()) {
            if successors(s).iter().any(|&t| component[t] != component[s]) {
                closed[component[s]] = false;
            }
        }
        let mut classes: Vec<Vec<(usize, NodeId)>> = Vec::new();
        let mut slot = vec![usize::MAX; components];
        for s in (0..count).filter(|&s| !self.moves[s].is_empty()) {
            let c = component[s];
            if !closed[c] {
                continue;
            }
            if slot[c] == usize::MAX {
                slot[c] = classes.len();
                classes.push(Vec::new());
            }
            classes[slot[c]].push((s / n, self.support[s % n]));
        }
        classes
    }

    /// This policy with every move of probability below `epsilon` dropped (rows renormalised;
    /// a row keeps at least its likeliest move): LP solutions leave moves of 10⁻¹⁶ that no
    /// patroller ever takes but that would keep unvisited states in a recurrent class.
    pub(crate) fn without_tiny_moves(&self, epsilon: f64) -> Policy {
        let moves = self
            .moves
            .iter()
            .map(|row| {
                let top = row.iter().map(|m| m.1).fold(0.0, f64::max);
                let kept: Vec<(NodeId, f64)> = row
                    .iter()
                    .copied()
                    .filter(|&(_, p)| p >= epsilon || p == top)
                    .collect();
                let sum: f64 = kept.iter().map(|m| m.1).sum();
                kept.into_iter().map(|(w, p)| (w, p / sum)).collect()
            })
            .collect();
        Policy {
            support: self.support.clone(),
            phases: self.phases,
            moves,
        }
    }

    /// This policy restricted to a closed set of its states `(phase, vertex)` (as given by
    /// [`Policy::recurrent_states`]): a phase-locked policy on those states only.
    pub(crate) fn restricted_to_states(&self, states: &[(usize, NodeId)]) -> Policy {
        let mut support: Vec<NodeId> = states.iter().map(|&(_, v)| v).collect();
        support.sort_unstable();
        support.dedup();
        let n = support.len();
        let mut moves = vec![Vec::new(); self.phases * n];
        for &(phase, v) in states {
            if let (Ok(i), Some(row)) = (support.binary_search(&v), self.moves_at(v, phase)) {
                moves[phase * n + i] = row.to_vec();
            }
        }
        Policy {
            support,
            phases: self.phases,
            moves,
        }
    }
}

/// Validates one row of moves from `v` (every move to `v` itself or a neighbour, in `allowed`
/// when positive, listed once, probabilities summing to 1) and returns it renormalised,
/// ascending, positive entries only.
fn checked_row(
    graph: &Graph,
    v: NodeId,
    mut row: Vec<(NodeId, f64)>,
    allowed: &[NodeId],
) -> Result<Vec<(NodeId, f64)>, PatrolError> {
    let bad = |message: String| Err(PatrolError::InvalidPolicy(message));
    if v >= graph.node_count() {
        return bad(format!("vertex {v} is not in the graph"));
    }
    row.sort_by_key(|(w, _)| *w);
    let mut sum = 0.0;
    for (i, &(w, p)) in row.iter().enumerate() {
        if !(p.is_finite() && p >= 0.0) {
            return bad(format!("move {v} -> {w} has probability {p}"));
        }
        if w != v && !graph.has_edge(v, w) {
            return bad(format!("move {v} -> {w} does not follow an edge"));
        }
        if allowed.binary_search(&w).is_err() && p > 0.0 {
            return bad(format!("move {v} -> {w} leaves the support"));
        }
        if i > 0 && row[i - 1].0 == w {
            return bad(format!("move {v} -> {w} is listed twice"));
        }
        sum += p;
    }
    if (sum - 1.0).abs() > ROW_SUM_TOLERANCE {
        return bad(format!("the moves from {v} sum to {sum}, not 1"));
    }
    Ok(row
        .into_iter()
        .filter(|&(_, p)| p > 0.0)
        .map(|(w, p)| (w, p / sum))
        .collect())
}
