//! # vitro-mission: missions as plug-ins
//!
//! A mission is an application of the toolkit: its own agents, briefing, referee and scenario
//! tables on the shared site and tactical environment. The tools (`vitro run`, `validate`,
//! `batch`, `view`, `--record`, `export`, `search`, the Python package) know no mission by
//! name: they read a scenario file's `kind`, look the kind up in a [`Registry`], and drive
//! the [`Mission`] registered under it through one small interface.
//!
//! A mission crate implements two traits:
//!
//! - [`Mission`], the kind: validates a scenario text and builds a [`Run`] from it;
//! - [`Run`], one run of it: advances in simulated time, reports its [`Metric`]s, its trace
//!   hash and a human summary, and draws itself for recordings and the viewer
//!   ([`Scene`] once, a [`Frame`] per sample).
//!
//! What every run repeats (the simulation, the settings, the advance loop, the listener, the
//! trace hash, the snapshot framing) is written once: a mission writes its own part as a
//! [`session::Play`] and its runs are [`session::Session`]s, each a [`Run`]. Its metrics are
//! declared once, as a [`MetricTable`]; its scene starts from [`scene::site_scene`] or
//! [`Scene::flat`].
//!
//! With the `batch` feature, `batch::MissionRunner` runs any mission as the runs of a
//! `vitro-batch` experiment, so a mission crate batches its experiments from code too.
//!
//! Scenario files name their kind on the first line that matters:
//!
//! ```toml
//! kind = "evacuation"
//! ```
//!
//! [`kind_of`] reads it (with file, line and column when it is missing, not a string, or
//! unknown) so every tool reports a wrong file the same way.
//!
//! ```
//! use std::path::Path;
//! use vitro_mission::{kind_of, KindError};
//!
//! let kinds = ["demo", "evacuation"];
//! let file = Path::new("scenario.toml");
//! assert_eq!(kind_of(file, "kind = \"demo\"\nseed = 7\n", &kinds).unwrap(), "demo");
//! let e = kind_of(file, "seed = 7\n", &kinds).unwrap_err();
//! assert!(matches!(e, KindError::Missing { .. }));
//! assert_eq!(
//!     e.to_string(),
//!     "scenario.toml:1:1: the scenario names no kind (expected a top-level key `kind = \"...\"`, one of: demo, evacuation)"
//! );
//! ```

#[cfg(feature = "batch")]
pub mod batch;
mod kind;
mod metric;
mod registry;
pub mod scene;
pub mod session;
pub mod snapshot;

pub use kind::{KindError, kind_of};
pub use metric::{Metric, MetricTable, ToMetric};
pub use registry::{Registry, RegistryError};
pub use snapshot::{Snapshot, SnapshotError};

use std::path::Path;
use vitro::sim::Control;
use vitro::time::{SimDuration, SimTime};
pub use vitro_record::{Frame, Scene};

/// How a run is built: overrides of the scenario's own settings.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BuildOptions {
    /// Master seed (overrides the scenario's).
    pub seed: Option<u64>,
    /// Fidelity level for every entity (one of [`Mission::fidelity_levels`]).
    pub fidelity: Option<String>,
}

/// Why a mission could not be validated or built.
///
/// Both are fatal to the run they were asked for; [`MissionError::is_bad_input`] tells whether
/// the file is to blame (every run of it fails the same way: a batch stops) or the set-up failed
/// (the batch records the run as failed and goes on). New variants may be added.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MissionError {
    /// The scenario has problems (bad input): every line names file, line and column.
    #[error("{0}")]
    Scenario(String),
    /// The scenario is valid but the run cannot be set up (a runtime failure).
    #[error("{0}")]
    Setup(String),
}

impl MissionError {
    /// True if the scenario is to blame (exit code 2), false if a valid scenario could not be
    /// set up (exit code 1).
    ///
    /// ```
    /// use vitro_mission::MissionError;
    /// assert!(MissionError::Scenario("a.toml:3:1: expected a number".into()).is_bad_input());
    /// assert!(!MissionError::Setup("no route".into()).is_bad_input());
    /// ```
    pub fn is_bad_input(&self) -> bool {
        matches!(self, MissionError::Scenario(_))
    }
}

/// A run that broke while running (an agent failed, the state is inconsistent): a runtime
/// failure, not a verdict on the mission.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct RunFailed(pub String);

