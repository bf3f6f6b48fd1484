//! Local optimisation of a Markov policy by successive linear programming (good_lp + microlp).
//!
//! The patroller's problem on a fixed support is
//! `minimise z  s.t.  z ≥ value_t · (1 − P(t, h; α))` for every attack `(t, h)`, with each row
//! of `α` a probability distribution. `P` is a polynomial in `α`, so the program is non-linear
//! and non-convex. Each iteration replaces every `P(t, h; α)` by its first-order expansion at
//! the current policy, adds a trust region `|α − α_k| ≤ Δ`, and solves the resulting linear
//! program; the step is accepted if the true worst-case loss drops, and `Δ` grows or shrinks
//! with the agreement between predicted and actual decrease. This converges to a local
//! optimum, not necessarily the global one: [`super::exact`] certifies global optimality.

use good_lp::{Expression, ProblemVariables, Solution, SolverModel, microlp, variable};

use super::PatrolError;
use super::chain::Chain;

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
}

/// The uniform policy on a chain: every row spread evenly over its entries.
pub(crate) fn uniform(chain: &Chain) -> Vec<f64> {
    let mut alpha = vec![0.0; chain.entries()];
    for i in 0..chain.len() {
        let row = chain.row(i);
        let p = 1.0 / row.len() as f64;
        for e in row {
            alpha[e] = p;
        }
    }
    alpha
}

/// Improves `alpha` on `chain` by successive linear programming; returns the final entries and
/// their exact loss (never worse than the start's).
pub(crate) fn improve(
    chain: &Chain,
    mut alpha: Vec<f64>,
    max_iterations: usize,
    stats: &mut LpStats,
) -> (Vec<f64>, f64) {
    let mut scratch = Vec::new();
    let mut loss = chain.loss(&alpha, &mut scratch);
    let mut radius = 0.25;
    let mut gradients: Vec<Vec<f64>> = vec![Vec::new(); chain.targets.len()];
    for _ in 0..max_iterations {
        if loss <= 0.0 || radius < 1e-9 {
            break;
        }
        chain.capture(&alpha, &mut scratch);
        for (t, grad) in gradients.iter_mut().enumerate() {
            chain.gradients(&alpha, t, grad);
        }
        // A numerical failure of the LP solver ends the local search with what it has.
        let Ok((candidate, predicted)) =
            linearised_step(chain, &alpha, &scratch, &gradients, radius, stats)
        else {
            stats.failures += 1;
            break;
        };
        let predicted_decrease = loss - predicted;
        if predicted_decrease <= 1e-12 {
            break;
        }
        let candidate_loss = chain.loss(&candidate, &mut scratch);
        let actual_decrease = loss - candidate_loss;
        if actual_decrease > 0.0 {
            alpha = candidate;
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
    (alpha, loss)
}

/// Solves the linearised program around `alpha` within the trust region; returns the new
/// entries (rows renormalised) and the predicted worst-case loss.
fn linearised_step(
    chain: &Chain,
    alpha: &[f64],
    capture: &[f64],
    gradients: &[Vec<f64>],
    radius: f64,
    stats: &mut LpStats,
) -> Result<(Vec<f64>, f64), PatrolError> {
    let n = chain.len();
    let m = chain.entries();
    let mut vars = ProblemVariables::new();
    let x: Vec<_> = alpha
        .iter()
        .map(|&a| {
            vars.add(
                variable()
                    .min((a - radius).max(0.0))
                    .max((a + radius).min(1.0)),
            )
        })
        .collect();
    let z = vars.add(variable().min(0.0));
    let mut model = vars.minimise(z).using(microlp);
    let mut constraints = 0;
    for i in 0..n {
        let mut row = Expression::with_capacity(chain.row(i).len());
        for e in chain.row(i) {
            row.add_mul(1.0, x[e]);
        }
        model = model.with(row.eq(1.0));
        constraints += 1;
    }
    for (t, target) in chain.targets.iter().enumerate() {
        for h in 0..n {
            // z ≥ v (1 − P − g·(x − α))  ⇔  z + v g·x ≥ v (1 − P + g·α).
            let grad = &gradients[t][h * m..(h + 1) * m];
            let p = capture[t * n + h];
            let mut lhs = Expression::from(z);
            let mut rhs = 1.0 - p;
            for e in 0..m {
                if grad[e] != 0.0 {
                    lhs.add_mul(target.value * grad[e], x[e]);
                    rhs += grad[e] * alpha[e];
                }
            }
            model = model.with(lhs.geq(target.value * rhs));
            constraints += 1;
        }
    }
    stats.solves += 1;
    stats.max_variables = stats.max_variables.max(m + 1);
    stats.max_constraints = stats.max_constraints.max(constraints);
    let solution = model.solve().map_err(|e| PatrolError::Lp(e.to_string()))?;
    let mut next: Vec<f64> = x
        .iter()
        .map(|&v| solution.value(v).clamp(0.0, 1.0))
        .collect();
    for i in 0..n {
        let sum: f64 = chain.row(i).map(|e| next[e]).sum();
        if sum > 0.0 {
            for e in chain.row(i) {
                next[e] /= sum;
            }
        }
    }
    Ok((next, solution.value(z)))
}
