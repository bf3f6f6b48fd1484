//! Local optimisation of a Markov policy by successive linear programming (good_lp + Clarabel
//! or microlp).
//!
//! The patroller's problem on a fixed support is
//! `minimise z  s.t.  z ≥ value_t · (1 − P(t, h; α))` for every attack `(t, h)`, with each row
//! of `α` a probability distribution. `P` is a polynomial in `α`, so the program is non-linear
//! and non-convex. Each iteration replaces every `P(t, h; α)` by its first-order expansion at
//! the current policy, adds a trust region `|α − α_k| ≤ Δ`, and solves the resulting linear
//! program; the step is accepted if the true worst-case loss drops, and `Δ` grows or shrinks
//! with the agreement between predicted and actual decrease. This converges to a local
//! optimum, not necessarily the global one: [`super::exact`] certifies global optimality.
//!
//! The same method optimises a team of independent patrollers ([`improve_team`]): the escape
//! probability from a joint start is the product of the individual ones, linearised too.

use good_lp::{Expression, ProblemVariables, variable};

use super::PatrolError;
use super::chain::{Chain, Gradients};

/// LP work done, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct LpStats {
    /// Linear programs solved.
    pub solves: u64,
    /// Variables in the largest one.
    pub max_variables: usize,
    /// Constraints in the largest one (variable bounds not counted).
    pub max_constraints: usize,
    /// Solves that failed numerically (the caller fell back to a safe alternative).
    pub failures: u64,
    /// The LP solver used (set from [`SolveOptions::lp`](super::SolveOptions::lp)).
    pub backend: super::LpBackend,
}

/// The uniform policy on a chain: every row spread evenly over its entries.
pub(crate) fn uniform(chain: &Chain) -> Vec<f64> {
    let mut alpha = vec![0.0; chain.entries()];
    for i in 0..chain.rows() {
        let row = chain.row(i);
        let p = 1.0 / row.len() as f64;
        for e in row {
            alpha[e] = p;
        }
    }
    alpha
}

/// A random policy on a chain: every row drawn from a flat Dirichlet distribution (normalised
/// exponentials), a restart point for the local search.
pub(crate) fn random(chain: &Chain, rng: &mut impl rand::Rng) -> Vec<f64> {
    let mut alpha = vec![0.0; chain.entries()];
    for i in 0..chain.rows() {
        let row = chain.row(i);
        let mut sum = 0.0;
        for e in row.clone() {
            let u: f64 = rng.random();
            alpha[e] = -libm::log(1.0 - u);
            sum += alpha[e];
        }
        for e in row {
            alpha[e] /= sum;
        }
    }
    alpha
}

/// Escape probabilities of a team: `escape[i][t * period + φ]` is the largest chance, over
/// patroller `i`'s active start states at phase `φ`, that `i` misses an attack on target `t`
/// started then; `capture[i]` holds the chains' capture probabilities.
pub(crate) fn escapes(chains: &[&Chain], capture: &[Vec<f64>]) -> Vec<Vec<f64>> {
    chains
        .iter()
        .zip(capture)
        .map(|(chain, cap)| {
            let (n, period) = (chain.len(), chain.period);
            (0..chain.targets.len() * period)
                .map(|k| {
                    let phase_start = (k % period) * n;
                    cap[k * n..(k + 1) * n]
                        .iter()
                        .enumerate()
                        .filter(|&(x, _)| chain.is_active(phase_start + x))
                        .map(|(_, &p)| 1.0 - p.min(1.0))
                        .fold(0.0, f64::max)
                })
                .collect()
        })
        .collect()
}

/// The attacker's best expected gain against a team of independent patrollers, one chain each
/// (same targets and period): `max over (t, φ) of value_t · Π_i escape_i(t, φ)`. Patrollers
/// move independently, so the escape probability from a joint start is the product of the
/// individual ones, and the worst joint start takes each patroller's worst start. For a single
/// chain this is [`Chain::loss`].
pub(crate) fn team_loss(chains: &[&Chain], alphas: &[Vec<f64>]) -> f64 {
    let capture: Vec<Vec<f64>> = chains
        .iter()
        .zip(alphas)
        .map(|(chain, alpha)| {
            let mut out = Vec::new();
            chain.capture(alpha, &mut out);
            out
        })
        .collect();
    loss_from_escapes(chains, &escapes(chains, &capture))
}

fn loss_from_escapes(chains: &[&Chain], escape: &[Vec<f64>]) -> f64 {
    let Some(first) = chains.first() else {
        return 0.0;
    };
    let period = first.period;
    let mut worst: f64 = 0.0;
    for (t, target) in first.targets.iter().enumerate() {
        for phase in 0..period {
            let k = t * period + phase;
            let product: f64 = escape.iter().map(|e| e[k]).product();
            worst = worst.max(target.value * product);
        }
    }
    worst
}

