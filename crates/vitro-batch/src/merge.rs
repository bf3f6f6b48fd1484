//! Joining result directories (the shards of one experiment) into one result set.
//!
//! Every input must be of the same experiment (same experiment and scenario bytes) and no
//! run may be planned by two inputs. The merged directory plans every run of the
//! experiment, so `vitro batch --resume` on it completes whatever no shard made.

use crate::exec::failures;
use crate::journal::{self, JournalError, RunRecord};
use crate::manifest::{self, MANIFEST_FILE, Manifest, ManifestError};
use crate::table_out::{self, TableError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a merge did.
#[derive(Clone, Debug)]
pub struct MergeReport {
    /// Runs in the merged set.
    pub runs: u64,
    /// Runs of the whole experiment.
    pub total: u64,
    /// Failed runs: (run, error).
    pub failed: Vec<(u64, String)>,
    /// Inputs whose torn last journal line was left out.
    pub torn: Vec<PathBuf>,
    /// Tables written.
    pub tables: Vec<PathBuf>,
}

/// Why directories could not be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// No input directory.
    #[error("nothing to merge")]
    Nothing,
    /// An input has no manifest.
    #[error("{0} is not a result directory (no {MANIFEST_FILE})")]
    NotResults(PathBuf),
    /// Two inputs are of different experiments.
    #[error("{a} and {b} are results of different experiments ({why})")]
    Different {
        /// One input.
        a: PathBuf,
        /// Another.
        b: PathBuf,
        /// What differs.
        why: String,
    },
    /// Two inputs plan the same run.
    #[error("{a} and {b} overlap: both hold run {run}")]
    Overlap {
        /// One input.
        a: PathBuf,
        /// Another.
        b: PathBuf,
        /// The first shared run.
        run: u64,
    },
    /// The output already holds results.
    #[error("{0} already holds results; merge into a new directory")]
    Exists(PathBuf),
    /// A journal could not be read or written.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// A manifest could not be read or written.
    #[error(transparent)]
    Manifest(#[from] ManifestError),
    /// A table could not be written.
    #[error(transparent)]
    Table(#[from] TableError),
    /// The output could not be created.
    #[error("cannot create {path}: {source}")]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl MergeError {
    /// Whether the user's input is at fault.
    pub fn is_input(&self) -> bool {
        !matches!(
            self,
            MergeError::Journal(_)
                | MergeError::Manifest(ManifestError::Io { .. })
                | MergeError::Table(_)
                | MergeError::CreateDir { .. }
        )
    }
}

/// Merges the result directories `dirs` into `out` (created; must hold no results).
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<MergeReport, MergeError> {
    let mut inputs = Vec::with_capacity(dirs.len());
    for dir in dirs {
        let m = Manifest::load(dir)?.ok_or_else(|| MergeError::NotResults(dir.clone()))?;
        let reading = journal::read(dir)?;
        inputs.push((dir, m, reading));
    }
    let Some((first_dir, first, _)) = inputs.first() else {
        return Err(MergeError::Nothing);
    };
    let mut merged = first.clone();
    let mut planner: BTreeMap<u64, &Path> = BTreeMap::new();
    let mut records: Vec<RunRecord> = Vec::new();
    let mut sessions = Vec::new();
    let mut torn = Vec::new();
    for (dir, m, reading) in &inputs {
        if !first.same_experiment(m) {
            let why = if first.experiment.sha256 != m.experiment.sha256 {
                "experiment files differ"
            } else {
                "scenario files differ"
            };
            return Err(MergeError::Different {
                a: (*first_dir).clone(),
                b: (*dir).clone(),
                why: why.into(),
            });
        }
        for e in &m.runs {
            if let Some(other) = planner.insert(e.run, dir.as_path()) {
                return Err(MergeError::Overlap {
                    a: other.to_owned(),
                    b: (*dir).clone(),
                    run: e.run,
                });
            }
        }
        records.extend(reading.records.iter().cloned());
        sessions.extend(m.sessions.iter().cloned());
        if reading.torn {
            torn.push((*dir).clone());
        }
    }
    if Manifest::load(out)?.is_some() {
        return Err(MergeError::Exists(out.to_owned()));
    }
    std::fs::create_dir_all(out).map_err(|source| MergeError::CreateDir {
        path: out.to_owned(),
        source,
    })?;

    records.sort_by_key(|r| r.run);
    sessions.sort_by(|a, b| a.started.cmp(&b.started));
    let mut session = manifest::session(0);
    session.finished = Some(manifest::now());
    sessions.push(session);
    merged.shard = None;
    merged.shard_from = None;
    merged.merged_from = dirs.iter().map(|d| d.display().to_string()).collect();
    merged.sessions = sessions;
    merged.plan_runs(0..merged.runs_total);
    merged.set_statuses(&records);
    journal::write_all(out, &records)?;
    merged.save(out)?;
    let tables = table_out::write_tables(out, &merged, &records)?;
    Ok(MergeReport {
        runs: records.len() as u64,
        total: merged.runs_total,
        failed: failures(&records),
        torn,
        tables,
    })
}
