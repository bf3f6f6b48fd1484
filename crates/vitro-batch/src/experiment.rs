//! The experiment file: which scenario, which parameters to vary and how, how many
//! replicates, what to keep. [`Experiment::load`] reads one and checks it against its scenario.
//!
//! ```toml
//! name = "loss and fleet size"
//! scenario = "../scenarios/demo.toml"   # relative to this file
//! seed = 1                              # every run's seed derives from it
//! replicates = 5
//! end_s = 3600.0                        # overrides the scenario's end time
//!
//! [parameters]                          # full factorial, in this order
//! "channel.loss" = [0.0, 0.2, 0.4]      # explicit levels
//! "cars.count" = { start = 2, stop = 8, step = 2 }   # a range, stop included
//!
//! [latin_hypercube]                     # optional: n points over intervals
//! samples = 10
//! intervals = { "cars.speed_mps" = [5.0, 20.0] }
//!
//! [keep]
//! metrics = ["mean_idleness_s", "max_idleness_s"]   # default: all
//! series = ["mean_idleness_s"]                      # sampled over time
//! every_s = 60.0
//! ```

use crate::design::{Design, Factor, Interval, Origin};
use crate::diag::{Located, key_offset};
use crate::keys::{scenario_kind, set_path};
pub use crate::levels::{Levels, MAX_LEVELS, Number, RangeSpec};
use crate::levels::{coerce, range_levels};
use crate::runner::{Keep, Runner};
use crate::search::spec::{self, Search, SearchFile};
use crate::stop::{self, StopFile, StopRule};
use crate::value::Value;
use schemars::JsonSchema;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Most runs one experiment may plan (the manifest lists each).
pub const MAX_RUNS: u64 = 1_000_000;
/// Column names of the summary and series tables that parameters and metrics may not take.
pub const RESERVED_COLUMNS: [&str; 8] = [
    "run",
    "point",
    "replicate",
    "seed",
    "status",
    "error",
    "wall_s",
    "t_s",
];

/// A Vitro experiment: a scenario, the parameters to vary, the replicates and seeds, and
/// what to keep of each run (the [module docs](self) show a file).
#[derive(Clone, Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "Vitro experiment")]
pub struct ExperimentFile {
    /// A short name for reports and plots (default: the file's stem).
    pub name: Option<String>,
    /// Free text: what the experiment asks.
    pub description: Option<String>,
    /// The scenario file (TOML), relative to the experiment file.
    pub scenario: String,
    /// Base seed: run k's seed is derived from it and k alone.
    pub seed: u64,
    /// Runs per combination of parameter levels (at least 1).
    #[serde(default = "one")]
    #[schemars(range(min = 1))]
    pub replicates: u32,
    /// Derive seeds from the replicate number instead of the run number, so that every
    /// combination sees the same seeds (common random numbers, for paired comparisons).
    #[serde(default)]
    pub common_random_numbers: bool,
    /// Simulated time at which every run stops, in seconds (overrides the scenario's).
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub end_s: Option<f64>,
    /// Parameters to vary, by dotted scenario key (`"channel.loss"`): a list of levels or a
    /// range `{ start, stop, step }` (stop included). The runs are their full factorial, the
    /// first parameter varying slowest.
    #[serde(default)]
    pub parameters: BTreeMap<String, Levels>,
    /// A Latin-hypercube sample over intervals of other parameters, crossed with the above.
    pub latin_hypercube: Option<LatinHypercube>,
    /// Which metrics and time series to keep.
    #[serde(default)]
    pub keep: KeepFile,
    /// Conditioned replicates: stop adding replicates to a point once a metric's mean is
    /// known well enough (`replicates` is then the most per point).
    pub stop: Option<StopFile>,
    /// What `vitro search` looks for and where.
    pub search: Option<SearchFile>,
}

fn one() -> u32 {
    1
}

