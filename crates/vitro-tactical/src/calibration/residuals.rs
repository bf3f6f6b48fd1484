//! How far an abstract level's trip times are from the concrete level's.

use serde::{Deserialize, Serialize};

/// How far an abstract level's trip times are from the concrete level's.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Residuals {
    /// Trips.
    pub n: usize,
    /// Mean relative error without calibration, % (signed: negative = optimistic).
    pub bias_pct_before: f64,
    /// Mean absolute relative error without calibration, %.
    pub mape_pct_before: f64,
    /// Root mean square error without calibration, seconds.
    pub rmse_s_before: f64,
    /// Mean relative error with calibration, % (signed).
    pub bias_pct_after: f64,
    /// Mean absolute relative error with calibration, %.
    pub mape_pct_after: f64,
    /// Root mean square error with calibration, seconds.
    pub rmse_s_after: f64,
    /// Largest absolute relative error with calibration, %.
    pub max_pct_after: f64,
}

impl Residuals {
    /// The residuals of `before` and `after` against `concrete` (paired, seconds).
    pub fn of(concrete: &[f64], before: &[f64], after: &[f64]) -> Self {
        let n = concrete.len().min(before.len()).min(after.len());
        if n == 0 {
            return Residuals::default();
        }
        let stats = |pred: &[f64]| {
            let (mut bias, mut abs, mut sq, mut max) = (0.0, 0.0, 0.0, 0.0f64);
            for (c, p) in concrete.iter().zip(pred) {
                let rel = 100.0 * (p - c) / c.max(1e-9);
                bias += rel;
                abs += rel.abs();
                max = max.max(rel.abs());
                sq += (p - c) * (p - c);
            }
            let n = n as f64;
            (bias / n, abs / n, libm::sqrt(sq / n), max)
        };
        let b = stats(before);
        let a = stats(after);
        Residuals {
            n,
            bias_pct_before: b.0,
            mape_pct_before: b.1,
            rmse_s_before: b.2,
            bias_pct_after: a.0,
            mape_pct_after: a.1,
            rmse_s_after: a.2,
            max_pct_after: a.3,
        }
    }
}

/// The median of `v` (0 for an empty list).
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}
