//! Phase-locked supports ("tubes"): the product states `(vertex, phase)` a patroller may
//! occupy while it keeps a set of moving targets within reach.
//!
//! A state `(v, φ)` keeps target `t` *within reach* if an attack on `t` started there could be
//! caught: `dist(v, pos_t(φ + s)) ≤ s` for some step `s ∈ 1..=deadline_t`. Its *distance* to a
//! set of targets `T` is `max over t ∈ T of dist(v, pos_t(φ))` for a patroller keeping *all*
//! of them within reach ([`Reach::All`]), the minimum for one keeping *any* of them
//! ([`Reach::Any`]: it follows one target or another and may switch where they meet).
//!
//! The tube with slack `δ` holds, at every phase, the states that keep the targets within
//! reach (all, or any) and whose distance is at most `δ` above the least such distance of that
//! phase: where the patroller is best placed, with some room (slack 0 and a single convoy: ride
//! on it). States that cannot move on inside it are then dropped ([`Chain::phase_locked`]: the
//! greatest set the patroller can stay in forever), and so are states from which, moving only
//! inside the set, some target of `T` (for [`Reach::All`]; every one for [`Reach::Any`])
//! cannot be reached in time — its capture probability is 0 under every policy on the set; the
//! two steps repeat until nothing changes. The result may be empty: no patrol keeps all of `T`
//! within reach with that slack.
//!
//! The states are the support of a phase-locked time-dependent chain and the only attack
//! starts, which is the point: a patroller riding with a convoy is never far from it. A wider
//! tube gives the policy more room but also more states to be attacked from.

use super::chain::{Chain, Track};
use super::local;
use crate::graph::{Graph, NodeId};

/// How states are ranked for a tube.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    /// By distance to the targets' current positions, relative to the best placed state of
    /// each phase.
    Near,
    /// By intercept time (the first step at which the targets could be caught), against one
    /// limit for every phase.
    Intercept,
}

/// Which of its targets a patroller keeps within reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Reach {
    /// Every one, at every state.
    All,
    /// At least one at every state.
    Any,
}

/// Distances from every vertex any target visits: `table[v]` is `Some(distances from v)`
/// (`usize::MAX` where unreachable).
pub(crate) fn target_distances(graph: &Graph, targets: &[Track]) -> Vec<Option<Vec<usize>>> {
    let mut table = vec![None; graph.node_count()];
    for (nodes, _, _) in targets {
        for &v in nodes {
            if table[v].is_none() {
                let d = graph.distances_from(v);
                table[v] = Some(d.into_iter().map(|d| d.unwrap_or(usize::MAX)).collect());
            }
        }
    }
    table
}

/// How a patroller guarding some targets is placed at every state `φ · n + v` (see the module
/// docs): its distance to them ([`Shape::Near`]) or its intercept time
/// ([`Shape::Intercept`]), `i64::MAX` where it does not keep them within reach.
pub(crate) fn placement(
    graph: &Graph,
    targets: &[Track],
    distance: &[Option<Vec<usize>>],
    assigned: &[usize],
    period: usize,
    reach: Reach,
    shape: Shape,
) -> Vec<i64> {
    let n = graph.node_count();
    let far = |t: usize, phase: usize, v: NodeId| -> usize {
        distance[targets[t].0[phase % period]]
            .as_ref()
            .map_or(usize::MAX, |d| d[v])
    };
    // The first step at which `t` could be caught from `(v, phase)`.
    let intercept =
        |t: usize, phase: usize, v: NodeId| (1..=targets[t].1).find(|&s| far(t, phase + s, v) <= s);
    let score = |t: usize, phase: usize, v: NodeId| match shape {
        Shape::Near => far(t, phase, v),
        Shape::Intercept => intercept(t, phase, v).unwrap_or(usize::MAX),
    };
    (0..period * n)
        .map(|state| {
            let (phase, v) = (state / n, state % n);
            let in_reach = |&t: &usize| intercept(t, phase, v).is_some();
            let (ok, d) = match reach {
                Reach::All => (
                    assigned.iter().all(in_reach),
                    assigned.iter().map(|&t| score(t, phase, v)).max(),
                ),
                Reach::Any => (
                    assigned.iter().any(in_reach),
                    assigned
                        .iter()
                        .filter(|t| in_reach(t))
                        .map(|&t| score(t, phase, v))
                        .min(),
                ),
            };
            match d {
                Some(d) if ok => i64::try_from(d).unwrap_or(i64::MAX),
                _ => i64::MAX,
            }
        })
        .collect()
}