/// Improves `alpha` on `chain` by successive linear programming; returns the final entries and
/// their exact loss (never worse than the start's).
pub(crate) fn improve(
    chain: &Chain,
    alpha: Vec<f64>,
    max_iterations: usize,
    stats: &mut LpStats,
) -> (Vec<f64>, f64) {
    let (mut alphas, loss) = improve_team(&[chain], vec![alpha], max_iterations, stats);
    (alphas.pop().unwrap_or_default(), loss)
}

/// The trust region below which a local search stops (steps that small change no value
/// reported to six digits).
const MIN_RADIUS: f64 = 1e-6;
/// The smallest predicted decrease of the loss worth another step.
const MIN_DECREASE: f64 = 1e-10;

/// Improves a team's policies (one chain and entry vector per patroller) by successive linear
/// programming on [`team_loss`]; returns the final entries and their exact loss (never worse
/// than the start's).
pub(crate) fn improve_team(
    chains: &[&Chain],
    mut alphas: Vec<Vec<f64>>,
    max_iterations: usize,
    stats: &mut LpStats,
) -> (Vec<Vec<f64>>, f64) {
    let mut loss = team_loss(chains, &alphas);
    let mut radius = 0.25;
    let mut gradients: Vec<Vec<Gradients>> = chains
        .iter()
        .map(|c| vec![Gradients::default(); c.targets.len()])
        .collect();
    for _ in 0..max_iterations {
        if loss <= 0.0 || radius < MIN_RADIUS {
            break;
        }
        let mut capture = Vec::with_capacity(chains.len());
        for ((chain, alpha), grads) in chains.iter().zip(&alphas).zip(&mut gradients) {
            let mut cap = Vec::new();
            chain.capture(alpha, &mut cap);
            capture.push(cap);
            for (t, grad) in grads.iter_mut().enumerate() {
                chain.gradients(alpha, t, grad);
            }
        }
        let point = Linearisation {
            alphas: &alphas,
            capture: &capture,
            gradients: &gradients,
        };
        // A numerical failure of the LP solver ends the local search with what it has.
        let Ok((candidate, predicted)) = linearised_step(chains, &point, radius, stats) else {
            stats.failures += 1;
            break;
        };
        let predicted_decrease = loss - predicted;
        if predicted_decrease <= MIN_DECREASE {
            break;
        }
        let candidate_loss = team_loss(chains, &candidate);
        let actual_decrease = loss - candidate_loss;
        if actual_decrease > 0.0 {
            alphas = candidate;
            loss = candidate_loss;
            if actual_decrease > 0.75 * predicted_decrease {
                radius = (radius * 2.0).min(1.0);
            } else if actual_decrease < 0.25 * predicted_decrease {
                radius *= 0.5;
            }
        } else {
            radius *= 0.25;
        }
    }
    (alphas, loss)
}

/// The current point of a local search: entries, capture probabilities and their gradients,
/// per patroller.
struct Linearisation<'a> {
    alphas: &'a [Vec<f64>],
    capture: &'a [Vec<f64>],
    gradients: &'a [Vec<Gradients>],
}

/// Above this many attack rows the linearised program keeps only an active set: per
/// patroller, target and phase, the starts whose escape probability is within
/// [`ACTIVE_MARGIN`] of the worst, at most [`ACTIVE_STARTS`] of them (the worst ones); steps
/// are still accepted only if the exact loss drops.
const ALL_ROWS_LIMIT: usize = 3000;
const ACTIVE_MARGIN: f64 = 0.2;
const ACTIVE_STARTS: usize = 6;

