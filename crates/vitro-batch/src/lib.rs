//! # Vitro experiment suites
//!
//! Parameter sweeps over a scenario, run in parallel, recorded so that nothing done is lost,
//! and analysed: what Mesa's `batch_run`, Agents.jl's `paramscan` and NetLogo's
//! BehaviorSpace do, for Vitro scenarios.
//!
//! - An **experiment file** ([`experiment`]) names a scenario (TOML), the parameters to vary by
//!   their dotted scenario keys (explicit levels, ranges, a Latin-hypercube sample), the
//!   replicates, the base seed, an end time and what to keep. It is checked against the
//!   scenario: an unknown key or a level of the wrong type is an error with its place.
//! - The **design** ([`design`]) is the full factorial times the replicates in a fixed order;
//!   run `k`'s seed depends on the base seed and `k` only, so a run is the same whoever makes
//!   it, with any number of threads, in any shard.
//! - A **batch** ([`exec::run_batch`]) makes the runs of a shard on a thread pool through a
//!   [`Runner`] (the model is the caller's: this crate knows none). Each finished run is one
//!   line of `runs.jsonl`, synced to disk; a panic or an error fails that run only; a killed
//!   batch resumes where it stopped.
//! - **Results**: `manifest.json` (versions, hashes, seeds, statuses), the tidy tables
//!   `summary` and `series` in CSV (and Parquet with the `parquet` feature), [`merge()`] of
//!   shards, and plots (`plot` feature).
//!
//! ## A batch in five steps
//!
//! The model is the caller's: a [`Runner`] makes one run of a scenario (a TOML table) with a
//! seed and names its metrics. The experiment file says what to vary; [`run_batch`] makes
//! the runs in parallel and writes the tables; `plot::plot_dir` (feature `plot`) draws them.
//!
//! ```
//! use std::collections::BTreeMap;
//! use vitro_batch::{BatchOptions, Experiment, RunOutput, RunSettings, Runner, Value, run_batch};
//!
//! // 1. The model: the time a courier needs for `distance_m` at `speed_mps`, with a delay
//! //    drawn from the seed.
//! struct Courier;
//! impl Runner for Courier {
//!     fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
//!         Ok(vec!["time_s".into()])
//!     }
//!     fn run(&self, s: &toml::Table, seed: u64, _: &RunSettings<'_>) -> Result<RunOutput, String> {
//!         let get = |k: &str| s.get(k).and_then(|v| v.as_float()).ok_or(format!("{k}: a float"));
//!         let t = get("distance_m")? / get("speed_mps")? + (seed % 60) as f64;
//!         Ok(RunOutput { metrics: BTreeMap::from([("time_s".into(), Value::Float(t))]), series: vec![] })
//!     }
//! }
//!
//! // 2. A scenario and 3. an experiment: two speeds, five replicates each.
//! let dir = std::env::temp_dir().join(format!("vitro-batch-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! std::fs::write(dir.join("courier.toml"), "distance_m = 1200.0\nspeed_mps = 1.5\n")?;
//! std::fs::write(dir.join("speeds.toml"), r#"
//! scenario = "courier.toml"
//! seed = 1
//! replicates = 5
//! [parameters]
//! speed_mps = [1.5, 3.0]
//! "#)?;
//! let exp = Experiment::load(&dir.join("speeds.toml"), &Courier)?;
//! assert_eq!(exp.design.runs(), Some(10));
//!
//! // 4. The batch: resumable, the same results with any number of jobs.
//! let opts = BatchOptions { out: dir.join("results"), jobs: 2, shard: None, shard_from: None, resume: false };
//! let report = run_batch(&exp, &Courier, &opts, &|p| eprintln!("{}/{}", p.done, p.total))?;
//! assert_eq!((report.ran, report.failed.len()), (10, 0));
//!
//! // 5. The tidy table: one row per run (run, point, replicate, seed, parameters, metrics).
//! let summary = std::fs::read_to_string(dir.join("results/summary.csv"))?;
//! assert_eq!(summary.lines().count(), 11);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod design;
pub mod diag;
pub mod exec;
pub mod experiment;
pub mod journal;
mod keys;
mod levels;
mod make;
pub mod manifest;
pub mod merge;
#[cfg(feature = "parquet")]
mod parquet_out;
#[cfg(feature = "plot")]
pub mod plot;
pub mod runner;
pub mod search;
pub mod shard_env;
pub mod stats;
pub mod stop;
pub mod table;
pub mod table_out;
mod value;
mod write_file;

pub use exec::{BatchError, BatchOptions, BatchReport, Progress, run_batch};
pub use experiment::{Experiment, ExperimentError, experiment_schema};
pub use keys::set_scenario_key;
pub use merge::{MergeError, MergeReport, merge};
pub use runner::{Keep, RunOutput, RunSettings, Runner, SeriesRow};
pub use value::Value;