/// A kind of mission: the entry a mission crate registers.
pub trait Mission: Sync {
    /// The scenario files' `kind` for this mission (e.g. `"evacuation"`).
    fn kind(&self) -> &'static str;
    /// One line on what the mission is.
    fn about(&self) -> &'static str;
    /// The fidelity presets [`BuildOptions::fidelity`] may name (empty: none).
    fn fidelity_levels(&self) -> &'static [&'static str] {
        &[]
    }
    /// Checks a scenario text as if read from `path` (relative paths in it resolve from the
    /// file's directory); returns a one-line summary of what it describes.
    ///
    /// # Errors
    /// [`MissionError::Scenario`] with every problem found.
    fn validate(&self, path: &Path, text: &str) -> Result<String, MissionError>;
    /// Builds a run of the scenario text read from `path`.
    ///
    /// # Errors
    /// [`MissionError::Scenario`] for problems in the file or the options,
    /// [`MissionError::Setup`] when a valid scenario cannot be set up.
    fn build(
        &self,
        path: &Path,
        text: &str,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, MissionError>;
    /// The names [`Run::metrics`] returns, in the same order (batch summary columns).
    fn metric_names(&self) -> Vec<&'static str>;
    /// Where a scenario file says when the run ends: the keys from the top level down to
    /// the end time in seconds ([`standalone`](Self::standalone) lowers it). By default
    /// `end.time_s`, the shared tactical tables' `[end] time_s`.
    fn end_key(&self) -> &'static [&'static str] {
        &["end", "time_s"]
    }
    /// The paths a scenario file names, each as (table, key), relative to the file's own
    /// directory ([`standalone`](Self::standalone) rewrites them). By default the shared
    /// tactical tables' site files and calibration: `site.map`, `site.terrain`,
    /// `fidelity.calibration`.
    fn file_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("site", "map"),
            ("site", "terrain"),
            ("fidelity", "calibration"),
        ]
    }
    /// The text of a complete scenario file that, written into directory `to`, makes the same
    /// run as `scenario` (a scenario table read from a file in directory `from`) with `seed`
    /// and ending at `end_s` at the latest: the seed and end time set in it, relative paths
    /// rewritten for `to` ([`relative_path`]). `vitro search` writes its minimal failing
    /// scenarios with it. By default it does so at [`end_key`](Self::end_key) and
    /// [`file_keys`](Self::file_keys).
    ///
    /// # Errors
    /// Why the file cannot be written (e.g. a path that does not exist).
    fn standalone(
        &self,
        scenario: &toml::Table,
        seed: u64,
        end_s: Option<f64>,
        from: &Path,
        to: &Path,
    ) -> Result<String, String> {
        standalone(
            scenario,
            seed,
            end_s,
            self.end_key(),
            self.file_keys(),
            from,
            to,
        )
    }
}

/// [`Mission::standalone`]'s work: `scenario` with `seed` set, the end time at `end_key`
/// lowered to `end_s`, and the relative paths at `file_keys` rewritten from directory `from`
/// for directory `to`, as TOML text.
///
/// ```
/// let scenario: toml::Table = toml::from_str("seed = 1\n[end]\ntime_s = 900.0\n").unwrap();
/// let here = std::env::current_dir().unwrap();
/// let text = vitro_mission::standalone(&scenario, 7, Some(60.0), &["end", "time_s"], &[], &here, &here).unwrap();
/// let back: toml::Table = toml::from_str(&text).unwrap();
/// assert_eq!(back["seed"].as_integer(), Some(7));
/// assert_eq!(back["end"]["time_s"].as_float(), Some(60.0));
/// ```
///
/// # Errors
/// If the seed does not fit a TOML integer, the end key is not a table path, a path cannot be
/// resolved, or the table cannot be written.
pub fn standalone(
    scenario: &toml::Table,
    seed: u64,
    end_s: Option<f64>,
    end_key: &[&str],
    file_keys: &[(&str, &str)],
    from: &Path,
    to: &Path,
) -> Result<String, String> {
    let mut t = scenario.clone();
    set_seed(&mut t, seed)?;
    if let (Some(end), Some((last, tables))) = (end_s, end_key.split_last()) {
        let mut at = &mut t;
        for key in tables {
            let sub = at
                .entry(key.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            at = sub
                .as_table_mut()
                .ok_or_else(|| format!("`{key}` is not a table"))?;
        }
        // An end written as an integer (`time_s = 900`) is lowered too.
        let old = (at.get(*last)).and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)));
        at.insert(
            last.to_string(),
            toml::Value::Float(old.map_or(end, |o| o.min(end))),
        );
    }
    for &(table, key) in file_keys {
        let Some(toml::Value::Table(sub)) = t.get_mut(table) else {
            continue;
        };
        let Some(toml::Value::String(p)) = sub.get(key) else {
            continue;
        };
        if Path::new(p).is_absolute() {
            continue;
        }
        let moved = relative_path(&from.join(p), to)?;
        sub.insert(key.into(), toml::Value::String(moved));
    }
    toml::to_string(&t).map_err(|e| e.to_string())
}

