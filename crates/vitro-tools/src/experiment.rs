//! The runner of an experiment's runs: the mission its scenario's `kind` names
//! (`vitro_mission::batch::MissionRunner`), or [`NoMission`] saying why there is none.

use crate::{ToolError, registry};
use std::path::Path;
use vitro_batch::design::Shard;
use vitro_batch::shard_env::shard_from_env;
use vitro_batch::{BatchError, Experiment, ExperimentError, RunOutput, RunSettings, Runner};
use vitro_mission::batch::MissionRunner;

/// The runner of an experiment whose scenario names no registered mission: every call
/// answers why.
pub struct NoMission(pub String);

impl Runner for NoMission {
    fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
        Err(self.0.clone())
    }

    fn run(&self, _: &toml::Table, _: u64, _: &RunSettings<'_>) -> Result<RunOutput, String> {
        Err(self.0.clone())
    }
}

/// The runner for the scenario `experiment` names: its mission's, looked up by the
/// scenario's `kind`. When there is none (no scenario, an unreadable one, no or an unknown
/// kind) the runner says why, and loading the experiment reports it at its place.
pub fn runner_for(experiment: &Path) -> Box<dyn Runner> {
    let scenario = std::fs::read_to_string(experiment)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| t.get("scenario")?.as_str().map(str::to_owned));
    let dir = experiment.parent().unwrap_or(Path::new(""));
    let Some(path) = scenario.map(|s| dir.join(s)) else {
        return Box::new(NoMission("the experiment names no scenario file".into()));
    };
    match registry().read(&path) {
        Ok((mission, _)) => Box::new(MissionRunner { mission, path }),
        Err(e) => Box::new(NoMission(e.to_string())),
    }
}

/// Loads the experiment at `path` for `runner`; any problem is bad input, each located in
/// the file.
///
/// # Errors
/// [`ToolError::Input`]: `invalid experiment: FILE:LINE:COLUMN: ...` and the like.
pub fn load_experiment(path: &Path, runner: &dyn Runner) -> Result<Experiment, ToolError> {
    Experiment::load(path, runner).map_err(|e| match e {
        ExperimentError::Invalid(l) => {
            ToolError::Input(format!("invalid experiment: {}", crate::chain(&*l)))
        }
        e => ToolError::Input(crate::chain(&e)),
    })
}

/// The shard a batch makes: `explicit` (the `--shard` argument) if given, else the task's
/// of a Slurm job array or a Kubernetes Indexed Job (from the environment), else none; with
/// where it came from, for the manifest.
///
/// # Errors
/// [`ToolError::Input`] if the environment names a shard badly.
pub fn shard_for(explicit: Option<Shard>) -> Result<Option<(Shard, String)>, ToolError> {
    match explicit {
        Some(s) => Ok(Some((s, "--shard".to_string()))),
        None => shard_from_env(|k| std::env::var(k).ok())
            .map_err(|e| ToolError::Input(format!("no shard for this task: {e}"))),
    }
}

/// A batch that could not run: bad input (the experiment, the result directory) or a
/// runtime failure.
pub fn batch_error(e: BatchError) -> ToolError {
    if e.is_input() {
        ToolError::Input(crate::chain(&e))
    } else {
        ToolError::Runtime(crate::chain(&e))
    }
}

/// The error of a batch some of whose `total` runs failed (none if none did): names them.
pub fn failed_runs(failed: &[(u64, String)], total: u64) -> Option<ToolError> {
    if failed.is_empty() {
        return None;
    }
    let ids: Vec<String> = failed.iter().map(|(r, _)| r.to_string()).collect();
    Some(ToolError::Runtime(format!(
        "{} of {total} runs failed: {}",
        failed.len(),
        ids.join(", ")
    )))
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;
    use vitro_batch::{Keep, RunSettings, Runner};
    use vitro_mission::batch::MissionRunner;

    const DEMO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/demo.toml");

    fn runner() -> MissionRunner {
        MissionRunner {
            mission: &vitro_demo::PatrollingCars,
            path: PathBuf::from(DEMO),
        }
    }

    fn scenario() -> toml::Table {
        let src = include_str!("../../../scenarios/demo.toml");
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
