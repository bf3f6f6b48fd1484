//! `vitro._vitro`: the Rust side of the Python package. A thin layer over `vitro-tools` (the
//! same registry, run loop and report as the `vitro` command) and over the evacuation's
//! external controllers ([`env`]). Every entry point catches panics: a bug surfaces as
//! `vitro.RunError("internal error ...")`, never as a crash or a `PanicException`. Bad input
//! raises `vitro.InputError` (a `ValueError`) with the command's message.

mod env;

use pyo3::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::time::Instant;
use vitro_batch::BatchOptions;
use vitro_batch::design::Shard;
use vitro_mission::BuildOptions;
use vitro_tools::ToolError;

/// The Python exception for `e`: `vitro.errors.InputError` or `RunError`.
pub(crate) fn py_error(py: Python<'_>, e: ToolError) -> PyErr {
    let (class, message) = match e {
        ToolError::Input(m) => ("InputError", m),
        ToolError::Runtime(m) => ("RunError", m),
    };
    let made = py
        .import("vitro.errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1((message,)));
    match made {
        Ok(v) => PyErr::from_value(v),
        Err(e) => e,
    }
}

/// Runs `f`, turning a panic into a runtime error that says it is a bug.
pub(crate) fn guarded<T>(f: impl FnOnce() -> Result<T, ToolError>) -> Result<T, ToolError> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| {
        let why = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| (*s).to_owned()))
            .unwrap_or_default();
        Err(ToolError::Runtime(format!(
            "internal error (a bug in vitro, please report it): {why}"
        )))
    })
}

/// A JSON scalar as a TOML value (an override).
fn toml_value(key: &str, v: &serde_json::Value) -> Result<toml::Value, ToolError> {
    match v {
        serde_json::Value::Bool(b) => Ok(toml::Value::Boolean(*b)),
        serde_json::Value::String(s) => Ok(toml::Value::String(s.clone())),
        serde_json::Value::Number(n) => match n.as_i64() {
            Some(i) => Ok(toml::Value::Integer(i)),
            None => n.as_f64().map(toml::Value::Float).ok_or_else(|| {
                ToolError::Input(format!("override {key}: {n} is not a TOML number"))
            }),
        },
        other => Err(ToolError::Input(format!(
            "override {key}: {other} is not a number, a boolean or a string"
        ))),
    }
}

/// Parses the overrides: a JSON list of `[key, value]` pairs.
fn parse_overrides(json: Option<&str>) -> Result<Vec<(String, toml::Value)>, ToolError> {
    let Some(json) = json else {
        return Ok(Vec::new());
    };
    let pairs: Vec<(String, serde_json::Value)> =
        serde_json::from_str(json).map_err(|e| ToolError::Input(format!("overrides: {e}")))?;
    pairs
        .into_iter()
        .map(|(k, v)| Ok((k.clone(), toml_value(&k, &v)?)))
        .collect()
}

/// Runs a scenario to its end; returns the report of `vitro run --json` as JSON text.
fn run_scenario(
    path: PathBuf,
    options: BuildOptions,
    until: Option<f64>,
    overrides: Vec<(String, toml::Value)>,
) -> Result<String, ToolError> {
    let mut run = vitro_tools::build_run(&path, &options, &overrides)?;
    if let Some(until) = until {
        vitro_tools::set_until(run.as_mut(), until)?;
    }
    let started = Instant::now();
    let running = |e: vitro_mission::RunFailed| {
        ToolError::Runtime(format!("running {}: {e}", path.display()))
    };
    vitro_tools::drive(run.as_mut(), running, |_| Ok(()))?;
    let wall = started.elapsed().as_secs_f64();
    let report = vitro_tools::report(run.as_ref(), wall, None);
    serde_json::to_string(&report)
        .map_err(|e| ToolError::Runtime(format!("encoding the report: {e}")))
}

/// `vitro.run`'s Rust half: the report as JSON text.
#[pyfunction]
#[pyo3(signature = (scenario_path, seed=None, until=None, fidelity=None, overrides=None))]
fn run(
    py: Python<'_>,
    scenario_path: PathBuf,
    seed: Option<u64>,
    until: Option<f64>,
    fidelity: Option<String>,
    overrides: Option<String>,
) -> PyResult<String> {
    let options = BuildOptions { seed, fidelity };
    py.detach(move || {
        guarded(|| {
            let overrides = parse_overrides(overrides.as_deref())?;
            run_scenario(scenario_path, options, until, overrides)
        })
    })
    .map_err(|e| py_error(py, e))
}

/// Makes an experiment's runs into `out` (as `vitro batch`); returns a JSON summary.
fn run_experiment(
    experiment: PathBuf,
    out: PathBuf,
    jobs: Option<usize>,
    shard: Option<String>,
    resume: bool,
) -> Result<String, ToolError> {
    let shard = match shard {
        Some(s) => Some(
            s.parse::<Shard>()
                .map_err(|e| ToolError::Input(format!("shard {s:?}: {e}")))?,
        ),
        None => None,
    };
    let (shard, shard_from) = vitro_tools::shard_for(shard)?.unzip();
    let runner = vitro_tools::runner_for(&experiment);
    let exp = vitro_tools::load_experiment(&experiment, runner.as_ref())?;
    let jobs = jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    if jobs == 0 {
        return Err(ToolError::Input("jobs: expected at least 1".into()));
    }
    let opts = BatchOptions {
        out: out.clone(),
        jobs,
        shard,
        shard_from,
        resume,
    };
    let report = vitro_batch::run_batch(&exp, runner.as_ref(), &opts, &|_| {})
        .map_err(vitro_tools::batch_error)?;
    if let Some(e) = vitro_tools::failed_runs(&report.failed, report.planned) {
        return Err(e);
    }
    let tables: Vec<String> = report
        .tables
        .iter()
        .map(|t| t.display().to_string())
        .collect();
    let summary = serde_json::json!({
        "experiment": exp.name,
        "out": out.display().to_string(),
        "planned": report.planned,
        "ran": report.ran,
        "skipped": report.skipped,
        "wall_s": report.wall_s,
        "tables": tables,
    });
    Ok(summary.to_string())
}

/// `vitro.batch`'s Rust half: a JSON summary of what was made.
#[pyfunction]
#[pyo3(signature = (experiment_path, out, jobs=None, shard=None, resume=false))]
fn batch(
    py: Python<'_>,
    experiment_path: PathBuf,
    out: PathBuf,
    jobs: Option<usize>,
    shard: Option<String>,
    resume: bool,
) -> PyResult<String> {
    py.detach(move || guarded(|| run_experiment(experiment_path, out, jobs, shard, resume)))
        .map_err(|e| py_error(py, e))
}

/// The registered scenario kinds.
#[pyfunction]
fn kinds() -> Vec<&'static str> {
    vitro_tools::registry().kinds()
}

/// The module.
#[pymodule]
fn _vitro(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(batch, m)?)?;
    m.add_function(wrap_pyfunction!(kinds, m)?)?;
    m.add_class::<env::EvacSim>()?;
    Ok(())
}