/// The phase-locked chain of a patroller placed as given (by [`placement`] for `assigned`
/// and `reach`), with the states ranked at most `slack` above the best of their phase
/// ([`Shape::Near`]) or at most `slack` ([`Shape::Intercept`]); `None` if no state remains.
#[allow(clippy::too_many_arguments)]
pub(crate) fn tube(
    graph: &Graph,
    targets: &[Track],
    placement: &[i64],
    assigned: &[usize],
    period: usize,
    slack: i64,
    reach: Reach,
    shape: Shape,
) -> Option<Chain> {
    let n = graph.node_count();
    let mut admissible = vec![false; n * period];
    for phase in 0..period {
        let row = &placement[phase * n..(phase + 1) * n];
        let best = match shape {
            Shape::Near => row.iter().copied().min().unwrap_or(i64::MAX),
            Shape::Intercept => 0,
        };
        let limit = best.saturating_add(slack);
        for v in 0..n {
            admissible[phase * n + v] = row[v] != i64::MAX && row[v] <= limit;
        }
    }
    let support: Vec<NodeId> = (0..n)
        .filter(|&v| (0..period).any(|phase| admissible[phase * n + v]))
        .collect();
    if support.is_empty() {
        return None;
    }
    let mut active: Vec<bool> = (0..period)
        .flat_map(|phase| support.iter().map(move |&v| (phase, v)))
        .map(|(phase, v)| admissible[phase * n + v])
        .collect();
    let mut capture = Vec::new();
    loop {
        let chain = Chain::phase_locked(graph, &support, targets, period, active);
        // Every entry positive: a capture probability is 0 exactly where no walk inside the
        // set reaches the target in time.
        chain.capture(&local::uniform(&chain), &mut capture);
        let states = chain.states();
        let mut next: Vec<bool> = (0..states).map(|s| chain.is_active(s)).collect();
        let mut changed = false;
        for (s, keep) in next.iter_mut().enumerate() {
            let missed = |&t: &usize| capture[t * states + s] <= 0.0;
            let drop = match reach {
                Reach::All => assigned.iter().any(missed),
                Reach::Any => assigned.iter().all(missed),
            };
            if *keep && drop {
                *keep = false;
                changed = true;
            }
        }
        if !changed {
            return (chain.active_states() > 0).then_some(chain);
        }
        active = next;
    }
}

/// A starting policy on a tube: from every state, the patroller follows its nearest target
/// (ties share evenly), stepping to the successors nearest that target's next position; a
/// share `spread` of the mass is spread evenly over every move. Where two targets part, the
/// patroller picks one at random and keeps to it.
pub(crate) fn pursuit_start(
    chain: &Chain,
    targets: &[Track],
    distance: &[Option<Vec<usize>>],
    assigned: &[usize],
    spread: f64,
) -> Vec<f64> {
    let n = chain.len();
    let mut alpha = vec![0.0; chain.entries()];
    for r in 0..chain.rows() {
        let row = chain.row(r);
        let (phase, x) = (chain.row_state(r) / n, chain.row_state(r) % n);
        let next_phase = (phase + 1) % chain.period;
        for e in row.clone() {
            alpha[e] = spread / row.len() as f64;
        }
        // Follow the nearest targets (ties share).
        let gap = |t: usize| {
            distance[targets[t].0[phase]]
                .as_ref()
                .map_or(usize::MAX, |d| d[chain.nodes[x]])
        };
        let closest = assigned.iter().map(|&t| gap(t)).min().unwrap_or(usize::MAX);
        let followed: Vec<usize> = assigned
            .iter()
            .copied()
            .filter(|&t| gap(t) == closest)
            .collect();
        let share = (1.0 - spread) / followed.len().max(1) as f64;
        for &t in &followed {
            let Some(d) = distance[targets[t].0[next_phase]].as_ref() else {
                continue;
            };
            let far = |e: usize| d[chain.nodes[chain.entry_to(e)]];
            let best = row.clone().map(far).min().unwrap_or(usize::MAX);
            let nearest = row.clone().filter(|&e| far(e) == best).count() as f64;
            for e in row.clone().filter(|&e| far(e) == best) {
                alpha[e] += share / nearest;
            }
        }
        // Targets out of reach leave mass unplaced: renormalise.
        let sum: f64 = row.clone().map(|e| alpha[e]).sum();
        for e in row {
            alpha[e] /= sum;
        }
    }
    alpha
}

