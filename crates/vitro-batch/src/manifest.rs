//! `manifest.json`: what a result directory holds and how it was made: the Vitro version and
//! git hash, hashes of the experiment and scenario files, the design, every run's seed and
//! status, and each session (start or resume) with its times.

use crate::design::{Origin, Shard, seed_of};
use crate::experiment::Experiment;
use crate::journal::{RunRecord, Status};
use crate::runner::Keep;
use crate::stop::StopReport;
use crate::value::Value;
pub use crate::write_file::write_atomic;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// Name of the manifest file in a result directory.
pub const MANIFEST_FILE: &str = "manifest.json";
/// Version of the manifest layout.
pub const FORMAT: u32 = 1;
/// The git commit this crate was built from (`git rev-parse HEAD` at build time), or
/// `unknown`.
pub const GIT_HASH: &str = env!("VITRO_GIT_HASH");
/// The Vitro version.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// A source file: where it was and the SHA-256 of its bytes.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileInfo {
    /// Path as given.
    pub path: String,
    /// SHA-256 of the bytes, hex.
    pub sha256: String,
}

/// A varied parameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamInfo {
    /// Dotted scenario key: the column name.
    pub path: String,
    /// Where the levels came from.
    pub origin: Origin,
    /// Levels (for a hypercube: the sampled values, point by point).
    pub levels: Vec<Value>,
}

/// One invocation that wrote into the directory.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Session {
    /// Start, RFC 3339 UTC.
    pub started: String,
    /// End, RFC 3339 UTC (absent if it was killed).
    pub finished: Option<String>,
    /// Vitro version.
    pub vitro_version: String,
    /// Git commit of the build.
    pub git_hash: String,
    /// Worker threads (0 for a merge).
    pub jobs: usize,
    /// Runs it completed.
    pub runs_done: u64,
}

/// A run's seed and status.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunEntry {
    /// Run number.
    pub run: u64,
    /// Seed.
    pub seed: u64,
    /// `ok`, `failed` or `pending` (not run yet).
    pub status: String,
}

/// The manifest of a result directory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Layout version ([`FORMAT`]).
    pub format: u32,
    /// Experiment name.
    pub name: String,
    /// The experiment file.
    pub experiment: FileInfo,
    /// The scenario file.
    pub scenario: FileInfo,
    /// Base seed.
    pub base_seed: u64,
    /// Runs per point.
    pub replicates: u32,
    /// Seeds per replicate rather than per run.
    pub common_random_numbers: bool,
    /// End time override.
    pub end_s: Option<f64>,
    /// Varied parameters, in column order.
    pub parameters: Vec<ParamInfo>,
    /// Kept metrics and series.
    pub keep: Keep,
    /// Runs in the whole experiment.
    pub runs_total: u64,
    /// The share of runs this directory is for (`None`: all of them).
    pub shard: Option<Shard>,
    /// Where the shard came from: `--shard`, or a cluster's job array (see
    /// [`shard_env`](crate::shard_env)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard_from: Option<String>,
    /// Directories merged into this one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<String>,
    /// Sessions that wrote here, oldest first.
    pub sessions: Vec<Session>,
    /// A conditioned experiment's stopping rule and where each point stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<StopReport>,
    /// A search's settings and findings (`vitro search`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchInfo>,
    /// Every run of the directory's share: seed and status.
    pub runs: Vec<RunEntry>,
}

