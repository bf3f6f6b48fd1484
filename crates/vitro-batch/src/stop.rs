//! Conditioned experiments: a `[stop]` table makes `replicates` the most runs per point and
//! stops adding replicates to a point once the 95% confidence interval of a metric's mean
//! there is narrow enough.
//!
//! ```toml
//! replicates = 40                 # at most 40 runs per point
//! [stop]
//! metric = "time_to_extraction_s"
//! half_width = 15.0               # stop once the 95% CI of the mean is within ±15 s
//! min_replicates = 5              # never fewer runs than this (default 5)
//! ```
//!
//! Point `p` gets replicates `0, 1, 2, ...` of the fixed design (the same runs and seeds as
//! without `[stop]`), and stops at the first `n >= min_replicates` whose first `n` results
//! meet the rule, or at `replicates`. The rule reads only the point's own first `n` results,
//! so what is run does not depend on the job count, the order runs end in, or a resume.
//! Runs go in rounds: every open point gets its next replicate, all in parallel.
//!
//! The interval of a numeric metric is Student's (`t · s / √n`); of a boolean one (a rate),
//! Wilson's score interval. Runs that failed or lack the metric (NaN) do not count.

use crate::journal::{RunRecord, Status};
use crate::stats::{t975, wilson};
use crate::value::Value;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The `[stop]` table as written.
#[derive(Clone, Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StopFile {
    /// The metric whose mean is estimated (a number, or a boolean as a rate).
    pub metric: String,
    /// Stop a point once the half-width of the 95% CI of the metric's mean is at most this.
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub half_width: f64,
    /// Fewest replicates per point (default 5, at least 2).
    #[schemars(range(min = 2))]
    pub min_replicates: Option<u32>,
}

/// A checked stopping rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StopRule {
    /// The metric.
    pub metric: String,
    /// The largest half-width accepted.
    pub half_width: f64,
    /// Fewest replicates per point.
    pub min_replicates: u32,
}

/// How the rule ended at one point (recorded in the manifest).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointStop {
    /// The point.
    pub point: u64,
    /// Replicates made.
    pub replicates: u32,
    /// The metric's mean over them (NaN/null: none counted).
    pub mean: f64,
    /// The half-width of its 95% CI (NaN/null: fewer than 2 counted).
    pub half_width: f64,
    /// The rule held (false: stopped at the most replicates).
    pub met: bool,
}

/// The rule and its outcome at every point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StopReport {
    /// The rule.
    pub rule: StopRule,
    /// Each point, in order.
    pub points: Vec<PointStop>,
}

/// Checks the table: the metric is reported, the width positive, the minimum in
/// `2..=replicates`. Errors name the key at fault.
pub(crate) fn check(
    file: &StopFile,
    replicates: u32,
    metrics: &[String],
) -> Result<StopRule, (&'static str, String)> {
    if !metrics.contains(&file.metric) {
        return Err((
            "metric",
            format!(
                "unknown metric `{}`, expected one of: {}",
                file.metric,
                metrics.join(", ")
            ),
        ));
    }
    if !(file.half_width > 0.0 && file.half_width.is_finite()) {
        return Err((
            "half_width",
            format!(
                "invalid half-width {}, expected a positive number",
                file.half_width
            ),
        ));
    }
    let min = file.min_replicates.unwrap_or(5.min(replicates.max(2)));
    if min < 2 || min > replicates {
        return Err((
            "min_replicates",
            format!("invalid minimum {min}, expected 2 to `replicates` ({replicates})"),
        ));
    }
    Ok(StopRule {
        metric: file.metric.clone(),
        half_width: file.half_width,
        min_replicates: min,
    })
}

impl StopRule {
    /// Mean and CI half-width of the metric over `records` (one point's first replicates).
    pub fn estimate(&self, records: &[&RunRecord]) -> (f64, f64) {
        let values: Vec<&Value> = records
            .iter()
            .filter(|r| r.status == Status::Ok)
            .filter_map(|r| r.metrics.get(&self.metric))
            .collect();
        if values.iter().all(|v| matches!(v, Value::Bool(_))) && !values.is_empty() {
            let k = values.iter().filter(|v| ***v == Value::Bool(true)).count();
            return match wilson(k, values.len()) {
                Some(ci) => (ci.mean, (ci.hi - ci.lo) / 2.0),
                None => (f64::NAN, f64::NAN),
            };
        }
        let xs: Vec<f64> = values
            .iter()
            .filter_map(|v| v.as_f64())
            .filter(|x| x.is_finite())
            .collect();
        let n = xs.len();
        if n == 0 {
            return (f64::NAN, f64::NAN);
        }
        let mean = xs.iter().sum::<f64>() / n as f64;
        if n < 2 {
            return (mean, f64::NAN);
        }
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
        (mean, t975(n - 1) * (var / n as f64).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn rec(run: u64, x: Value) -> RunRecord {
        RunRecord {
            run,
            point: 0,
            replicate: run as u32,
            seed: run,
            params: BTreeMap::new(),
            status: Status::Ok,
            error: None,
            wall_s: 0.0,
            metrics: BTreeMap::from([("m".to_string(), x)]),
            series: Vec::new(),
        }
    }

    #[test]
    fn estimates_numbers_and_rates() {
        let rule = StopRule {
            metric: "m".into(),
            half_width: 1.0,
            min_replicates: 2,
        };
        let r: Vec<RunRecord> = [1.0, 2.0, 3.0]
            .iter()
            .enumerate()
            .map(|(i, &x)| rec(i as u64, Value::Float(x)))
            .collect();
        let refs: Vec<&RunRecord> = r.iter().collect();
        let (mean, hw) = rule.estimate(&refs);
        assert_eq!(mean, 2.0);
        assert!((hw - 4.3027 / 3f64.sqrt()).abs() < 1e-3);
        let b: Vec<RunRecord> = (0..10).map(|i| rec(i, Value::Bool(i < 5))).collect();
        let refs: Vec<&RunRecord> = b.iter().collect();
        let (rate, hw) = rule.estimate(&refs);
        assert_eq!(rate, 0.5);
        assert!((hw - (0.7634 - 0.2366) / 2.0).abs() < 1e-3);
        assert!(rule.estimate(&[]).0.is_nan());
    }
}