/// Solves the linearised program around the current point within the trust region; returns
/// the new entries (rows renormalised) and the predicted worst-case loss.
///
/// Variables: the entries `x_i`, one escape level `y_{i,t,φ}` per patroller, target and phase,
/// and the loss `z`. Constraints: rows stochastic; `y_{i,t,φ} ≥ 1 − linearised P_i(t, h, φ)`
/// for every start `h`; `z ≥ value_t · (Π_i y_{i,t,φ})` with the product linearised at the
/// current escape levels (exact for a single patroller).
fn linearised_step(
    chains: &[&Chain],
    point: &Linearisation,
    radius: f64,
    stats: &mut LpStats,
) -> Result<(Vec<Vec<f64>>, f64), PatrolError> {
    let escape = escapes(chains, point.capture);
    let mut vars = ProblemVariables::new();
    let x: Vec<Vec<_>> = point
        .alphas
        .iter()
        .map(|alpha| {
            alpha
                .iter()
                .map(|&a| {
                    vars.add(
                        variable()
                            .min((a - radius).max(0.0))
                            .max((a + radius).min(1.0)),
                    )
                })
                .collect()
        })
        .collect();
    // Starts whose capture probability no move can change (the target is out of reach) bound
    // their escape level from below by a constant: a variable bound, not a row.
    let floors: Vec<Vec<f64>> = chains
        .iter()
        .enumerate()
        .map(|(i, chain)| {
            let (n, states) = (chain.len(), chain.states());
            let mut floor = vec![0.0f64; escape[i].len()];
            for t in 0..chain.targets.len() {
                for start in (0..states).filter(|&s| chain.is_active(s)) {
                    if point.gradients[i][t].at(start).0.is_empty() {
                        let k = t * chain.period + start / n;
                        let p = point.capture[i][t * states + start];
                        floor[k] = floor[k].max(1.0 - p);
                    }
                }
            }
            floor
        })
        .collect();
    let y: Vec<Vec<_>> = floors
        .iter()
        .map(|f| f.iter().map(|&lo| vars.add(variable().min(lo))).collect())
        .collect();
    let z = vars.add(variable().min(0.0));
    let variables: usize = x.iter().map(Vec::len).sum::<usize>() + escape.len() * escape[0].len();
    let mut model = Vec::new();
    let mut constraints = 0;
    let total_rows: usize = chains
        .iter()
        .map(|c| c.targets.len() * c.active_states())
        .sum();
    let margin = if total_rows <= ALL_ROWS_LIMIT {
        f64::INFINITY
    } else {
        ACTIVE_MARGIN
    };
    for (i, chain) in chains.iter().enumerate() {
        let (n, states) = (chain.len(), chain.states());
        let alpha = &point.alphas[i];
        for r in 0..chain.rows() {
            let mut row = Expression::with_capacity(chain.row(r).len());
            for e in chain.row(r) {
                row.add_mul(1.0, x[i][e]);
            }
            model.push(row.eq(1.0));
            constraints += 1;
        }
        for t in 0..chain.targets.len() {
            // The starts kept, per phase: within the margin, the worst few in active-set mode.
            let mut kept = vec![false; states];
            for phase in 0..chain.period {
                let k = t * chain.period + phase;
                let mut near: Vec<(f64, usize)> = (phase * n..(phase + 1) * n)
                    .filter(|&s| chain.is_active(s))
                    .filter(|&s| !point.gradients[i][t].at(s).0.is_empty())
                    .map(|s| (1.0 - point.capture[i][t * states + s].min(1.0), s))
                    .filter(|&(e, _)| e >= escape[i][k] - margin)
                    .collect();
                if margin.is_finite() {
                    near.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
                    near.truncate(ACTIVE_STARTS);
                }
                for (_, s) in near {
                    kept[s] = true;
                }
            }
            for start in (0..states).filter(|&s| kept[s]) {
                // y ≥ 1 − P − g·(x − α)  ⇔  y + g·x ≥ 1 − P + g·α.
                let k = t * chain.period + start / n;
                let p = point.capture[i][t * states + start];
                let (entries, values) = point.gradients[i][t].at(start);
                let mut lhs = Expression::from(y[i][k]);
                let mut rhs = 1.0 - p;
                for (&e, &g) in entries.iter().zip(values) {
                    lhs.add_mul(g, x[i][e]);
                    rhs += g * alpha[e];
                }
                model.push(lhs.geq(rhs));
                constraints += 1;
            }
        }
    }
    let first = chains[0];
    for (t, target) in first.targets.iter().enumerate() {
        for phase in 0..first.period {
            // z ≥ v (E⁰ + Σ_i c_i (y_i − y_i⁰)), c_i = Π_{k≠i} y_k⁰.
            let k = t * first.period + phase;
            let levels: Vec<f64> = escape.iter().map(|e| e[k]).collect();
            let product: f64 = levels.iter().product();
            let mut lhs = Expression::from(z);
            let mut rhs = product;
            for i in 0..chains.len() {
                let others: f64 = (0..chains.len())
                    .filter(|&j| j != i)
                    .map(|j| levels[j])
                    .product();
                lhs.add_mul(-target.value * others, y[i][k]);
                rhs -= others * levels[i];
            }
            model.push(lhs.geq(target.value * rhs));
            constraints += 1;
        }
    }
    stats.solves += 1;
    stats.max_variables = stats.max_variables.max(variables + 1);
    stats.max_constraints = stats.max_constraints.max(constraints);
    let solution = super::lp::minimise(vars, z, model, stats.backend)?;
    let mut next = Vec::with_capacity(chains.len());
    for (chain, xs) in chains.iter().zip(&x) {
        let mut alpha: Vec<f64> = xs
            .iter()
            .map(|&v| solution.value(v).clamp(0.0, 1.0))
            .collect();
        for r in 0..chain.rows() {
            let sum: f64 = chain.row(r).map(|e| alpha[e]).sum();
            if sum > 0.0 {
                for e in chain.row(r) {
                    alpha[e] /= sum;
                }
            }
        }
        next.push(alpha);
    }
    Ok((next, solution.value(z)))
}
