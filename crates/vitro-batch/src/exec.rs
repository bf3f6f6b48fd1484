//! Running a batch: the runs of a shard on a pool of threads, each recorded in the journal
//! as it ends, then the manifest and the tables rebuilt from the journal.

use crate::design::{RunSpec, Shard};
use crate::experiment::Experiment;
use crate::journal::{self, Journal, JournalError, RunRecord, Status};
use crate::make::{self, execute_all};
use crate::manifest::{self, MANIFEST_FILE, Manifest, ManifestError};
use crate::runner::Runner;
use crate::stop;
use crate::table_out::{self, TableError};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// How to run a batch.
#[derive(Clone, Debug)]
pub struct BatchOptions {
    /// The result directory (created if needed).
    pub out: PathBuf,
    /// Worker threads (at least 1).
    pub jobs: usize,
    /// The share of runs to make (`None`: all).
    pub shard: Option<Shard>,
    /// Where the shard came from, for the manifest (e.g. `"--shard"`, or the line
    /// [`shard_from_env`](crate::shard_env::shard_from_env) gives).
    pub shard_from: Option<String>,
    /// Complete the runs missing from `out` instead of refusing a directory with results.
    pub resume: bool,
}

/// A finished run, as reported to the progress callback.
#[derive(Clone, Copy, Debug)]
pub struct Progress<'a> {
    /// Runs of the share done so far (including those of earlier sessions).
    pub done: u64,
    /// Runs in the share.
    pub total: u64,
    /// Runs found done at the start (by earlier sessions).
    pub before: u64,
    /// The run that just finished.
    pub record: &'a RunRecord,
}

/// What a batch did.
#[derive(Clone, Debug)]
pub struct BatchReport {
    /// Runs in the share.
    pub planned: u64,
    /// Runs found done already (resume).
    pub skipped: u64,
    /// Runs made now.
    pub ran: u64,
    /// Whether a torn last journal line (a run killed while being recorded) was dropped.
    pub torn_dropped: bool,
    /// Failed runs of the directory: (run, error).
    pub failed: Vec<(u64, String)>,
    /// Wall-clock seconds of this session.
    pub wall_s: f64,
    /// Tables written.
    pub tables: Vec<PathBuf>,
    /// Where each point of a conditioned experiment stopped.
    pub stop: Option<stop::StopReport>,
}

/// Why a batch could not run (failed runs are not errors: see [`BatchReport::failed`]).
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// The journal could not be read or written.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// The manifest could not be read or written.
    #[error(transparent)]
    Manifest(#[from] ManifestError),
    /// A table could not be written.
    #[error(transparent)]
    Table(#[from] TableError),
    /// The directory could not be created.
    #[error("cannot create {path}: {source}")]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The directory holds results and `resume` was not asked for.
    #[error(
        "{0} already holds results; pass --resume to complete them, or choose another directory"
    )]
    Exists(PathBuf),
    /// The directory holds results of another experiment (or other shard).
    #[error("cannot resume {dir}: {why}")]
    Mismatch {
        /// The directory.
        dir: PathBuf,
        /// What differs.
        why: String,
    },
    /// A conditioned experiment (`[stop]`) was asked for in shards.
    #[error(
        "a conditioned experiment ([stop]) cannot be sharded: whether a point needs another \
         replicate depends on its earlier ones"
    )]
    Conditioned,
    /// The worker pool could not start.
    #[error("cannot start {jobs} worker threads: {message}")]
    Pool {
        /// Threads asked for.
        jobs: usize,
        /// Why.
        message: String,
    },
}

impl BatchError {
    /// Whether the user's input is at fault (a directory that holds other results, or is
    /// in use), rather than the system.
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            BatchError::Exists(_)
                | BatchError::Mismatch { .. }
                | BatchError::Conditioned
                | BatchError::Journal(JournalError::Busy { .. })
        )
    }
}

