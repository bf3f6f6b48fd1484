//! Any mission as a batch runner (feature `batch`): each run validates the varied scenario as
//! if it were the experiment's scenario file (paths resolve from its directory), builds the
//! run with the run's seed through the mission's plug-in and runs it, sampling the kept
//! series. So a mission crate batches its experiments with `vitro_batch::run_batch` and a
//! [`MissionRunner`], with no binary in between.

use crate::{BuildOptions, Metric, Mission, MissionError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro::time::SimTime;
use vitro_batch::{RunOutput, RunSettings, Runner, SeriesRow, Value};

/// Runs one mission's scenarios as an experiment's runs (`vitro batch`, `vitro search`, or a
/// mission crate's own experiments from code).
pub struct MissionRunner {
    /// The mission the scenario file names.
    pub mission: &'static dyn Mission,
    /// The scenario file the experiment names (relative paths in it resolve from its
    /// directory).
    pub path: PathBuf,
}

/// A metric as a batch value (a missing value is NaN, as the tables hold it).
fn value(m: Metric) -> Value {
    match m {
        Metric::Bool(b) => Value::Bool(b),
        Metric::Int(i) => Value::Int(i),
        Metric::Float(x) => Value::Float(x),
        Metric::Text(t) => Value::Text(t),
        Metric::Missing => Value::Float(f64::NAN),
    }
}

fn text(scenario: &toml::Table) -> Result<String, String> {
    toml::to_string(scenario).map_err(|e| e.to_string())
}

fn message(e: MissionError) -> String {
    e.to_string()
}

impl Runner for MissionRunner {
    fn metric_names(&self, scenario: &toml::Table) -> Result<Vec<String>, String> {
        self.mission
            .validate(&self.path, &text(scenario)?)
            .map_err(message)?;
        Ok(self
            .mission
            .metric_names()
            .into_iter()
            .map(str::to_owned)
            .collect())
    }

    fn run(
        &self,
        scenario: &toml::Table,
        seed: u64,
        settings: &RunSettings<'_>,
    ) -> Result<RunOutput, String> {
        let options = BuildOptions {
            seed: Some(seed),
            fidelity: None,
        };
        let mut run = self
            .mission
            .build(&self.path, &text(scenario)?, &options)
            .map_err(message)?;
        if let Some(end) = settings.end_s {
            run.set_end(run.end().min(SimTime::from_secs_f64(end)));
        }
        let keep = settings.keep;
        let mut series = Vec::new();
        match keep.every_s.filter(|_| !keep.series.is_empty()) {
            None => while run.advance(run.end()).map_err(|e| e.to_string())? {},
            Some(every) => {
                // Sample at every, 2*every, ... (no drift: each time from its index) and at
                // the end.
                for k in 1u64.. {
                    let t = SimTime::from_secs_f64(k as f64 * every).min(run.end());
                    let going = run.advance(t).map_err(|e| e.to_string())?;
                    let values: BTreeMap<String, Value> = run
                        .metrics()
                        .into_iter()
                        .filter(|(name, _)| keep.series.iter().any(|k| k == name))
                        .map(|(name, v)| (name.to_owned(), value(v)))
                        .collect();
                    series.push(SeriesRow {
                        t_s: run.now().as_secs_f64(),
                        values,
                    });
                    if !going || t >= run.end() {
                        break;
                    }
                }
            }
        }
        let metrics = run
            .metrics()
            .into_iter()
            .map(|(k, v)| (k.to_owned(), value(v)))
            .collect();
        Ok(RunOutput { metrics, series })
    }

    fn scenario_file(
        &self,
        scenario: &toml::Table,
        seed: u64,
        end_s: Option<f64>,
        dir: &Path,
    ) -> Result<String, String> {
        let from = self.path.parent().unwrap_or(Path::new(""));
        self.mission.standalone(scenario, seed, end_s, from, dir)
    }
}
