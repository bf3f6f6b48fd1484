//! Snapshot files: a run saved mid-way, resumed later to the same trace hash.
//!
//! A snapshot file holds everything `vitro resume` needs but the data files the scenario
//! names (map, terrain, programs): the format version, the mission kind, the scenario's path
//! and its text, the build options, the end time, the time it was saved at and the trace hash
//! then, and the mission's own state ([`Run::save_state`]). The static world is rebuilt
//! from the scenario rather than stored; the mission checks that what it rebuilt is what the
//! run was saved on.
//!
//! The file: 8 bytes of magic (`VITROSAV`), the format version (u32, little-endian), the
//! length of the body (u64) and its FNV-1a checksum (u64), then the body (postcard). A
//! truncated, corrupt, foreign or newer file is a [`SnapshotError`], never a panic.
//!
//! ```
//! use vitro_mission::snapshot::{Snapshot, SnapshotError};
//! let snap = Snapshot {
//!     kind: "demo".into(),
//!     scenario: "/tmp/demo.toml".into(),
//!     text: "kind = \"demo\"\n".into(),
//!     seed: Some(7),
//!     fidelity: None,
//!     end_ns: 60_000_000_000,
//!     saved_at_ns: 30_000_000_000,
//!     trace_hash: 0x1234,
//!     state: vec![1, 2, 3],
//! };
//! let mut bytes = Vec::new();
//! snap.write(&mut bytes).unwrap();
//! assert_eq!(Snapshot::read(bytes.as_slice()).unwrap(), snap);
//! let cut = &bytes[..bytes.len() - 1];
//! assert!(matches!(Snapshot::read(cut), Err(SnapshotError::Truncated { .. })));
//! assert!(matches!(Snapshot::read(&b"kind = \"demo\"\n"[..]), Err(SnapshotError::Foreign)));
//! ```

use crate::{BuildOptions, Run};
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};

mod agents;
pub mod briefed;
mod format;
pub use format::{FORMAT_VERSION, MAGIC, SnapshotError};

/// Bytes before the body: magic, version, length, checksum.
const HEAD: usize = 8 + 4 + 8 + 8;
/// The largest body read (a guard against a corrupt length), bytes.
const MAX_BODY: u64 = 1 << 32;

/// A saved run: what to rebuild it from and its state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// The mission kind.
    pub kind: String,
    /// The scenario's path when it was saved (relative paths in it resolve from its
    /// directory).
    pub scenario: String,
    /// The scenario's text.
    pub text: String,
    /// The seed option the run was built with.
    pub seed: Option<u64>,
    /// The fidelity option the run was built with.
    pub fidelity: Option<String>,
    /// When the run ends, ns.
    pub end_ns: u64,
    /// The simulated time of the state, ns.
    pub saved_at_ns: u64,
    /// The trace hash at that time.
    pub trace_hash: u64,
    /// The mission's own state ([`Run::save_state`]).
    pub state: Vec<u8>,
}

