//! [`Runner`]: how a batch runs one scenario. The batch knows no model: the caller (the
//! `vitro` command) implements this trait for its scenarios.

use crate::value::Value;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What to keep of each run (resolved from the experiment's `[keep]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Keep {
    /// Metrics of the summary table, in column order.
    pub metrics: Vec<String>,
    /// Metrics sampled over time, in column order (empty: no series).
    pub series: Vec<String>,
    /// Sampling period of the series, in simulated seconds.
    pub every_s: Option<f64>,
}

/// How one run is to be made, besides its scenario and seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings<'a> {
    /// Simulated end time override, in seconds.
    pub end_s: Option<f64>,
    /// What the batch keeps: a runner samples `keep.series` every `keep.every_s` simulated
    /// seconds (from `every_s` on, and once at the end), and may skip other work.
    pub keep: &'a Keep,
}

/// One sample of a run's time series.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeriesRow {
    /// Simulated time of the sample, in seconds.
    pub t_s: f64,
    /// Metric values at that time.
    pub values: BTreeMap<String, Value>,
}

/// What one run produced.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunOutput {
    /// Final metrics, by name (extra ones are dropped; missing kept ones are left empty).
    pub metrics: BTreeMap<String, Value>,
    /// Samples over time, in time order.
    pub series: Vec<SeriesRow>,
}

/// Runs scenarios for a batch. Called from several threads at once.
///
/// ```
/// use std::collections::BTreeMap;
/// use vitro_batch::{RunOutput, RunSettings, Runner, Value};
///
/// /// A "model" whose only metric is the seed's parity plus a scenario key.
/// struct Toy;
/// impl Runner for Toy {
///     fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
///         Ok(vec!["score".into()])
///     }
///     fn run(&self, s: &toml::Table, seed: u64, _: &RunSettings<'_>) -> Result<RunOutput, String> {
///         let x = s.get("x").and_then(|v| v.as_float()).ok_or("x must be a float")?;
///         let metrics = BTreeMap::from([("score".to_string(), Value::Float(x + (seed % 2) as f64))]);
///         Ok(RunOutput { metrics, series: vec![] })
///     }
/// }
/// ```
pub trait Runner: Sync {
    /// Checks the base scenario and names the metrics its runs report, in a sensible column
    /// order; an error is a message for the user (the scenario is bad input).
    fn metric_names(&self, scenario: &toml::Table) -> Result<Vec<String>, String>;

    /// Runs `scenario` with master seed `seed`. An error (e.g. a parameter value the
    /// scenario rejects) fails this run only; so does a panic.
    fn run(
        &self,
        scenario: &toml::Table,
        seed: u64,
        settings: &RunSettings<'_>,
    ) -> Result<RunOutput, String>;

    /// The text of a complete scenario file that, written into directory `dir`, makes the
    /// same run as `run(scenario, seed, end_s)` when run on its own (`vitro run FILE`): the
    /// seed and end time set in it, relative paths rewritten for `dir`. `vitro search`
    /// writes its minimal failing scenarios with it. The default cannot.
    fn scenario_file(
        &self,
        scenario: &toml::Table,
        seed: u64,
        end_s: Option<f64>,
        dir: &std::path::Path,
    ) -> Result<String, String> {
        let _ = (scenario, seed, end_s, dir);
        Err("this kind of scenario cannot be written as a standalone file".into())
    }
}
