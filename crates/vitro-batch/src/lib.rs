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
//! ```no_run
//! use std::path::Path;
//! use vitro_batch::{BatchOptions, Experiment, Runner, run_batch};
//! # fn demo(runner: &dyn Runner) -> Result<(), Box<dyn std::error::Error>> {
//! let exp = Experiment::load(Path::new("experiments/demo_sweep.toml"), runner)?;
//! let opts = BatchOptions { out: "results".into(), jobs: 2, shard: None, resume: false };
//! let report = run_batch(&exp, runner, &opts, &|p| eprintln!("{}/{}", p.done, p.total))?;
//! println!("{} runs, {} failed", report.ran, report.failed.len());
//! # Ok(()) }
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
pub mod stats;
pub mod stop;
pub mod table;
pub mod table_out;
mod value;
mod write_file;

pub use exec::{BatchError, BatchOptions, BatchReport, Progress, run_batch};
pub use experiment::{Experiment, ExperimentError, experiment_schema};
pub use merge::{MergeError, MergeReport, merge};
pub use runner::{Keep, RunOutput, RunSettings, Runner, SeriesRow};
pub use value::Value;
