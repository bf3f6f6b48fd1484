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

use super::chain::{Chain, Track};
use super::local;
use super::tube::{self, Reach, Shape};
use super::{Instance, PatrolError, Policy, Solution, SolveOptions, SolveStats, Threat};
use crate::graph::{Graph, NodeId};

/// Most target-to-patroller assignments tried.
pub const MAX_ASSIGNMENTS: usize = 64;

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
        // Attacks come by target, then phase, then vertex: the largest escape per (t, phase).
        let mut best: Vec<Option<(f64, NodeId)>> = vec![None; worst.len()];
        for a in policy.attacks(instance)? {
            let slot = &mut best[a.target * period + a.phase % period];
            if slot.is_none_or(|(p, _)| a.capture_probability < p) {
                *slot = Some((a.capture_probability, a.from));
            }
        }
        for (threat, best) in worst.iter_mut().zip(best) {
            // A patroller with no state at some phase cannot be (its moves are closed).
            let (p, from) = best.unwrap_or((0.0, NodeId::MAX));
            threat.from.push(from);
            threat.expected_loss *= 1.0 - p;
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

/// Assignments of targets to `k` interchangeable patrollers: `owner[j]` guards target `j`;
/// only those whose first use of each patroller comes in order, and none when there are more
/// than [`MAX_ASSIGNMENTS`] of them.
fn assignments(k: usize, targets: usize) -> Vec<Vec<usize>> {
    let count = k
        .checked_pow(u32::try_from(targets).unwrap_or(u32::MAX))
        .filter(|&c| c <= MAX_ASSIGNMENTS);
    let Some(count) = count else {
        return Vec::new();
    };
    // Assignment `a` gives target `j` to patroller `(a / k^j) % k`.
    (0..count)
        .map(|a| {
            (0..targets)
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
        .collect()
}

/// The targets each patroller guards under `owner` (idle patrollers guard every target).
fn guarded(k: usize, owner: &[usize]) -> Vec<Vec<usize>> {
    (0..k)
        .map(|i| {
            let mine: Vec<usize> = (0..owner.len()).filter(|&j| owner[j] == i).collect();
            if mine.is_empty() {
                (0..owner.len()).collect()
            } else {
                mine
            }
        })
        .collect()
}

/// The tubes tried for every assignment (see [`super::tube`]): each shape with extra slack
/// beyond its tightest feasible tube. (On the village and grid instances of the examples the
/// tightest tubes of either shape won; wider ones, up to every state within reach, only cost
/// time.)
const TUBES: [(Shape, &[i64]); 2] = [(Shape::Near, &[0, 1]), (Shape::Intercept, &[0])];

/// A loss this small is a perfect patrol (up to rounding): nothing left to search.
const PERFECT: f64 = 1e-12;

/// Mass a tube's pursuit starting policy spreads evenly over every move.
const PURSUIT_SPREAD: f64 = 0.25;
/// Mass a policy lifted to a wider tube spreads evenly over every move.
const LIFT_SPREAD: f64 = 0.05;

/// A candidate team: one chain per patroller, and a starting policy for each when there is a
/// better one than uniform.
struct Candidate {
    chains: Vec<Chain>,
    starts: Option<Vec<Vec<f64>>>,
    /// Candidates of one family hold the same targets per patroller, tubes ever wider.
    family: usize,
}

/// Candidate teams: for every assignment of targets (everybody guarding everything first),
/// either each patroller on the connected cover of its targets' positions (all phases), or,
/// if `phase_locked`, on tubes of a few slacks around them (keeping all its targets within
/// reach where possible, else any of them).
fn candidates(
    instance: &Instance,
    period: usize,
    targets: &[Track],
    timed: bool,
    phase_locked: bool,
) -> Vec<Candidate> {
    let k = instance.patrollers.len();
    let graph = &instance.graph;
    let mut owners = vec![vec![k; targets.len()]];
    owners.extend(assignments(k, targets.len()));
    let mut teams = Vec::new();
    if !phase_locked {
        for (family, owner) in owners.iter().enumerate() {
            let chains = guarded(k, owner)
                .iter()
                .map(|mine| {
                    let mut nodes: Vec<NodeId> = mine
                        .iter()
                        .flat_map(|&t| targets[t].0.iter().copied())
                        .collect();
                    nodes.sort_unstable();
                    nodes.dedup();
                    Chain::new(graph, &cover(graph, &nodes, 0), targets, period, timed)
                })
                .collect();
            teams.push(Candidate {
                chains,
                starts: None,
                family,
            });
        }
        return teams;
    }
    let distance = tube::target_distances(graph, targets);
    let n = graph.node_count();
    // Slack enough to take every state within reach.
    let loosest = targets.iter().map(|t| t.1 as i64).max().unwrap_or(1) + n as i64;
    let mut family = 0;
    for owner in &owners {
        let guards = guarded(k, owner);
        for (shape, extras) in TUBES {
            // Each patroller's tightest tube keeping all its targets in reach, else any.
            let plans: Vec<Option<(Reach, Vec<i64>, i64)>> = guards
                .iter()
                .map(|mine| {
                    let plan = |reach: Reach| {
                        let rank =
                            tube::placement(graph, targets, &distance, mine, period, reach, shape);
                        // Tubes grow with the slack: bisect for the least feasible one.
                        let fits = |slack: i64| {
                            tube::tube(graph, targets, &rank, mine, period, slack, reach, shape)
                                .is_some()
                        };
                        if !fits(loosest) {
                            return None;
                        }
                        let (mut lo, mut hi) = (-1, loosest);
                        while hi - lo > 1 {
                            let mid = lo + (hi - lo) / 2;
                            if fits(mid) {
                                hi = mid;
                            } else {
                                lo = mid;
                            }
                        }
                        Some((reach, rank, hi))
                    };
                    plan(Reach::All).or_else(|| plan(Reach::Any))
                })
                .collect();
            let mut sizes: Option<Vec<usize>> = None;
            for &extra in extras {
                let team: Option<Vec<(Chain, Vec<f64>)>> = guards
                    .iter()
                    .zip(&plans)
                    .map(|(mine, plan)| {
                        let (reach, rank, slack) = plan.as_ref()?;
                        let slack = slack.saturating_add(extra).min(loosest);
                        let chain =
                            tube::tube(graph, targets, rank, mine, period, slack, *reach, shape)?;
                        let start =
                            tube::pursuit_start(&chain, targets, &distance, mine, PURSUIT_SPREAD);
                        Some((chain, start))
                    })
                    .collect();
                let Some(team) = team else {
                    continue;
                };
                let (chains, starts): (Vec<Chain>, _) = team.into_iter().unzip();
                // No wider than the last one: nothing new to search.
                let now: Vec<usize> = chains.iter().map(Chain::active_states).collect();
                if sizes.as_ref() == Some(&now) {
                    continue;
                }
                sizes = Some(now);
                teams.push(Candidate {
                    chains,
                    starts: Some(starts),
                    family,
                });
            }
            family += 1;
        }
    }
    teams
}

/// A lower bound on the loss of every team of policies on these chains: an attack on `t` at
/// phase `φ` is surely missed when every patroller has a state at `φ` from which no walk
/// inside its chain reaches the target in time.
fn certain_loss(chains: &[Chain]) -> f64 {
    let Some(first) = chains.first() else {
        return 0.0;
    };
    let refs: Vec<&Chain> = chains.iter().collect();
    let capture: Vec<Vec<f64>> = chains
        .iter()
        .map(|c| {
            let mut out = Vec::new();
            c.capture(&local::uniform(c), &mut out);
            out
        })
        .collect();
    let escape = local::escapes(&refs, &capture);
    let mut worst: f64 = 0.0;
    for (t, target) in first.targets.iter().enumerate() {
        for phase in 0..first.period {
            let k = t * first.period + phase;
            if escape.iter().all(|e| e[k] >= 1.0) {
                worst = worst.max(target.value);
            }
        }
    }
    worst
}

/// The team search of the module docs.
pub(crate) fn solve(
    instance: &Instance,
    options: &SolveOptions,
    period: usize,
    targets: &[Track],
    timed: bool,
) -> Result<Solution, PatrolError> {
    let phase_locked = options.phase_locked && period > 1;
    let candidates = candidates(instance, period, targets, timed, phase_locked);
    let mut stats = SolveStats {
        supports: candidates.len(),
        ..SolveStats::default()
    };
    stats.lp.backend = options.lp;
    stats.bnb_lp.backend = options.lp;
    // The most promising first: candidates that surely miss no attack (stable order).
    let mut candidates: Vec<(f64, Candidate)> = candidates
        .into_iter()
        .filter(|c| c.chains.iter().all(|c| c.len() > 0))
        .map(|c| (certain_loss(&c.chains), c))
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut best: Option<(Vec<Chain>, Vec<Vec<f64>>, f64)> = None;
    // A team's chains and policies' entries.
    type Team = (Vec<Chain>, Vec<Vec<f64>>);
    // Per family, the best policies of the last candidate searched.
    let families = candidates.iter().map(|c| c.1.family + 1).max().unwrap_or(0);
    let mut previous: Vec<Option<Team>> = vec![None; families];
    for (
        floor,
        Candidate {
            chains,
            starts,
            family,
        },
    ) in candidates
    {
        // Skip teams that cannot beat the best found (or tie a sure loss); stop at a perfect
        // patrol.
        if best
            .as_ref()
            .is_some_and(|b| floor >= b.2 || b.2 <= PERFECT)
        {
            continue;
        }
        stats.supports_searched += 1;
        let refs: Vec<&Chain> = chains.iter().collect();
        // A wider tube of the same family starts from the tighter one's policies.
        let lifted: Option<Vec<Vec<f64>>> = match (&previous[family], &starts) {
            (Some((narrow, alphas)), Some(fallback)) => Some(
                (0..chains.len())
                    .map(|i| {
                        tube::lift(
                            &narrow[i],
                            &alphas[i],
                            &chains[i],
                            &fallback[i],
                            LIFT_SPREAD,
                        )
                    })
                    .collect(),
            ),
            _ => None,
        };
        // Starts: the lifted policies, the pursuit ones, uniform, then in turn random ones and
        // the best so far shaken (half of every row redrawn at random).
        let uniform: Vec<Vec<f64>> = chains.iter().map(local::uniform).collect();
        let mut planned = lifted
            .into_iter()
            .chain(starts)
            .chain(std::iter::once(uniform));
        let mut family_best: Option<(Vec<Vec<f64>>, f64)> = None;
        for restart in 0..=options.restarts {
            let start: Vec<Vec<f64>> = match (planned.next(), &family_best) {
                (Some(start), _) => start,
                (None, Some((best, _))) if restart % 2 == 0 => chains
                    .iter()
                    .zip(best)
                    .map(|(c, b)| {
                        let noise = local::random(c, &mut rng);
                        b.iter().zip(noise).map(|(x, y)| 0.5 * (x + y)).collect()
                    })
                    .collect(),
                (None, _) => chains.iter().map(|c| local::random(c, &mut rng)).collect(),
            };
            let (alphas, loss) =
                local::improve_team(&refs, start, options.local_iterations, &mut stats.lp);
            stats.local_searches += 1;
            if family_best.as_ref().is_none_or(|b| loss < b.1) {
                family_best = Some((alphas.clone(), loss));
            }
            if best.as_ref().is_none_or(|b| loss < b.2) {
                best = Some((chains.clone(), alphas, loss));
            }
            if loss <= PERFECT {
                break;
            }
        }
        if let Some((alphas, _)) = family_best {
            previous[family] = Some((chains, alphas));
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
    let policies = if phase_locked {
        recurrent_team(instance, policies)?
    } else {
        policies
    };
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

/// Moves less likely than this are dropped before restricting a policy to a recurrent class.
const TINY_MOVE: f64 = 1e-9;

/// Most combinations of recurrent classes compared when restricting a team.
const MAX_CLASS_COMBINATIONS: usize = 64;

/// Restricts every time-dependent policy to one closed class of its states (where the
/// patroller really ends up; the others are never visited again, so the attacker never sees
/// them): the best combination for the team, or each patroller's best class on its own when
/// there are too many combinations.
pub(crate) fn recurrent_team(
    instance: &Instance,
    policies: Vec<Policy>,
) -> Result<Vec<Policy>, PatrolError> {
    let options: Vec<Vec<Policy>> = policies
        .iter()
        .map(|p| {
            if p.phases() == 1 {
                return vec![p.clone()];
            }
            let p = &p.without_tiny_moves(TINY_MOVE);
            let classes = p.recurrent_states();
            if classes.is_empty() {
                vec![p.clone()]
            } else {
                classes.iter().map(|c| p.restricted_to_states(c)).collect()
            }
        })
        .collect();
    let combinations = options
        .iter()
        .try_fold(1usize, |acc, o| acc.checked_mul(o.len()))
        .filter(|&c| c <= MAX_CLASS_COMBINATIONS);
    let mut chosen: Vec<Policy> = options.iter().map(|o| o[0].clone()).collect();
    let mut best = team_value(instance, &chosen)?;
    match combinations {
        Some(count) => {
            for mut code in 1..count {
                let team: Vec<Policy> = options
                    .iter()
                    .map(|o| {
                        let pick = code % o.len();
                        code /= o.len();
                        o[pick].clone()
                    })
                    .collect();
                let value = team_value(instance, &team)?;
                if value < best {
                    (chosen, best) = (team, value);
                }
            }
        }
        None => {
            for (i, o) in options.iter().enumerate() {
                for candidate in &o[1..] {
                    let mut team = chosen.clone();
                    team[i] = candidate.clone();
                    let value = team_value(instance, &team)?;
                    if value < best {
                        (chosen, best) = (team, value);
                    }
                }
            }
        }
    }
    Ok(chosen)
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