/// A Latin-hypercube sample: `samples` points; each interval is cut into `samples` equal
/// strata and every stratum holds exactly one point, placed at random (from the base seed).
#[derive(Clone, Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LatinHypercube {
    /// Number of points (at least 1).
    #[schemars(range(min = 1))]
    pub samples: u32,
    /// `[low, high]` of each sampled parameter, by dotted scenario key. Integer keys get
    /// rounded samples.
    #[schemars(extend("minProperties" = 1))]
    pub intervals: BTreeMap<String, [f64; 2]>,
}

/// What to keep of each run.
#[derive(Clone, Debug, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KeepFile {
    /// Metrics of the summary table (default: every metric the runner reports).
    pub metrics: Option<Vec<String>>,
    /// Metrics sampled over simulated time into the series table (default: none).
    #[serde(default)]
    pub series: Vec<String>,
    /// Sampling period of the series, in simulated seconds (needed with `series`).
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub every_s: Option<f64>,
}

/// Why an experiment could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// A file could not be read.
    #[error("cannot read {file}")]
    Read {
        /// The file.
        file: String,
        /// Why.
        source: std::io::Error,
    },
    /// The experiment or its scenario is malformed.
    #[error("{0}")]
    Invalid(Box<Located>),
    /// The runner rejected the scenario.
    #[error("invalid scenario {file}: {message}")]
    Scenario {
        /// The scenario file.
        file: String,
        /// The runner's message.
        message: String,
    },
}

/// A checked experiment: its sources, its scenario, its design and what to keep.
#[derive(Clone, Debug)]
pub struct Experiment {
    /// Name for reports.
    pub name: String,
    /// The experiment file.
    pub path: PathBuf,
    /// The experiment file's bytes (hashed into the manifest).
    pub source: String,
    /// The scenario file.
    pub scenario_path: PathBuf,
    /// The scenario file's bytes.
    pub scenario_source: String,
    /// The scenario, parsed.
    pub scenario: toml::Table,
    /// The runs to make.
    pub design: Design,
    /// End time override, in simulated seconds.
    pub end_s: Option<f64>,
    /// What to keep.
    pub keep: Keep,
    /// The stopping rule of a conditioned experiment.
    pub stop: Option<StopRule>,
    /// The search `vitro search` makes.
    pub search: Option<Search>,
}