/// Why a manifest could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ManifestError {
    /// An I/O error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not a manifest of this format.
    #[error("{path}: not a Vitro result manifest: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl Manifest {
    /// A new manifest for `exp` (shard `shard`), with no session and every run pending.
    pub fn new(exp: &Experiment, shard: Option<Shard>) -> Self {
        let d = &exp.design;
        let mut parameters: Vec<ParamInfo> = d
            .factors
            .iter()
            .map(|f| ParamInfo {
                path: f.path.clone(),
                origin: f.origin,
                levels: f.levels.clone(),
            })
            .collect();
        if let Some(h) = &d.hypercube {
            for (i, p) in h.paths.iter().enumerate() {
                parameters.push(ParamInfo {
                    path: p.clone(),
                    origin: Origin::LatinHypercube,
                    levels: h.points.iter().map(|row| row[i].clone()).collect(),
                });
            }
        }
        let total = d.runs().unwrap_or(0);
        let share = shard.unwrap_or(Shard::ALL);
        let mut m = Manifest {
            format: FORMAT,
            name: exp.name.clone(),
            experiment: file_info(&exp.path, exp.source.as_bytes()),
            scenario: file_info(&exp.scenario_path, exp.scenario_source.as_bytes()),
            base_seed: d.base_seed,
            replicates: d.replicates,
            common_random_numbers: d.common_random_numbers,
            end_s: exp.end_s,
            parameters,
            keep: exp.keep.clone(),
            runs_total: total,
            shard,
            shard_from: None,
            merged_from: Vec::new(),
            sessions: Vec::new(),
            stop: None,
            search: None,
            runs: Vec::new(),
        };
        m.plan_runs((0..total).filter(|&k| share.contains(k)));
        m
    }

    /// Sets the runs of the directory's share: each with its seed, pending.
    pub fn plan_runs(&mut self, runs: impl Iterator<Item = u64>) {
        let reps = u64::from(self.replicates.max(1));
        let (base, crn) = (self.base_seed, self.common_random_numbers);
        self.runs = runs
            .map(|k| RunEntry {
                run: k,
                seed: seed_of(base, if crn { k % reps } else { k }),
                status: "pending".into(),
            })
            .collect();
    }

    /// Whether `other` is of the same experiment: same experiment and scenario bytes.
    pub fn same_experiment(&self, other: &Manifest) -> bool {
        self.experiment.sha256 == other.experiment.sha256
            && self.scenario.sha256 == other.scenario.sha256
    }

    /// Sets every run's status from the records (others stay `pending`).
    pub fn set_statuses(&mut self, records: &[RunRecord]) {
        for entry in &mut self.runs {
            entry.status = "pending".into();
        }
        for rec in records {
            if let Ok(i) = self.runs.binary_search_by_key(&rec.run, |e| e.run) {
                self.runs[i].status = rec.status.as_str().into();
            }
        }
        // A conditioned experiment's points stop early: their later replicates are not run.
        if let Some(stop) = &self.stop {
            let reps = u64::from(self.replicates.max(1));
            for entry in &mut self.runs {
                let (p, r) = (entry.run / reps, entry.run % reps);
                let stopped = stop
                    .points
                    .get(p as usize)
                    .is_some_and(|s| s.point == p && r >= u64::from(s.replicates));
                if stopped && entry.status == "pending" {
                    entry.status = NOT_NEEDED.into();
                }
            }
        }
    }

    /// Counts of (ok, failed, pending) runs.
    pub fn counts(&self) -> (u64, u64, u64) {
        let count = |s: &str| self.runs.iter().filter(|e| e.status == s).count() as u64;
        (
            count(Status::Ok.as_str()),
            count(Status::Failed.as_str()),
            count("pending"),
        )
    }

    /// Reads `dir`'s manifest, if there is one.
    pub fn load(dir: &Path) -> Result<Option<Manifest>, ManifestError> {
        let path = dir.join(MANIFEST_FILE);
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(ManifestError::Io { path, source }),
        };
        let m: Manifest = serde_json::from_slice(&bytes).map_err(|e| ManifestError::Format {
            path: path.clone(),
            message: e.to_string(),
        })?;
        if m.format != FORMAT {
            return Err(ManifestError::Format {
                path,
                message: format!("format {} (this Vitro reads {FORMAT})", m.format),
            });
        }
        Ok(Some(m))
    }

    /// Writes the manifest into `dir` (atomically: a reader sees the old or the new one).
    pub fn save(&self, dir: &Path) -> Result<(), ManifestError> {
        let path = dir.join(MANIFEST_FILE);
        let mut bytes = serde_json::to_vec_pretty(self).map_err(|e| ManifestError::Io {
            path: path.clone(),
            source: e.into(),
        })?;
        bytes.push(b'\n');
        write_atomic(&path, &bytes).map_err(|source| ManifestError::Io { path, source })
    }
}

