//! Several patrollers: evaluation of independent policies against a watching attacker, and
//! the scalable local method (successive LP with restarts over support assignments).
//!
//! Each patroller follows its own Markov policy, independently of the others. The attacker
//! sees every patroller's vertex and the phase; the escape probability from a joint start is
//! the product of the patrollers' escape probabilities, so his best joint start takes each
//! patroller's worst start (the factors are non-negative and independent of each other).
//!
//! The search: for every way of assigning the targets to the patrollers (while there are at
//! most [`MAX_ASSIGNMENTS`] of them; else only the one where everybody guards everything),
//! each patroller's support is the connected cover of its targets' positions ([`cover`]);
//! the policies start uniform (and from [`SolveOptions::restarts`] random starts) and are
//! improved together by successive LP ([`local::improve_team`]). The best team found is
//! returned: anytime, a local optimum, never certified.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::chain::{Chain, Track};
use super::local;
use super::{Instance, PatrolError, Policy, Solution, SolveOptions, SolveStats};
use crate::graph::{Graph, NodeId};

/// Most target-to-patroller assignments tried.
pub const MAX_ASSIGNMENTS: usize = 64;

/// The worst start for one target and phase against a team.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Threat {
    /// Index of the target in [`Instance::targets`].
    pub target: usize,
    /// The phase of the schedule period when the attack starts.
    pub phase: usize,
    /// Each patroller's vertex at the worst joint start.
    pub from: Vec<NodeId>,
    /// Probability that some patroller stands on the target during the attack.
    pub capture_probability: f64,
    /// The attacker's expected gain: the target's value times the escape probability.
    pub expected_loss: f64,
}

/// For every target and phase, the attacker's best joint start against `policies` (one per
/// patroller, moving independently), by target then phase.
///
/// # Errors
/// As for [`Policy::attacks`]; [`PatrolError::InvalidPolicy`] for no policies.
pub fn threats(instance: &Instance, policies: &[Policy]) -> Result<Vec<Threat>, PatrolError> {
    if policies.is_empty() {
        return Err(PatrolError::InvalidPolicy("no policies".into()));
    }
    let period = instance.period()?;
    let mut worst: Vec<Threat> = (0..instance.targets.len() * period)
        .map(|k| Threat {
            target: k / period,
            phase: k % period,
            from: Vec::with_capacity(policies.len()),
            capture_probability: 0.0,
            expected_loss: 1.0,
        })
        .collect();
    for policy in policies {
        let attacks = policy.attacks(instance)?;
        // Attacks come by target, then phase, then vertex: the largest escape per (t, phase).
        for (k, threat) in worst.iter_mut().enumerate() {
            let n = policy.support().len();
            let group = &attacks[k * n..(k + 1) * n];
            let mut best = &group[0];
            for a in group {
                if a.capture_probability < best.capture_probability {
                    best = a;
                }
            }
            threat.from.push(best.from);
            threat.expected_loss *= 1.0 - best.capture_probability;
        }
    }
    for threat in &mut worst {
        threat.capture_probability = 1.0 - threat.expected_loss;
        threat.expected_loss *= instance.targets[threat.target].value;
    }
    Ok(worst)
}

/// The attacker's best expected gain against a team's policies.
///
/// # Errors
/// As for [`threats`].
pub fn team_value(instance: &Instance, policies: &[Policy]) -> Result<f64, PatrolError> {
    Ok(threats(instance, policies)?
        .iter()
        .map(|t| t.expected_loss)
        .fold(0.0, f64::max))
}

/// The smallest connected vertex set containing `nodes` (approximately: components joined by
/// shortest paths, nearest first), widened by every vertex within `radius` steps. Ascending.
/// Vertices unreachable from the first node are left out.
pub(crate) fn cover(graph: &Graph, nodes: &[NodeId], radius: usize) -> Vec<NodeId> {
    let n = graph.node_count();
    let mut wanted = vec![false; n];
    for &v in nodes {
        if v < n {
            wanted[v] = true;
        }
    }
    let mut inside = vec![false; n];
    let Some(&first) = nodes.iter().find(|&&v| v < n) else {
        return Vec::new();
    };
    inside[first] = true;
    loop {
        // Breadth-first search from the whole cover to the nearest wanted vertex outside it.
        let mut parent = vec![usize::MAX; n];
        let mut queue: std::collections::VecDeque<NodeId> = (0..n).filter(|&v| inside[v]).collect();
        for &v in &queue {
            parent[v] = v;
        }
        let mut found = None;
        while let Some(x) = queue.pop_front() {
            if wanted[x] && !inside[x] {
                found = Some(x);
                break;
            }
            for &y in graph.neighbors(x) {
                if parent[y] == usize::MAX {
                    parent[y] = x;
                    queue.push_back(y);
                }
            }
        }
        let Some(mut x) = found else {
            break;
        };
        while !inside[x] {
            inside[x] = true;
            x = parent[x];
        }
    }
    for _ in 0..radius {
        let grown: Vec<NodeId> = (0..n)
            .filter(|&v| !inside[v] && graph.neighbors(v).iter().any(|&w| inside[w]))
            .collect();
        for v in grown {
            inside[v] = true;
        }
    }
    (0..n).filter(|&v| inside[v]).collect()
}