/// Carries a policy from `from` to a chain `to` whose states include `from`'s (a wider tube of
/// the same targets): rows of shared states keep their moves, the others take `fallback`'s;
/// then a share `spread` of every row is spread evenly (so that, as on every tube, each
/// target stays within reach).
pub(crate) fn lift(
    from: &Chain,
    alpha: &[f64],
    to: &Chain,
    fallback: &[f64],
    spread: f64,
) -> Vec<f64> {
    let mut lifted = fallback.to_vec();
    let (n_to, n_from) = (to.len(), from.len());
    for r in 0..to.rows() {
        let state = to.row_state(r);
        let (phase, v) = (state / n_to, to.nodes[state % n_to]);
        let Some(source) = from
            .nodes
            .binary_search(&v)
            .ok()
            .and_then(|x| from.state_row(phase * n_from + x))
        else {
            continue;
        };
        let moves: Vec<(NodeId, f64)> = from
            .row(source)
            .map(|e| (from.nodes[from.entry_to(e)], alpha[e]))
            .collect();
        for e in to.row(r) {
            let w = to.nodes[to.entry_to(e)];
            lifted[e] = moves.iter().find(|m| m.0 == w).map_or(0.0, |m| m.1);
        }
    }
    for r in 0..to.rows() {
        let even = spread / to.row(r).len() as f64;
        for e in to.row(r) {
            lifted[e] = (1.0 - spread) * lifted[e] + even;
        }
    }
    lifted
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;

    fn chain_for(
        g: &Graph,
        targets: &[Track],
        assigned: &[usize],
        period: usize,
        slack: i64,
        reach: Reach,
    ) -> Option<Chain> {
        let distance = target_distances(g, targets);
        let late = placement(g, targets, &distance, assigned, period, reach, Shape::Near);
        tube(
            g,
            targets,
            &late,
            assigned,
            period,
            slack,
            reach,
            Shape::Near,
        )
    }

    #[test]
    fn a_tight_tube_keeps_close_to_the_convoy() {
        // A convoy shuttling along a path of six: 0 1 2 3 4 5 4 3 2 1 (period 10), attacks
        // of three steps.
        let g = graph::path(6).unwrap();
        let schedule: Vec<NodeId> = vec![0, 1, 2, 3, 4, 5, 4, 3, 2, 1];
        let targets = vec![(schedule.clone(), 3, 1.0)];
        let tight = chain_for(&g, &targets, &[0], 10, 0, Reach::All).unwrap();
        // Slack 0: ride on the convoy.
        for (phase, &on) in schedule.iter().enumerate() {
            let states: Vec<NodeId> = (0..tight.len())
                .filter(|&x| tight.is_active(phase * tight.len() + x))
                .map(|x| tight.nodes[x])
                .collect();
            assert_eq!(states, vec![on]);
        }
        let tight = chain_for(&g, &targets, &[0], 10, 1, Reach::All).unwrap();
        // Slack 1: every state is within the attack's reach of the convoy, and catches it with
        // positive probability under a uniform policy.
        let mut capture = Vec::new();
        tight.capture(&local::uniform(&tight), &mut capture);
        for s in (0..tight.states()).filter(|&s| tight.is_active(s)) {
            let (phase, v) = (s / tight.len(), tight.nodes[s % tight.len()]);
            let near = (1..=3).any(|k| v.abs_diff(schedule[(phase + k) % 10]) <= k);
            assert!(near && capture[s] > 0.0, "phase {phase} vertex {v}");
        }
        // More slack, more states.
        let loose = chain_for(&g, &targets, &[0], 10, 3, Reach::All).unwrap();
        assert!(loose.active_states() > tight.active_states());
    }

    #[test]
    fn far_apart_targets_leave_no_tube_for_both() {
        // Two posts at the ends of a path of nine, attacks of two steps: no vertex is within
        // two steps of both.
        let g = graph::path(9).unwrap();
        let targets = vec![(vec![0], 2, 1.0), (vec![8], 2, 1.0)];
        assert!(chain_for(&g, &targets, &[0, 1], 1, 5, Reach::All).is_none());
        assert!(chain_for(&g, &targets, &[0], 1, 0, Reach::All).is_some());
        // Keeping either in reach: near one end or the other, never in the middle.
        let either = chain_for(&g, &targets, &[0, 1], 1, 2, Reach::Any).unwrap();
        assert_eq!(either.nodes, vec![0, 1, 2, 6, 7, 8]);
    }

    #[test]
    fn pursuit_starts_are_stochastic_and_head_for_the_targets() {
        // Posts at both ends of a path of five: from the middle, half the mass goes each way.
        let g = graph::path(5).unwrap();
        let targets = vec![(vec![0], 4, 1.0), (vec![4], 4, 1.0)];
        let distance = target_distances(&g, &targets);
        let late = placement(&g, &targets, &distance, &[0, 1], 1, Reach::All, Shape::Near);
        let chain = tube(&g, &targets, &late, &[0, 1], 1, 2, Reach::All, Shape::Near).unwrap();
        let alpha = pursuit_start(&chain, &targets, &distance, &[0, 1], 0.0);
        for r in 0..chain.rows() {
            let sum: f64 = chain.row(r).map(|e| alpha[e]).sum();
            assert!((sum - 1.0).abs() < 1e-12);
        }
        let middle = chain.nodes.binary_search(&2).unwrap();
        let moves: Vec<(NodeId, f64)> = chain
            .row(chain.state_row(middle).unwrap())
            .map(|e| (chain.nodes[chain.entry_to(e)], alpha[e]))
            .collect();
        assert_eq!(moves, vec![(1, 0.5), (2, 0.0), (3, 0.5)]);
    }

    #[test]
    fn lifted_policies_keep_their_moves_and_their_values() {
        let g = graph::path(6).unwrap();
        let schedule: Vec<NodeId> = vec![0, 1, 2, 3, 4, 5, 4, 3, 2, 1];
        let targets = vec![(schedule, 3, 1.0)];
        let distance = target_distances(&g, &targets);
        let late = placement(&g, &targets, &distance, &[0], 10, Reach::All, Shape::Near);
        let tight = tube(&g, &targets, &late, &[0], 10, 1, Reach::All, Shape::Near).unwrap();
        let wide = tube(&g, &targets, &late, &[0], 10, 2, Reach::All, Shape::Near).unwrap();
        let alpha = pursuit_start(&tight, &targets, &distance, &[0], 0.1);
        let fallback = local::uniform(&wide);
        let lifted = lift(&tight, &alpha, &wide, &fallback, 0.0);
        for r in 0..wide.rows() {
            let sum: f64 = wide.row(r).map(|e| lifted[e]).sum();
            assert!((sum - 1.0).abs() < 1e-12);
        }
        // Capture from the tight tube's states is unchanged: its moves never leave it.
        let (mut before, mut after) = (Vec::new(), Vec::new());
        tight.capture(&alpha, &mut before);
        wide.capture(&lifted, &mut after);
        for s in (0..tight.states()).filter(|&s| tight.is_active(s)) {
            let (phase, v) = (s / tight.len(), tight.nodes[s % tight.len()]);
            let x = wide.nodes.binary_search(&v).unwrap();
            assert!((before[s] - after[phase * wide.len() + x]).abs() < 1e-12);
        }
    }
}