impl Experiment {
    /// Reads the experiment at `path` and its scenario, and checks both (the scenario with
    /// `runner`, which also names the metrics that may be kept).
    pub fn load(path: &Path, runner: &dyn Runner) -> Result<Self, ExperimentError> {
        let source = read(path)?;
        let file: ExperimentFile = toml::from_str(&source).map_err(|e| {
            ExperimentError::Invalid(Box::new(Located::from_toml(
                &path.display().to_string(),
                &source,
                &e,
            )))
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        let scenario_path = base.join(&file.scenario);
        let scenario_source = read(&scenario_path)?;
        Self::check(file, path, source, scenario_path, scenario_source, runner)
    }

    fn check(
        file: ExperimentFile,
        path: &Path,
        source: String,
        scenario_path: PathBuf,
        scenario_source: String,
        runner: &dyn Runner,
    ) -> Result<Self, ExperimentError> {
        let name_of_file = path.display().to_string();
        let err = |keys: &[&str], message: String| {
            ExperimentError::Invalid(Box::new(Located::at_key(
                &name_of_file,
                &source,
                keys,
                message,
            )))
        };
        let sc_file = scenario_path.display().to_string();
        let scenario: toml::Table = toml::from_str(&scenario_source).map_err(|e| {
            ExperimentError::Invalid(Box::new(Located::from_toml(&sc_file, &scenario_source, &e)))
        })?;

        if file.replicates == 0 {
            return Err(err(&["replicates"], "expected at least 1 replicate".into()));
        }
        if let Some(end) = file.end_s
            && !(end > 0.0 && end.is_finite())
        {
            return Err(err(
                &["end_s"],
                format!("invalid end time {end}, expected a positive number of seconds"),
            ));
        }

        // Factors, in the order they are written.
        let mut named: Vec<(&String, &Levels)> = file.parameters.iter().collect();
        named.sort_by_key(|(p, _)| key_offset(&source, &["parameters", p]));
        let mut factors = Vec::with_capacity(named.len());
        for (p, levels) in named {
            let keys = ["parameters", p.as_str()];
            let kind = scenario_kind(&scenario, p).map_err(|m| err(&keys, m))?;
            let (origin, raw) = match levels {
                Levels::List(v) => (Origin::List, v.clone()),
                Levels::Range(r) => (Origin::Range, range_levels(r).map_err(|m| err(&keys, m))?),
            };
            if raw.is_empty() {
                return Err(err(&keys, format!("`{p}` needs at least one level")));
            }
            let mut levels = Vec::with_capacity(raw.len());
            for v in &raw {
                let v = coerce(v, &kind, p).map_err(|m| err(&keys, m))?;
                if levels.contains(&v) {
                    return Err(err(&keys, format!("level {v} of `{p}` appears twice")));
                }
                levels.push(v);
            }
            factors.push(Factor {
                path: p.clone(),
                origin,
                levels,
            });
        }

        let mut lhs = None;
        if let Some(l) = &file.latin_hypercube {
            if l.samples == 0 {
                return Err(err(
                    &["latin_hypercube", "samples"],
                    "expected at least 1 sample".into(),
                ));
            }
            if l.intervals.is_empty() {
                return Err(err(
                    &["latin_hypercube", "intervals"],
                    "expected at least one interval".into(),
                ));
            }
            let mut dims: Vec<(&String, &[f64; 2])> = l.intervals.iter().collect();
            dims.sort_by_key(|(p, _)| key_offset(&source, &["latin_hypercube", "intervals", p]));
            let mut checked = Vec::with_capacity(dims.len());
            for (p, &[lo, hi]) in dims {
                let keys = ["latin_hypercube", "intervals", p.as_str()];
                if file.parameters.contains_key(p) {
                    return Err(err(
                        &keys,
                        format!("`{p}` is already varied under [parameters]"),
                    ));
                }
                let kind = scenario_kind(&scenario, p).map_err(|m| err(&keys, m))?;
                let integer = match kind {
                    Value::Int(_) => true,
                    Value::Float(_) => false,
                    _ => {
                        return Err(err(
                            &keys,
                            format!(
                                "`{p}` is {} in the scenario; only numbers can be sampled",
                                kind.kind()
                            ),
                        ));
                    }
                };
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(err(
                        &keys,
                        format!(
                            "invalid interval [{lo}, {hi}], expected [low, high] with low < high"
                        ),
                    ));
                }
                checked.push(Interval {
                    path: p.clone(),
                    low: lo,
                    high: hi,
                    integer,
                });
            }
            lhs = Some((l.samples, checked));
        }

        let design = Design::new(
            factors,
            lhs,
            file.replicates,
            file.seed,
            file.common_random_numbers,
        );
        if design.runs().is_none_or(|n| n > MAX_RUNS) {
            return Err(err(
                &["parameters"],
                format!("too many runs: at most {MAX_RUNS} per experiment"),
            ));
        }

        let available =
            runner
                .metric_names(&scenario)
                .map_err(|message| ExperimentError::Scenario {
                    file: sc_file.clone(),
                    message,
                })?;
        let unknown = |list: &[String], keys: &[&str]| -> Result<(), ExperimentError> {
            match list.iter().find(|m| !available.contains(m)) {
                Some(m) => Err(err(
                    keys,
                    format!(
                        "unknown metric `{m}`, expected one of: {}",
                        available.join(", ")
                    ),
                )),
                None => Ok(()),
            }
        };
        let mut metrics = match &file.keep.metrics {
            Some(m) => {
                unknown(m, &["keep", "metrics"])?;
                m.clone()
            }
            None => available.clone(),
        };
        let stop = match &file.stop {
            Some(f) => Some(
                stop::check(f, file.replicates, &available)
                    .map_err(|(key, m)| err(&["stop", key], m))?,
            ),
            None => None,
        };
        let search = match &file.search {
            Some(f) => {
                if file.latin_hypercube.is_some() || !file.parameters.is_empty() {
                    return Err(err(
                        &["search"],
                        "a search sets its parameters under [search.parameters], not with \
                         [parameters] or [latin_hypercube]"
                            .into(),
                    ));
                }
                let order = |p: &str| key_offset(&source, &["search", "parameters", p]);
                let checked = spec::check(f, &scenario, &available, order).map_err(|(k, m)| {
                    let keys: Vec<&str> = k.iter().map(String::as_str).collect();
                    err(&keys, m)
                })?;
                Some(checked)
            }
            None => None,
        };
        // What the stopping rule, the objective and shrinking read is always kept.
        let mut needed: Vec<String> = stop.iter().map(|s| s.metric.clone()).collect();
        if let Some(s) = &search {
            needed.extend(s.objective.metrics());
            needed.extend(["trace_hash".to_owned(), "sim_time_s".to_owned()]);
        }
        for m in needed {
            if available.contains(&m) && !metrics.contains(&m) {
                metrics.push(m);
            }
        }
        unknown(&file.keep.series, &["keep", "series"])?;
        let every_s = match (file.keep.every_s, file.keep.series.is_empty()) {
            (Some(e), _) if !(e > 0.0 && e.is_finite()) => {
                return Err(err(
                    &["keep", "every_s"],
                    format!("invalid period {e}, expected a positive number of seconds"),
                ));
            }
            (None, false) => {
                return Err(err(
                    &["keep", "series"],
                    "a sampling period `every_s` is needed to keep series".into(),
                ));
            }
            (e, _) => e,
        };
        let keep = Keep {
            metrics,
            series: file.keep.series.clone(),
            every_s,
        };

        // Every column name once.
        let mut columns: Vec<&str> = RESERVED_COLUMNS.to_vec();
        for name in design
            .parameter_names()
            .iter()
            .map(String::as_str)
            .chain(keep.metrics.iter().map(String::as_str))
        {
            if columns.contains(&name) {
                return Err(err(
                    &["keep"],
                    format!("column `{name}` would appear twice in the summary table"),
                ));
            }
            columns.push(name);
        }

        let name = file.name.clone().unwrap_or_else(|| {
            path.file_stem().map_or_else(
                || "experiment".to_owned(),
                |s| s.to_string_lossy().into_owned(),
            )
        });
        Ok(Experiment {
            name,
            path: path.to_owned(),
            source,
            scenario_path,
            scenario_source,
            scenario,
            design,
            end_s: file.end_s,
            keep,
            stop,
            search,
        })
    }

    /// The scenario of one run: the base scenario with the run's parameter levels set.
    pub fn scenario_for(&self, params: &[(String, Value)]) -> toml::Table {
        let mut table = self.scenario.clone();
        for (path, v) in params {
            set_path(&mut table, path, v.to_toml());
        }
        table
    }
}

fn read(path: &Path) -> Result<String, ExperimentError> {
    std::fs::read_to_string(path).map_err(|source| ExperimentError::Read {
        file: path.display().to_string(),
        source,
    })
}

/// The JSON Schema of experiment files (pretty-printed), for editors and validators.
///
/// ```
/// let schema = vitro_batch::experiment_schema();
/// assert!(schema.contains("\"replicates\""));
/// ```
pub fn experiment_schema() -> String {
    let schema = schemars::schema_for!(ExperimentFile);
    // A schema is plain JSON: serialising it cannot fail.
    serde_json::to_string_pretty(&schema).unwrap_or_default() + "\n"
}

#[cfg(test)]
#[path = "experiment_tests.rs"]
mod tests;