/// `target` as a path relative to directory `dir` (both must exist), with `/` separators.
///
/// ```
/// let here = std::env::current_dir().unwrap();
/// let up = vitro_mission::relative_path(&here, &here.join("src")).unwrap();
/// assert_eq!(up, "..");
/// ```
///
/// # Errors
/// If either path cannot be resolved.
pub fn relative_path(target: &Path, dir: &Path) -> Result<String, String> {
    let abs = |p: &Path| {
        p.canonicalize()
            .map_err(|e| format!("{}: {e}", p.display()))
    };
    let (target, dir) = (abs(target)?, abs(dir)?);
    let t: Vec<_> = target.components().collect();
    let d: Vec<_> = dir.components().collect();
    let common = t.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let mut out = std::path::PathBuf::new();
    for _ in common..d.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    Ok(out.to_string_lossy().replace('\\', "/"))
}

/// Sets the top-level `seed` of a scenario table.
///
/// # Errors
/// If `seed` does not fit a TOML integer.
pub fn set_seed(scenario: &mut toml::Table, seed: u64) -> Result<(), String> {
    let seed =
        i64::try_from(seed).map_err(|_| format!("seed {seed} does not fit a TOML integer"))?;
    scenario.insert("seed".into(), toml::Value::Integer(seed));
    Ok(())
}

/// One run of a mission, driven by a tool.
///
/// A run is deterministic: the same scenario, options and calls give the same trace hash,
/// whatever the pacing or the thread it runs on.
pub trait Run {
    /// The scenario's name.
    fn name(&self) -> String;
    /// The master seed.
    fn seed(&self) -> u64;
    /// When the run ends.
    fn end(&self) -> SimTime;
    /// Ends the run earlier (or later) than the scenario says.
    fn set_end(&mut self, end: SimTime);
    /// Simulated time between samples (frames, series rows, progress).
    fn sample(&self) -> SimDuration;
    /// The simulated time reached.
    fn now(&self) -> SimTime;
    /// Runs up to `until` (events at that time included); `Ok(false)` once the run is over
    /// (its end, its own end condition, or nothing left to happen).
    ///
    /// # Errors
    /// [`RunFailed`] if the run broke (an agent failed, the state is inconsistent).
    fn advance(&mut self, until: SimTime) -> Result<bool, RunFailed>;
    /// The simulation's control handle (pacing, pause, stop).
    fn control(&self) -> Control;
    /// The trace hash so far.
    fn trace_hash(&self) -> u64;
    /// The metrics so far, named as [`Mission::metric_names`] says, in that order.
    fn metrics(&self) -> Vec<(&'static str, Metric)>;
    /// The run's own fields of `vitro run --json` (the tool adds the scenario's name, the
    /// seed, the trace hash and the wall-clock figures): by default the metrics.
    fn report(&self) -> serde_json::Map<String, serde_json::Value> {
        self.metrics()
            .into_iter()
            .map(|(k, v)| (k.to_owned(), serde_json::to_value(v).unwrap_or_default()))
            .collect()
    }
    /// The mission's verdict on the run so far: `Err` with why it failed (the tools exit
    /// with code 4), `Ok` otherwise.
    fn verdict(&self) -> Result<(), String> {
        Ok(())
    }
    /// The human summary: labelled lines, e.g. `("outcome", "SUCCESS: ...")`.
    fn summary(&self) -> Vec<(String, String)>;
    /// The static world, drawn once.
    fn scene(&self) -> Scene;
    /// The state now. Must not change the run.
    fn frame(&mut self) -> Frame;
    /// What happened since the last call, as (simulated seconds, line), for `--verbose`.
    fn drain_log(&mut self) -> Vec<(f64, String)> {
        Vec::new()
    }
    /// The run's whole state (environment, physics, agents, queue, random streams, trace,
    /// referee), for a [`Snapshot`]; the static world is left out (rebuilt from the scenario).
    /// Must not change the run. By default the mission cannot save.
    ///
    /// # Errors
    /// [`SnapshotError::Unsupported`] if the mission cannot save its runs.
    fn save_state(&self) -> Result<Vec<u8>, SnapshotError> {
        Err(SnapshotError::Unsupported(self.name()))
    }
    /// Puts the state [`save_state`](Self::save_state) made into this run, a fresh build of
    /// the same scenario with the same options: the run then goes on as the saved one would
    /// have.
    ///
    /// # Errors
    /// [`SnapshotError::Corrupt`] if the state does not decode,
    /// [`SnapshotError::Mismatch`] if the rebuilt world is not the one saved,
    /// [`SnapshotError::Unsupported`] by default.
    fn restore_state(&mut self, state: &[u8]) -> Result<(), SnapshotError> {
        let _ = state;
        Err(SnapshotError::Unsupported(self.name()))
    }
}
