//! # vitro-tools: what the `vitro` command and the Python package share
//!
//! Both front ends know no mission by name: they look a scenario's `kind` up in
//! [`registry`], drive the run with [`drive`], and print or return [`report`]. An
//! experiment's runs go to [`runner_for`]'s runner. Errors come as a [`ToolError`] whose
//! kind decides the exit code (or the Python exception) and whose text is the same for both.
//!
//! ```no_run
//! use std::path::Path;
//! use vitro_mission::BuildOptions;
//!
//! let path = Path::new("scenarios/evacuation.toml");
//! let options = BuildOptions { seed: Some(42), fidelity: None };
//! let mut run = vitro_tools::registry()
//!     .build(path, &options)
//!     .map_err(|e| vitro_tools::scenario_error(path, e))?;
//! vitro_tools::drive(run.as_mut(), |e| vitro_tools::ToolError::Runtime(e.to_string()), |_| Ok(()))?;
//! let report = vitro_tools::report(run.as_ref(), 0.0, None);
//! println!("{}", report["trace_hash"]);
//! # Ok::<(), vitro_tools::ToolError>(())
//! ```

mod experiment;

pub use experiment::{NoMission, batch_error, failed_runs, load_experiment, runner_for, shard_for};

use std::path::Path;
use std::sync::OnceLock;
use vitro::time::{SimDuration, SimTime};
use vitro_mission::{BuildOptions, Mission, MissionError, Registry, RegistryError, Run, RunFailed};

/// The longest run `until` accepts, simulated seconds.
pub const MAX_UNTIL_S: f64 = 1.0e6;

/// How a tool's work failed; the exit code (or the Python exception) follows from the kind,
/// the text is the message.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ToolError {
    /// Bad input (unreadable or malformed file, a value out of range): exit 2.
    #[error("{0}")]
    Input(String),
    /// A failure while setting up or running: exit 1.
    #[error("{0}")]
    Runtime(String),
}

/// An error and its causes, joined by `": "` (as the command prints them), each cause said
/// once: one whose text the message already ends with (an error that shows its source in its
/// own text, `cannot read X: {source}`) is not repeated.
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut out = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let text = c.to_string();
        if !text.is_empty() && !out.ends_with(&text) {
            out.push_str(": ");
            out.push_str(&text);
        }
        cause = c.source();
    }
    out
}

/// Checks that `path` is a file that can be opened for reading; a missing, unreadable or
/// directory path is bad input, said once with the file's name.
///
/// # Errors
///
/// [`ToolError::Input`] naming `path` and why it cannot be read.
pub fn input_file(path: &Path) -> Result<(), ToolError> {
    let why = match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => "a directory, expected a file".to_owned(),
        Ok(_) => match std::fs::File::open(path) {
            Ok(_) => return Ok(()),
            Err(e) => e.to_string(),
        },
        Err(e) => e.to_string(),
    };
    Err(ToolError::Input(format!(
        "cannot read {}: {why}",
        path.display()
    )))
}

/// The registry the tools use, set on first use.
static REGISTRY: OnceLock<Registry> = OnceLock::new();

/// The missions shipped with the tools: the evacuation, the patrolling-cars demo, the
/// surveillance mission and the traffic scenario.
fn stock() -> Vec<&'static dyn Mission> {
    vec![
        &vitro_evac::Evacuation,
        &vitro_demo::PatrollingCars,
        &vitro_surveillance::Surveillance,
        &vitro_traffic::Traffic,
    ]
}

/// The registry of every mission the tools run: the stock missions, and those
/// [`install`]ed beside them.
pub fn registry() -> &'static Registry {
    REGISTRY.get_or_init(|| Registry::new(stock()))
}

/// Registers `missions` beside the stock ones for the rest of the process, so every tool
/// (`vitro run`, `validate`, `batch`, `search`, `view`, `resume`, the Python package) runs
/// their scenario files. Call it once, before the first run; `vitro_cli::run` does.
///
/// A mission's own binary installs it and hands over to the `vitro` command
/// (`vitro_cli::run` does both). A kind is registered once:
///
/// ```
/// let e = vitro_tools::install(vec![&vitro_evac::Evacuation]).unwrap_err();
/// assert_eq!(e.to_string(), r#"two missions registered as kind "evacuation""#);
/// ```
///
/// # Errors
///
/// [`ToolError::Input`] if two missions (stock or given) share a kind;
/// [`ToolError::Runtime`] if the registry is already in use (installed, or read).
pub fn install(missions: Vec<&'static dyn Mission>) -> Result<(), ToolError> {
    let mut all = stock();
    for m in missions {
        if all.iter().any(|o| o.kind() == m.kind()) {
            return Err(ToolError::Input(format!(
                "two missions registered as kind {:?}",
                m.kind()
            )));
        }
        all.push(m);
    }
    REGISTRY.set(Registry::new(all)).map_err(|_| {
        ToolError::Runtime(
            "the missions are already in use: install them once, before the first run".into(),
        )
    })
}

