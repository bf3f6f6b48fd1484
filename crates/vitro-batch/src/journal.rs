//! The run journal `runs.jsonl`: one JSON line per finished run, appended and flushed to
//! disk as each run ends, so a killed batch loses no finished run. Tables are rebuilt from it.
//!
//! A process killed while writing can leave a torn last line: reading drops it (and
//! [`Journal::open`] truncates it away before appending). A bad line anywhere else is
//! corruption and an error, as is a run recorded twice.

use crate::runner::SeriesRow;
use crate::value::Value;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Name of the journal file in a result directory.
pub const JOURNAL_FILE: &str = "runs.jsonl";

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// It ran to its end.
    Ok,
    /// It returned an error or panicked.
    Failed,
}

impl Status {
    /// `ok` or `failed`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
        }
    }
}

/// One finished run: one line of the journal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    /// Run number.
    pub run: u64,
    /// Combination of levels.
    pub point: u64,
    /// Replicate within the point.
    pub replicate: u32,
    /// The run's seed.
    pub seed: u64,
    /// Level of each varied parameter, by dotted key.
    pub params: BTreeMap<String, Value>,
    /// How it ended.
    pub status: Status,
    /// Why it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Wall-clock seconds it took.
    pub wall_s: f64,
    /// Kept metrics (empty if it failed).
    pub metrics: BTreeMap<String, Value>,
    /// Kept time series.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<SeriesRow>,
}

/// Why the journal could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum JournalError {
    /// An I/O error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A line before the last is not a run record.
    #[error("{path}:{line}: corrupt run record: {message}")]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A run appears twice.
    #[error("{path}: run {run} is recorded twice")]
    Duplicate {
        /// The file.
        path: PathBuf,
        /// The run.
        run: u64,
    },
    /// Another process holds the journal.
    #[error("{path} is being written by another batch (locked)")]
    Busy {
        /// The file.
        path: PathBuf,
    },
}

/// The records of a journal.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reading {
    /// The records, in the order written.
    pub records: Vec<RunRecord>,
    /// Bytes of the intact lines (the length to truncate to).
    pub intact_len: u64,
    /// Whether a torn last line was dropped.
    pub torn: bool,
}

/// Parses journal bytes (`path` names it in errors).
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Reading, JournalError> {
    let mut out = Reading::default();
    let mut seen = BTreeSet::new();
    let mut offset = 0usize;
    let mut lines = bytes
        .split_inclusive(|&b| b == b'\n')
        .enumerate()
        .peekable();
    while let Some((i, line)) = lines.next() {
        let last = lines.peek().is_none();
        let complete = line.ends_with(b"\n");
        let parsed = std::str::from_utf8(line)
            .map_err(|e| e.to_string())
            .and_then(|s| serde_json::from_str::<RunRecord>(s).map_err(|e| e.to_string()));
        match parsed {
            Ok(rec) if complete => {
                if !seen.insert(rec.run) {
                    return Err(JournalError::Duplicate {
                        path: path.to_owned(),
                        run: rec.run,
                    });
                }
                out.records.push(rec);
                offset += line.len();
            }
            // A torn write leaves an unfinished (or unparsable) last line.
            _ if last => out.torn = true,
            other => {
                return Err(JournalError::Corrupt {
                    path: path.to_owned(),
                    line: i + 1,
                    message: other.err().unwrap_or_else(|| "unterminated line".into()),
                });
            }
        }
    }
    out.intact_len = offset as u64;
    Ok(out)
}

/// Reads the journal of `dir` without changing it (a missing journal has no records).
pub fn read(dir: &Path) -> Result<Reading, JournalError> {
    let path = dir.join(JOURNAL_FILE);
    match std::fs::read(&path) {
        Ok(bytes) => parse(&path, &bytes),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Reading::default()),
        Err(source) => Err(JournalError::Io { path, source }),
    }
}

/// The journal of a running batch: locked, appended to, synced after every record.
#[derive(Debug)]
pub struct Journal {
    file: File,
    path: PathBuf,
}

impl Journal {
    /// Opens (or creates) the journal of `dir` for appending, locks it against other
    /// batches, drops a torn last line and returns the records already there.
    pub fn open(dir: &Path) -> Result<(Journal, Reading), JournalError> {
        let path = dir.join(JOURNAL_FILE);
        let io = |source| JournalError::Io {
            path: path.clone(),
            source,
        };
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(io)?;
        lock(&file, &path)?;
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes).map_err(io)?;
        let reading = parse(&path, &bytes)?;
        if reading.torn {
            file.set_len(reading.intact_len).map_err(io)?;
            file.sync_data().map_err(io)?;
        }
        file.seek(SeekFrom::Start(reading.intact_len)).map_err(io)?;
        Ok((Journal { file, path }, reading))
    }

    /// Appends one record as one line and waits until it is on disk.
    pub fn append(&mut self, rec: &RunRecord) -> Result<(), JournalError> {
        let io = |source| JournalError::Io {
            path: self.path.clone(),
            source,
        };
        let mut line = serde_json::to_vec(rec).map_err(|e| io(e.into()))?;
        line.push(b'\n');
        self.file.write_all(&line).map_err(io)?;
        self.file.sync_data().map_err(io)
    }
}

