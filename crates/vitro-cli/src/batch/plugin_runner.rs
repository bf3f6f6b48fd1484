//! The batch runner of every mission: each run validates the varied scenario as if it were
//! the experiment's scenario file (paths resolve from its directory), builds the run with the
//! run's seed through the mission's plug-in and runs it, sampling the kept series.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro::time::SimTime;
use vitro_batch::{RunOutput, RunSettings, Runner, SeriesRow, Value};
use vitro_mission::{BuildOptions, Metric, Mission, MissionError};

/// Runs one mission's scenarios for `vitro batch` and `vitro search`.
pub(crate) struct PluginRunner {
    /// The mission the scenario file names.
    pub(crate) mission: &'static dyn Mission,
    /// The scenario file the experiment names (relative paths in it resolve from its
    /// directory).
    pub(crate) path: PathBuf,
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

impl Runner for PluginRunner {
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

/// The runner of an experiment whose scenario names no registered mission: every call
/// answers why.
pub(crate) struct NoMission(pub(crate) String);

impl Runner for NoMission {
    fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
        Err(self.0.clone())
    }

    fn run(&self, _: &toml::Table, _: u64, _: &RunSettings<'_>) -> Result<RunOutput, String> {
        Err(self.0.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vitro_batch::Keep;

    const DEMO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/demo.toml");

    fn runner() -> PluginRunner {
        PluginRunner {
            mission: &vitro_demo::PatrollingCars,
            path: PathBuf::from(DEMO),
        }
    }

    fn scenario() -> toml::Table {
        let src = include_str!("../../../../scenarios/demo.toml");
        toml::from_str(src).expect("the demo scenario parses")
    }

    #[test]
    fn runs_the_demo_and_samples_series() {
        let keep = Keep {
            metrics: vec![],
            series: vec!["visits".into(), "mean_idleness_s".into()],
            every_s: Some(250.0),
        };
        let settings = RunSettings {
            end_s: Some(600.0),
            keep: &keep,
        };
        let out = runner().run(&scenario(), 5, &settings).unwrap();
        let times: Vec<f64> = out.series.iter().map(|r| r.t_s).collect();
        assert_eq!(times, [250.0, 500.0, 600.0]);
        assert_eq!(out.series[0].values.len(), 2);
        assert_eq!(
            out.series[2].values["visits"], out.metrics["visits"],
            "the last sample is the end"
        );
        // Sampling does not change the run.
        let plain = RunSettings {
            end_s: Some(600.0),
            keep: &Keep::default(),
        };
        let again = runner().run(&scenario(), 5, &plain).unwrap();
        assert_eq!(again.metrics, out.metrics);
        assert!(again.series.is_empty());
    }

    #[test]
    fn bad_values_fail_the_run() {
        let mut s = scenario();
        s["channel"]
            .as_table_mut()
            .expect("a channel table")
            .insert("loss".into(), toml::Value::Float(1.5));
        let keep = Keep::default();
        let settings = RunSettings {
            end_s: None,
            keep: &keep,
        };
        let err = runner().run(&s, 1, &settings).unwrap_err();
        assert!(err.contains("channel.loss"), "{err}");
        assert!(runner().metric_names(&s).is_err());
        assert_eq!(
            runner().metric_names(&scenario()).unwrap()[0],
            "mean_idleness_s"
        );
    }
}