/// FNV-1a, 64 bits.
fn checksum(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

impl Snapshot {
    /// The snapshot of `run`, a run of mission `kind` built from the scenario `text` read
    /// from `scenario` with `options`.
    ///
    /// # Errors
    /// [`SnapshotError::Unsupported`] if the mission cannot save its runs.
    pub fn of(
        kind: &str,
        scenario: &std::path::Path,
        text: &str,
        options: &BuildOptions,
        run: &dyn Run,
    ) -> Result<Snapshot, SnapshotError> {
        let scenario = scenario
            .canonicalize()
            .unwrap_or_else(|_| scenario.to_path_buf());
        Ok(Snapshot {
            kind: kind.to_owned(),
            scenario: scenario.to_string_lossy().into_owned(),
            text: text.to_owned(),
            seed: options.seed,
            fidelity: options.fidelity.clone(),
            end_ns: run.end().as_nanos(),
            saved_at_ns: run.now().as_nanos(),
            trace_hash: run.trace_hash(),
            state: run.save_state()?,
        })
    }

    /// The build options the run was built with.
    pub fn options(&self) -> BuildOptions {
        BuildOptions {
            seed: self.seed,
            fidelity: self.fidelity.clone(),
        }
    }

    /// Writes the snapshot file.
    ///
    /// # Errors
    /// [`SnapshotError::Io`], or [`SnapshotError::Corrupt`] if it cannot be encoded.
    pub fn write(&self, mut w: impl Write) -> Result<(), SnapshotError> {
        let body = postcard::to_stdvec(self).map_err(|e| SnapshotError::Corrupt(e.to_string()))?;
        w.write_all(MAGIC)?;
        w.write_all(&FORMAT_VERSION.to_le_bytes())?;
        w.write_all(&(body.len() as u64).to_le_bytes())?;
        w.write_all(&checksum(&body).to_le_bytes())?;
        w.write_all(&body)?;
        w.flush()?;
        Ok(())
    }

    /// Reads a snapshot file.
    ///
    /// # Errors
    /// [`SnapshotError::Foreign`], [`Version`](SnapshotError::Version),
    /// [`Truncated`](SnapshotError::Truncated), [`Corrupt`](SnapshotError::Corrupt) or
    /// [`Io`](SnapshotError::Io).
    pub fn read(mut r: impl Read) -> Result<Snapshot, SnapshotError> {
        let mut head = Vec::with_capacity(HEAD);
        (&mut r).take(HEAD as u64).read_to_end(&mut head)?;
        let magic_len = head.len().min(MAGIC.len());
        if head[..magic_len] != MAGIC[..magic_len] || head.is_empty() {
            return Err(SnapshotError::Foreign);
        }
        if head.len() < HEAD {
            return Err(SnapshotError::Truncated {
                expected: HEAD as u64,
                found: head.len() as u64,
            });
        }
        let word = |at: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&head[at..at + 8]);
            u64::from_le_bytes(b)
        };
        let mut v = [0u8; 4];
        v.copy_from_slice(&head[8..12]);
        let found = u32::from_le_bytes(v);
        if found != FORMAT_VERSION {
            return Err(SnapshotError::Version { found });
        }
        let (len, sum) = (word(12), word(20));
        if len > MAX_BODY {
            return Err(SnapshotError::Corrupt(format!(
                "the header announces a body of {len} bytes"
            )));
        }
        let mut body = Vec::new();
        (&mut r).take(len).read_to_end(&mut body)?;
        if (body.len() as u64) < len {
            return Err(SnapshotError::Truncated {
                expected: HEAD as u64 + len,
                found: (HEAD + body.len()) as u64,
            });
        }
        let mut more = [0u8; 1];
        if r.read(&mut more)? > 0 {
            return Err(SnapshotError::Corrupt(
                "bytes after the end of the snapshot".into(),
            ));
        }
        if checksum(&body) != sum {
            return Err(SnapshotError::Corrupt("the checksum does not match".into()));
        }
        postcard::from_bytes(&body).map_err(|e| SnapshotError::Corrupt(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes() -> Vec<u8> {
        let snap = Snapshot {
            kind: "k".into(),
            scenario: "s.toml".into(),
            text: "kind = \"k\"".into(),
            seed: None,
            fidelity: Some("physical".into()),
            end_ns: 10,
            saved_at_ns: 5,
            trace_hash: 9,
            state: vec![7; 100],
        };
        let mut out = Vec::new();
        snap.write(&mut out).unwrap();
        out
    }

    #[test]
    fn every_flipped_byte_and_every_cut_is_an_error() {
        let good = bytes();
        assert!(Snapshot::read(good.as_slice()).is_ok());
        for i in 0..good.len() {
            let mut bad = good.clone();
            bad[i] ^= 0x40;
            assert!(Snapshot::read(bad.as_slice()).is_err(), "byte {i} flipped");
            assert!(Snapshot::read(&good[..i]).is_err(), "cut at {i}");
        }
    }

    #[test]
    fn another_version_is_named() {
        let mut bad = bytes();
        bad[8] = 9;
        let e = Snapshot::read(bad.as_slice()).unwrap_err();
        assert!(matches!(e, SnapshotError::Version { found: 9 }), "{e}");
        assert!(e.to_string().contains("version 9"), "{e}");
    }

    #[test]
    fn trailing_bytes_are_corruption() {
        let mut bad = bytes();
        bad.push(0);
        let e = Snapshot::read(bad.as_slice()).unwrap_err();
        assert!(matches!(e, SnapshotError::Corrupt(_)), "{e}");
    }
}