/// A registry error about the scenario at `path`: bad input, or a run that could not be set
/// up. The message names the file (and line and column where the mission gives them).
pub fn scenario_error(path: &Path, e: RegistryError) -> ToolError {
    match e {
        RegistryError::Mission(MissionError::Scenario(m)) => {
            ToolError::Input(format!("invalid scenario {}: {m}", path.display()))
        }
        RegistryError::Mission(MissionError::Setup(m)) => {
            ToolError::Runtime(format!("cannot set up {}: {m}", path.display()))
        }
        RegistryError::Read { source, .. } => {
            ToolError::Input(format!("cannot read scenario {}: {source}", path.display()))
        }
        e if e.is_bad_input() => ToolError::Input(e.to_string()),
        e => ToolError::Runtime(e.to_string()),
    }
}

/// Builds a run of the scenario file at `path` with `options`, each `(key, value)` of
/// `overrides` first set in the scenario as an experiment's parameter would be (dotted keys:
/// `channel.loss`, `entity.4.count`). Without overrides the file's own text is built, so
/// every message points into it.
///
/// # Errors
/// [`scenario_error`]'s, or [`ToolError::Input`] for an override the scenario cannot take.
pub fn build_run(
    path: &Path,
    options: &BuildOptions,
    overrides: &[(String, toml::Value)],
) -> Result<Box<dyn Run>, ToolError> {
    if overrides.is_empty() {
        return registry()
            .build(path, options)
            .map_err(|e| scenario_error(path, e));
    }
    let (mission, text) = registry().read(path).map_err(|e| scenario_error(path, e))?;
    let mut table: toml::Table = match text.parse() {
        Ok(t) => t,
        // Let the mission locate the syntax error in the file.
        Err(_) => {
            return mission
                .build(path, &text, options)
                .map_err(|e| scenario_error(path, e.into()));
        }
    };
    for (key, value) in overrides {
        vitro_batch::set_scenario_key(&mut table, key, value.clone())
            .map_err(|m| ToolError::Input(format!("override {key}: {m}")))?;
    }
    let text = toml::to_string(&table)
        .map_err(|e| ToolError::Input(format!("overrides of {}: {e}", path.display())))?;
    mission
        .build(path, &text, options)
        .map_err(|e| scenario_error(path, e.into()))
}

/// Ends `run` at `until` simulated seconds at the latest (the `--until` of `vitro run`).
///
/// # Errors
/// [`ToolError::Input`] unless `until` is in (0, [`MAX_UNTIL_S`]].
pub fn set_until(run: &mut dyn Run, until: f64) -> Result<(), ToolError> {
    if !(until > 0.0 && until <= MAX_UNTIL_S) {
        return Err(ToolError::Input(format!(
            "--until {until}: expected a number of simulated seconds in (0, {MAX_UNTIL_S:e}]"
        )));
    }
    run.set_end(run.end().min(SimTime::from_secs_f64(until)));
    Ok(())
}

/// Runs `run` to its end in slices of its sample period (at least a simulated second),
/// calling `each` after every slice (a recorder's frame, a progress bar). A run that breaks
/// becomes `failed(why)`.
///
/// # Errors
/// The first error of `each`, or `failed`'s.
pub fn drive<E>(
    run: &mut dyn Run,
    failed: impl Fn(RunFailed) -> E,
    mut each: impl FnMut(&mut dyn Run) -> Result<(), E>,
) -> Result<(), E> {
    let chunk = run.sample().max(SimDuration::from_secs(1));
    let mut t = SimTime::ZERO;
    loop {
        t += chunk;
        let going = run.advance(t.min(run.end())).map_err(&failed)?;
        each(run)?;
        if !going || t >= run.end() {
            return Ok(());
        }
    }
}