/// Status of a run a conditioned experiment did not need.
pub const NOT_NEEDED: &str = "not_needed";

/// A search's settings (those a resume must keep) and what it found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchInfo {
    /// `adaptive` or `random`.
    pub strategy: String,
    /// The search seed.
    pub seed: u64,
    /// Evaluations asked for (a resume may raise it).
    pub budget: u64,
    /// Evaluations per generation.
    pub population: u32,
    /// Share of the evaluations that steer the adaptive strategy.
    pub elite: f64,
    /// The objective, in words.
    pub objective: String,
    /// The range of a searched seed (`None`: run k's seed derives from the search seed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed_range: Option<[u64; 2]>,
    /// Failing runs found.
    pub failures: u64,
    /// The minimal failing scenarios written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub minimal: Vec<MinimalInfo>,
}

impl SearchInfo {
    /// What a resume must keep: strategy, seed, population, elite share and objective.
    pub fn key(&self) -> (String, u64, u32, u64, String) {
        (
            self.strategy.clone(),
            self.seed,
            self.population,
            self.elite.to_bits(),
            self.objective.clone(),
        )
    }

    /// `an adaptive search with seed 3`.
    pub fn describe(&self) -> String {
        format!(
            "a{} {} search with seed {} (population {})",
            if self.strategy.starts_with('a') {
                "n"
            } else {
                ""
            },
            self.strategy,
            self.seed,
            self.population
        )
    }
}

/// A failing run shrunk to a minimal scenario.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MinimalInfo {
    /// The failing run it started from.
    pub run: u64,
    /// The scenario file, relative to the result directory.
    pub file: String,
    /// The trace hash the scenario runs to.
    pub trace_hash: String,
    /// Runs the shrink made.
    pub runs: u32,
    /// What changed from the failing run, in order.
    pub changes: Vec<String>,
    /// Other failing runs that shrank to this same run (same trace hash).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<u64>,
}

/// A new session starting now.
pub fn session(jobs: usize) -> Session {
    Session {
        started: now(),
        finished: None,
        vitro_version: VERSION.to_owned(),
        git_hash: GIT_HASH.to_owned(),
        jobs,
        runs_done: 0,
    }
}

/// Path and SHA-256 of a file's bytes.
pub fn file_info(path: &Path, bytes: &[u8]) -> FileInfo {
    FileInfo {
        path: path.display().to_string(),
        sha256: sha256_hex(bytes),
    }
}

/// SHA-256 of `bytes`, lower-case hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The current time, RFC 3339 UTC to the second.
pub fn now() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    rfc3339(secs)
}

/// Seconds since the Unix epoch as `YYYY-MM-DDTHH:MM:SSZ`.
pub fn rfc3339(secs: u64) -> String {
    let ms = i64::try_from(secs).map_or(i64::MAX, |s| s.saturating_mul(1000));
    vitro::time::UtcTime::from_unix_millis(ms).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00Z");
        assert_eq!(rfc3339(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(rfc3339(1_700_000_000), "2023-11-14T22:13:20Z");
    }

    #[test]
    fn sha256_of_abc() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn git_hash_is_a_hash_or_unknown() {
        assert!(
            GIT_HASH == "unknown"
                || (GIT_HASH.len() == 40 && GIT_HASH.chars().all(|c| c.is_ascii_hexdigit())),
            "{GIT_HASH}"
        );
    }
}