/// Writes a whole journal (sorted records) to `dir`, replacing any (for merges).
pub fn write_all(dir: &Path, records: &[RunRecord]) -> Result<(), JournalError> {
    let path = dir.join(JOURNAL_FILE);
    let mut bytes = Vec::new();
    for rec in records {
        let line = serde_json::to_vec(rec).map_err(|e| JournalError::Io {
            path: path.clone(),
            source: e.into(),
        })?;
        bytes.extend_from_slice(&line);
        bytes.push(b'\n');
    }
    crate::write_file::write_atomic(&path, &bytes)
        .map_err(|source| JournalError::Io { path, source })
}

#[cfg(unix)]
fn lock(file: &File, path: &Path) -> Result<(), JournalError> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a descriptor we own; the lock is released when the file is closed,
    // or by the kernel if the process dies.
    let rc = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if rc == 0 {
        return Ok(());
    }
    let e = std::io::Error::last_os_error();
    if e.kind() == std::io::ErrorKind::WouldBlock {
        Err(JournalError::Busy {
            path: path.to_owned(),
        })
    } else {
        Err(JournalError::Io {
            path: path.to_owned(),
            source: e,
        })
    }
}

#[cfg(not(unix))]
fn lock(_: &File, _: &Path) -> Result<(), JournalError> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(run: u64) -> RunRecord {
        RunRecord {
            run,
            point: run / 2,
            replicate: (run % 2) as u32,
            seed: u64::MAX - run,
            params: BTreeMap::from([("a.b".to_string(), Value::Float(0.5))]),
            status: Status::Ok,
            error: None,
            wall_s: 0.25,
            metrics: BTreeMap::from([("m".to_string(), Value::Int(3))]),
            series: vec![SeriesRow {
                t_s: 1.0,
                values: BTreeMap::from([("m".to_string(), Value::Float(f64::NAN))]),
            }],
        }
    }

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("vitro-journal-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn append_then_read_back() {
        let d = tmp("append");
        let (mut j, r) = Journal::open(&d).unwrap();
        assert!(r.records.is_empty());
        j.append(&rec(1)).unwrap();
        j.append(&rec(0)).unwrap();
        drop(j);
        let r = read(&d).unwrap();
        assert_eq!(r.records.len(), 2);
        assert_eq!(r.records[0].run, 1);
        assert_eq!(r.records[0].seed, u64::MAX - 1);
        assert!(!r.torn);
    }

    #[test]
    fn torn_last_line_is_dropped_and_truncated() {
        let d = tmp("torn");
        let (mut j, _) = Journal::open(&d).unwrap();
        j.append(&rec(0)).unwrap();
        drop(j);
        let path = d.join(JOURNAL_FILE);
        let good = std::fs::read(&path).unwrap();
        let line = serde_json::to_vec(&rec(1)).unwrap();
        let mut torn = good.clone();
        torn.extend_from_slice(&line[..line.len() / 2]);
        std::fs::write(&path, &torn).unwrap();
        let r = read(&d).unwrap();
        assert!(r.torn);
        assert_eq!(r.records.len(), 1);
        // Opening for appending cuts the torn tail; the next record lands on its own line.
        let (mut j, r) = Journal::open(&d).unwrap();
        assert_eq!(r.intact_len, good.len() as u64);
        j.append(&rec(1)).unwrap();
        drop(j);
        let r = read(&d).unwrap();
        assert!(!r.torn);
        assert_eq!(r.records.iter().map(|r| r.run).collect::<Vec<_>>(), [0, 1]);
    }

    #[test]
    fn corruption_and_duplicates_are_errors() {
        let p = Path::new("j");
        let line = serde_json::to_string(&rec(0)).unwrap();
        let bad = format!("{line}\n{{oops\n{line}\n");
        assert!(matches!(
            parse(p, bad.as_bytes()),
            Err(JournalError::Corrupt { line: 2, .. })
        ));
        let dup = format!("{line}\n{line}\n");
        assert!(matches!(
            parse(p, dup.as_bytes()),
            Err(JournalError::Duplicate { run: 0, .. })
        ));
    }

    #[test]
    fn a_second_writer_is_refused() {
        let d = tmp("lock");
        let (_j, _) = Journal::open(&d).unwrap();
        if cfg!(unix) {
            assert!(matches!(Journal::open(&d), Err(JournalError::Busy { .. })));
        }
    }
}