/// What `vitro run --json` prints (and `vitro.run` returns): the run's own fields, then the
/// scenario, the seed, the trace hash and the wall-clock figures (`wall` seconds taken,
/// the pacing `speed` if any).
pub fn report(
    run: &dyn Run,
    wall: f64,
    speed: Option<f64>,
) -> serde_json::Map<String, serde_json::Value> {
    let per_wall = |x: f64| if wall > 0.0 { x / wall } else { 0.0 };
    let events = run.control().events_fired();
    let sim_s = run.now().as_secs_f64();
    let mut out = run.report();
    out.entry("scenario").or_insert_with(|| run.name().into());
    out.insert("seed".into(), run.seed().into());
    out.insert("events".into(), events.into());
    out.entry("sim_time_s").or_insert_with(|| sim_s.into());
    out.insert(
        "trace_hash".into(),
        format!("{:016x}", run.trace_hash()).into(),
    );
    out.insert("wall_time_s".into(), wall.into());
    out.insert("events_per_wall_s".into(), per_wall(events as f64).into());
    out.insert("sim_s_per_wall_s".into(), per_wall(sim_s).into());
    out.insert("speed".into(), speed.into());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEMO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/demo.toml");

    /// An error that shows its source in its own text, as many do.
    #[derive(Debug, thiserror::Error)]
    #[error("cannot read x: {0}")]
    struct Shows(#[source] std::io::Error);

    /// An error that does not.
    #[derive(Debug, thiserror::Error)]
    #[error("cannot resume")]
    struct Wraps(#[source] Shows);

    #[test]
    fn a_chain_says_each_cause_once() {
        let io = || std::io::Error::new(std::io::ErrorKind::IsADirectory, "Is a directory");
        assert_eq!(chain(&Shows(io())), "cannot read x: Is a directory");
        assert_eq!(
            chain(&Wraps(Shows(io()))),
            "cannot resume: cannot read x: Is a directory"
        );
    }

    #[test]
    fn a_driven_run_reports_its_hash_and_the_same_hash_again() {
        let run_once = || {
            let options = BuildOptions {
                seed: Some(3),
                fidelity: None,
            };
            let mut run = registry().build(Path::new(DEMO), &options).unwrap();
            set_until(run.as_mut(), 120.0).unwrap();
            let mut slices = 0;
            drive(
                run.as_mut(),
                |e| ToolError::Runtime(e.to_string()),
                |_| {
                    slices += 1;
                    Ok(())
                },
            )
            .unwrap();
            assert!(slices > 1, "driven in slices");
            report(run.as_ref(), 0.0, None)
        };
        let (a, b) = (run_once(), run_once());
        assert_eq!(a["trace_hash"], b["trace_hash"]);
        assert_eq!(a["seed"], 3);
        assert_eq!(a["sim_time_s"], 120.0);
    }

    #[test]
    fn overrides_change_the_run_and_unknown_keys_are_named() {
        let path = Path::new(DEMO);
        let options = BuildOptions {
            seed: Some(3),
            fidelity: None,
        };
        let hash = |overrides: &[(String, toml::Value)]| {
            let mut run = build_run(path, &options, overrides).unwrap();
            set_until(run.as_mut(), 60.0).unwrap();
            drive(
                run.as_mut(),
                |e| ToolError::Runtime(e.to_string()),
                |_| Ok(()),
            )
            .unwrap();
            run.trace_hash()
        };
        let plain = hash(&[]);
        assert_ne!(
            plain,
            hash(&[("channel.loss".into(), toml::Value::Float(0.9))])
        );
        let e = build_run(path, &options, &[("channel.los".into(), 1.into())])
            .map(|_| ())
            .unwrap_err();
        assert!(
            matches!(&e, ToolError::Input(m) if m.starts_with("override channel.los: unknown scenario key")),
            "{e}"
        );
    }

    #[test]
    fn until_out_of_range_is_bad_input() {
        let mut run = registry()
            .build(Path::new(DEMO), &BuildOptions::default())
            .unwrap();
        let e = set_until(run.as_mut(), -1.0).unwrap_err();
        assert!(matches!(e, ToolError::Input(_)), "{e}");
    }

    #[test]
    fn a_missing_file_is_bad_input_naming_it() {
        let path = Path::new("no/such.toml");
        let e = registry()
            .build(path, &BuildOptions::default())
            .map(|_| ())
            .unwrap_err();
        let e = scenario_error(path, e);
        assert!(
            matches!(&e, ToolError::Input(m) if m.starts_with("cannot read scenario no/such.toml")),
            "{e}"
        );
    }
}