/// The team search of the module docs.
pub(crate) fn solve(
    instance: &Instance,
    options: &SolveOptions,
    period: usize,
    targets: &[Track],
    timed: bool,
) -> Result<Solution, PatrolError> {
    let k = instance.patrollers.len();
    let graph = &instance.graph;
    let count = k
        .checked_pow(u32::try_from(targets.len()).unwrap_or(u32::MAX))
        .filter(|&c| c <= MAX_ASSIGNMENTS);
    // Assignment `a` gives target `j` to patroller `(a / k^j) % k`; patrollers are
    // interchangeable, so only assignments whose first use of each patroller comes in order.
    let assignments: Vec<Vec<usize>> = match count {
        Some(count) => (0..count)
            .map(|a| {
                (0..targets.len())
                    .map(|j| (a / k.pow(j as u32)) % k)
                    .collect::<Vec<usize>>()
            })
            .filter(|owner| {
                let mut next = 0;
                owner.iter().all(|&o| {
                    if o > next {
                        false
                    } else {
                        next += usize::from(o == next);
                        true
                    }
                })
            })
            .collect(),
        None => Vec::new(),
    };
    // Everybody guarding every target is always a candidate.
    let mut candidates: Vec<Vec<Vec<NodeId>>> = vec![vec![all_positions(targets); k]];
    for owner in &assignments {
        let supports: Vec<Vec<NodeId>> = (0..k)
            .map(|i| {
                let mine: Vec<NodeId> = targets
                    .iter()
                    .zip(owner)
                    .filter(|&(_, &o)| o == i)
                    .flat_map(|(t, _)| t.0.iter().copied())
                    .collect();
                mine
            })
            .collect();
        // Idle patrollers (no targets) help everywhere.
        let supports = supports
            .into_iter()
            .map(|s| {
                if s.is_empty() {
                    all_positions(targets)
                } else {
                    s
                }
            })
            .collect();
        candidates.push(supports);
    }
    let mut stats = SolveStats {
        supports: candidates.len(),
        ..SolveStats::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut best: Option<(Vec<Chain>, Vec<Vec<f64>>, f64)> = None;
    for positions in candidates {
        let chains: Vec<Chain> = positions
            .iter()
            .map(|p| {
                let mut nodes = p.clone();
                nodes.sort_unstable();
                nodes.dedup();
                Chain::new(graph, &cover(graph, &nodes, 0), targets, period, timed)
            })
            .collect();
        if chains.iter().any(|c| c.len() == 0) {
            continue;
        }
        let refs: Vec<&Chain> = chains.iter().collect();
        for restart in 0..=options.restarts {
            let start: Vec<Vec<f64>> = chains
                .iter()
                .map(|c| {
                    if restart == 0 {
                        local::uniform(c)
                    } else {
                        local::random(c, &mut rng)
                    }
                })
                .collect();
            let (alphas, loss) =
                local::improve_team(&refs, start, options.local_iterations, &mut stats.lp);
            stats.local_searches += 1;
            if best.as_ref().is_none_or(|b| loss < b.2) {
                best = Some((chains.clone(), alphas, loss));
            }
        }
    }
    let Some((chains, alphas, _)) = best else {
        return Err(PatrolError::InvalidInstance(
            "no patroller can reach a target".into(),
        ));
    };
    let policies: Vec<Policy> = chains
        .iter()
        .zip(&alphas)
        .map(|(c, a)| Policy::from_chain(c, a))
        .collect();
    let threats = threats(instance, &policies)?;
    let value = threats.iter().map(|t| t.expected_loss).fold(0.0, f64::max);
    let capture_probability = threats
        .iter()
        .map(|t| t.capture_probability)
        .fold(1.0, f64::min);
    Ok(Solution {
        value,
        lower_bound: 0.0,
        exact: value <= 0.0,
        capture_probability,
        policies,
        threats,
        stats,
    })
}

/// Every vertex any target visits, ascending.
fn all_positions(targets: &[Track]) -> Vec<NodeId> {
    let mut nodes: Vec<NodeId> = targets.iter().flat_map(|t| t.0.iter().copied()).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;

    #[test]
    fn covers_join_and_widen() {
        let g = graph::path(7).unwrap();
        assert_eq!(cover(&g, &[1, 4], 0), vec![1, 2, 3, 4]);
        assert_eq!(cover(&g, &[1, 4], 1), vec![0, 1, 2, 3, 4, 5]);
        assert_eq!(cover(&g, &[6], 0), vec![6]);
    }
}
