//! Searching a scenario's parameters for failures (`vitro search`): where an algorithm
//! breaks, rather than how it does on average.
//!
//! An experiment's `[search]` table ([`spec`]) names the objective (what counts as a failing
//! run, or a metric to maximise or minimise), the parameters searched with their ranges and
//! a budget of evaluations. [`run_search`] spends the budget generation by generation: the
//! `adaptive` strategy is the cross-entropy method ([`cem`]), which draws each generation
//! from a law fitted to the best evaluations so far; `random` draws uniformly, the baseline.
//! Each distinct failure is then shrunk ([`shrink`]) to a smaller run that still fails, and
//! written as a complete scenario file with its expected trace hash.
//!
//! Why the cross-entropy method and not a crate: the space mixes floats, integers, choices
//! and seeds, the objective is noisy and often binary (a run fails or not), and evaluations
//! come in parallel batches of a generation. CEM handles all of that in a page of code
//! whose every draw is reproducible (our SplitMix streams, libm). argmin's solvers are for
//! continuous objectives over `f64` vectors, with no integer or categorical variables.
//! egobox's EGO does handle mixed-integer variables (by continuous relaxation), but it fits
//! a mixture of Gaussian processes to the responses, a surrogate made for smooth, expensive
//! functions, not for a pass/fail outcome of a seed-driven world, and brings ndarray and
//! linfa into a crate that needs neither.
//!
//! A search directory holds what a batch directory does (`runs.jsonl`, `manifest.json` with
//! the search's settings and findings, `summary.csv`/`.parquet`) plus `found.csv` (one row
//! per failing run) and `minimal/` (the shrunk scenarios). Run `k` of a search is the same
//! run whatever the job count: generation `g`'s points depend only on the search seed and the
//! results of generations before `g`. A killed search resumes from its journal: finished
//! generations are replayed from their records, the missing runs made.

pub mod cem;
mod error;
mod found;
mod run;
pub mod shrink;
pub mod spec;

pub use cem::Strategy;
pub use error::SearchError;
pub use run::{SearchEvent, SearchOptions, SearchReport, run_search};
