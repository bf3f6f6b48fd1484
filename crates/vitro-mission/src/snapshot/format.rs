//! The file format's marks (magic, version) and why a snapshot could not be written, read
//! or resumed.

/// The magic bytes a snapshot file starts with.
pub const MAGIC: &[u8; 8] = b"VITROSAV";
/// The format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 2;

/// Why a snapshot could not be written, read or resumed.
///
/// Each is fatal to the save or the resume asked for (nothing is half-written or half-restored);
/// [`SnapshotError::is_bad_input`] says whether the file is to blame. New variants may be added.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SnapshotError {
    /// Reading or writing the file failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The file is not a Vitro snapshot.
    #[error(
        "not a Vitro snapshot (expected a file that starts with {:?})",
        String::from_utf8_lossy(MAGIC)
    )]
    Foreign,
    /// The file is a snapshot of another format version.
    #[error(
        "snapshot format version {found}, this build reads version {FORMAT_VERSION} (save it again with this build)"
    )]
    Version {
        /// The file's version.
        found: u32,
    },
    /// The file ends early.
    #[error("truncated snapshot: {found} of {expected} bytes")]
    Truncated {
        /// Bytes the header announces (header included).
        expected: u64,
        /// Bytes there are.
        found: u64,
    },
    /// The body does not match its checksum, or does not decode.
    #[error("corrupt snapshot: {0}")]
    Corrupt(String),
    /// No mission of this kind is registered.
    #[error("the snapshot is of a {0:?} mission, which this tool does not know")]
    UnknownKind(String),
    /// The mission cannot save or resume runs.
    #[error("{0} runs cannot be saved or resumed")]
    Unsupported(String),
    /// The world rebuilt from the scenario, or the restored state, is not the one saved.
    #[error("the snapshot does not match: {0}")]
    Mismatch(String),
    /// The scenario in the snapshot could not be built again.
    #[error("the snapshot's scenario cannot be built: {0}")]
    Build(String),
}

impl SnapshotError {
    /// True if the file is to blame (exit code 2), false for a failure of the machine
    /// (reading or writing, exit code 1).
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, SnapshotError::Io(_))
    }
}
