//! A linear-programming lower bound on the loss over a box of policies.
//!
//! Inside a box `lo ≤ α ≤ hi` pick a stochastic point `x`. Every capture probability `P` is a
//! polynomial with non-negative coefficients, so its partial derivatives are non-decreasing in
//! every entry, and along the segment from `x` to any `α` in the box the mean-value theorem
//! gives, entry by entry,
//! `P(α) ≤ P(x) + Σ_e ∂_eP(hi)·(α_e − x_e)⁺ − Σ_e ∂_eP(lo)·(x_e − α_e)⁺`.
//! Writing `α − x = u − d` with `0 ≤ u ≤ hi − x`, `0 ≤ d ≤ x − lo`, the program
//! `min z s.t. z ≥ value_t · (1 − [P(x) + ∂P(hi)·u − ∂P(lo)·d])` for every attack, rows of
//! `u − d` summing to 0, is a linear relaxation of the patroller's problem on the box (any
//! split `u − d` only raises the right-hand bound on `P`), so its optimum is a valid lower
//! bound. Its error is `O((∂P(hi) − ∂P(lo))·width) = O(width²)`: second order, where the
//! interval bound of [`super::chain::Chain::capture_upper`] is first order. It also couples all
//! attacks through one policy, which per-attack interval bounds cannot.

use good_lp::{Expression, ProblemVariables, variable};

use super::PatrolError;
use super::chain::{Chain, Gradients};
use super::local::LpStats;

/// The relaxation's result on one box.
pub(crate) struct Relaxation {
    /// A lower bound on the loss of every policy in the box.
    pub(crate) bound: f64,
    /// The relaxation's optimal policy (inside the box, stochastic): a candidate incumbent.
    pub(crate) alpha: Vec<f64>,
    /// Per entry, how much its width contributes to the bound's error on the binding attacks.
    pub(crate) score: Vec<f64>,
}

/// Safety margin against the LP solver's rounding.
const MARGIN: f64 = 1e-9;

/// Solves the relaxation on the (tightened) box `lo..hi` around the stochastic point `x`.
pub(crate) fn relax(
    chain: &Chain,
    lo: &[f64],
    hi: &[f64],
    x: &[f64],
    stats: &mut LpStats,
) -> Result<Relaxation, PatrolError> {
    let n = chain.states();
    let m = chain.entries();
    let mut capture = Vec::new();
    chain.capture(x, &mut capture);
    let mut gradients = Vec::with_capacity(chain.targets.len());
    for t in 0..chain.targets.len() {
        let (mut upper, mut lower) = (Gradients::default(), Gradients::default());
        chain.gradients(hi, t, &mut upper);
        chain.gradients(lo, t, &mut lower);
        gradients.push((upper, lower));
    }
    let mut vars = ProblemVariables::new();
    let up: Vec<_> = (0..m)
        .map(|e| vars.add(variable().min(0.0).max((hi[e] - x[e]).max(0.0))))
        .collect();
    let down: Vec<_> = (0..m)
        .map(|e| vars.add(variable().min(0.0).max((x[e] - lo[e]).max(0.0))))
        .collect();
    let z = vars.add(variable().min(0.0));
    let mut model = Vec::new();
    let mut constraints = 0;
    for i in 0..chain.rows() {
        let mut row = Expression::with_capacity(2 * chain.row(i).len());
        for e in chain.row(i) {
            row.add_mul(1.0, up[e]);
            row.add_mul(-1.0, down[e]);
        }
        model.push(row.eq(0.0));
        constraints += 1;
    }
    // Attacks on targets outside the support are never caught: a constant floor.
    let mut floor: f64 = 0.0;
    for (t, target) in chain.targets.iter().enumerate() {
        if !target.reachable() {
            floor = floor.max(target.value);
            continue;
        }
        let (g_up, g_down) = &gradients[t];
        for h in (0..n).filter(|&h| chain.is_active(h)) {
            let mut lhs = Expression::from(z);
            for (e, a, b) in merged(g_up, g_down, h) {
                if a != 0.0 {
                    lhs.add_mul(target.value * a, up[e]);
                }
                if b != 0.0 {
                    lhs.add_mul(-target.value * b, down[e]);
                }
            }
            let rhs = target.value * (1.0 - capture[t * n + h]);
            model.push(lhs.geq(rhs));
            constraints += 1;
        }
    }
    stats.solves += 1;
    stats.max_variables = stats.max_variables.max(2 * m + 1);
    stats.max_constraints = stats.max_constraints.max(constraints);
    let solution = super::lp::minimise(vars, z, model, stats.backend)?;
    let z_value = solution.value(z);
    let (u, d): (Vec<f64>, Vec<f64>) = (0..m)
        .map(|e| (solution.value(up[e]), solution.value(down[e])))
        .unzip();
    let mut alpha: Vec<f64> = (0..m)
        .map(|e| (x[e] + u[e] - d[e]).clamp(lo[e], hi[e]))
        .collect();
    for i in 0..chain.rows() {
        let sum: f64 = chain.row(i).map(|e| alpha[e]).sum();
        for e in chain.row(i) {
            alpha[e] /= sum;
        }
    }
    // Binding attacks: those whose relaxed loss reaches the optimum.
    let mut score = vec![0.0f64; m];
    for (t, target) in chain.targets.iter().enumerate() {
        if !target.reachable() {
            continue;
        }
        let (g_up, g_down) = &gradients[t];
        for h in (0..n).filter(|&h| chain.is_active(h)) {
            let relaxed: f64 = capture[t * n + h]
                + merged(g_up, g_down, h)
                    .map(|(e, a, b)| a * u[e] - b * d[e])
                    .sum::<f64>();
            if target.value * (1.0 - relaxed) < z_value - 1e-9 {
                continue;
            }
            for (e, a, b) in merged(g_up, g_down, h) {
                let error = target.value * (a - b) * (hi[e] - lo[e]);
                score[e] = score[e].max(error);
            }
        }
    }
    Ok(Relaxation {
        bound: (z_value - MARGIN).max(floor),
        alpha,
        score,
    })
}

/// The entries where either gradient of start `h` is non-zero, ascending, with both values
/// (0 where one has none).
fn merged<'a>(
    upper: &'a Gradients,
    lower: &'a Gradients,
    h: usize,
) -> impl Iterator<Item = (usize, f64, f64)> + 'a {
    let (ue, uv) = upper.at(h);
    let (le, lv) = lower.at(h);
    let (mut i, mut j) = (0, 0);
    std::iter::from_fn(move || {
        let a = ue.get(i).copied();
        let b = le.get(j).copied();
        match (a, b) {
            (Some(x), Some(y)) if x == y => {
                (i, j) = (i + 1, j + 1);
                Some((x, uv[i - 1], lv[j - 1]))
            }
            (Some(x), Some(y)) if x < y => {
                i += 1;
                Some((x, uv[i - 1], 0.0))
            }
            (Some(x), None) => {
                i += 1;
                Some((x, uv[i - 1], 0.0))
            }
            (_, Some(y)) => {
                j += 1;
                Some((y, 0.0, lv[j - 1]))
            }
            (None, None) => None,
        }
    })
}