/// Runs the experiment's runs of `opts.shard` missing from `opts.out`, in parallel, calling
/// `progress` after each; then writes the manifest and the tables.
pub fn run_batch(
    exp: &Experiment,
    runner: &dyn Runner,
    opts: &BatchOptions,
    progress: &(dyn Fn(Progress<'_>) + Sync),
) -> Result<BatchReport, BatchError> {
    let started = Instant::now();
    let dir = opts.out.as_path();
    if exp.stop.is_some() && opts.shard.is_some_and(|s| s.count > 1) {
        return Err(BatchError::Conditioned);
    }
    let mut manifest = Manifest::new(exp, opts.shard.filter(|s| s.count > 1));
    if manifest.shard.is_some() {
        manifest.shard_from = opts.shard_from.clone();
    }
    let (journal, reading) = open_dir(dir, &mut manifest, opts.resume)?;
    let mut done = BTreeSet::new();
    for rec in &reading.records {
        let planned = manifest.runs.binary_search_by_key(&rec.run, |e| e.run);
        match planned {
            Ok(i) if manifest.runs[i].seed == rec.seed => {
                done.insert(rec.run);
            }
            _ => {
                return Err(BatchError::Mismatch {
                    dir: dir.to_owned(),
                    why: format!(
                        "its run {} is not a run of this experiment's share",
                        rec.run
                    ),
                });
            }
        }
    }
    let pending: Vec<u64> = manifest
        .runs
        .iter()
        .map(|e| e.run)
        .filter(|k| !done.contains(k))
        .collect();
    let planned = manifest.runs.len() as u64;
    let skipped = done.len() as u64;

    let jobs = opts.jobs.max(1);
    manifest.sessions.push(manifest::session(jobs));
    manifest.set_statuses(&reading.records);
    manifest.save(dir)?;

    let pool = pool(jobs)?;
    let journal = Mutex::new(journal);
    let mut records = reading.records;
    let counter = AtomicU64::new(skipped);
    let report = |rec: &RunRecord| {
        let done = counter.fetch_add(1, Ordering::Relaxed) + 1;
        progress(Progress {
            done,
            total: planned,
            before: skipped,
            record: rec,
        });
    };
    let before = records.len();
    match &exp.stop {
        None => {
            let specs: Vec<RunSpec> = pending.iter().filter_map(|&k| exp.design.run(k)).collect();
            let made = execute_all(&pool, exp, runner, &specs, &journal, &report)?;
            records.extend(made);
        }
        Some(rule) => {
            let stop = make::run_rounds(&pool, exp, runner, rule, &journal, &mut records, &report)?;
            manifest.stop = Some(stop);
        }
    }
    let ran = (records.len() - before) as u64;
    drop(journal);

    records.sort_by_key(|r| r.run);
    manifest.set_statuses(&records);
    if let Some(s) = manifest.sessions.last_mut() {
        s.finished = Some(manifest::now());
        s.runs_done = ran;
    }
    manifest.save(dir)?;
    let tables = table_out::write_tables(dir, &manifest, &records)?;
    Ok(BatchReport {
        planned,
        skipped,
        ran,
        torn_dropped: reading.torn,
        failed: failures(&records),
        wall_s: started.elapsed().as_secs_f64(),
        tables,
        stop: manifest.stop.clone(),
    })
}

/// Opens result directory `dir` for a session that writes `manifest`: creates it, refuses
/// one with results unless `resume` (and then one of another experiment), carries the old
/// sessions over, and opens the journal.
pub(crate) fn open_dir(
    dir: &Path,
    manifest: &mut Manifest,
    resume: bool,
) -> Result<(Journal, journal::Reading), BatchError> {
    std::fs::create_dir_all(dir).map_err(|source| BatchError::CreateDir {
        path: dir.to_owned(),
        source,
    })?;
    match Manifest::load(dir)? {
        Some(_) if !resume => return Err(BatchError::Exists(dir.to_owned())),
        Some(old) => {
            check_resumable(dir, &old, manifest)?;
            manifest.sessions = old.sessions;
        }
        None if journal::read(dir)?.records.is_empty() => {}
        None => {
            return Err(BatchError::Mismatch {
                dir: dir.to_owned(),
                why: format!("it holds run records but no {MANIFEST_FILE}"),
            });
        }
    }
    Ok(Journal::open(dir)?)
}

/// A pool of `jobs` worker threads.
pub(crate) fn pool(jobs: usize) -> Result<rayon::ThreadPool, BatchError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| BatchError::Pool {
            jobs,
            message: e.to_string(),
        })
}

/// Whether a directory's old manifest is of the same experiment and share.
pub(crate) fn check_resumable(
    dir: &Path,
    old: &Manifest,
    new: &Manifest,
) -> Result<(), BatchError> {
    let why = if old.experiment.sha256 != new.experiment.sha256 {
        Some(format!(
            "it holds results of another experiment file ({}, sha256 {}...)",
            old.experiment.path,
            &old.experiment.sha256[..12.min(old.experiment.sha256.len())]
        ))
    } else if old.scenario.sha256 != new.scenario.sha256 {
        Some(format!(
            "the scenario {} changed since these results were made",
            old.scenario.path
        ))
    } else if old.search.as_ref().map(|s| s.key()) != new.search.as_ref().map(|s| s.key()) {
        let show = |m: &Manifest| {
            m.search
                .as_ref()
                .map_or_else(|| "a batch".to_owned(), |s| s.describe())
        };
        Some(format!("it holds {}, not {}", show(old), show(new)))
    } else if old.shard != new.shard {
        let show = |s: Option<Shard>| s.map_or_else(|| "all runs".to_owned(), |s| s.to_string());
        Some(format!(
            "it holds shard {}, not {}",
            show(old.shard),
            show(new.shard)
        ))
    } else {
        None
    };
    match why {
        Some(why) => Err(BatchError::Mismatch {
            dir: dir.to_owned(),
            why,
        }),
        None => Ok(()),
    }
}

/// The failed runs among `records`.
pub fn failures(records: &[RunRecord]) -> Vec<(u64, String)> {
    records
        .iter()
        .filter(|r| r.status == Status::Failed)
        .map(|r| (r.run, r.error.clone().unwrap_or_default()))
        .collect()
}
