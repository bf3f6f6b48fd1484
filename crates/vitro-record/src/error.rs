//! Why a recording could not be written or read back.

use std::path::PathBuf;

/// Why a recording could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file could not be created.
    #[error("cannot create {}: {source}", path.display())]
    Create {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The MCAP writer failed (usually an I/O error underneath).
    #[error("writing the recording: {0}")]
    Mcap(#[from] mcap::McapError),
    /// Flushing the output failed.
    #[error("writing the recording: {0}")]
    Io(#[from] std::io::Error),
    /// A message could not be encoded.
    #[error("encoding a message: {0}")]
    Json(#[from] serde_json::Error),
    /// Frames must come in time order (equal times are allowed).
    #[error(
        "frame at {t_ns} ns comes after one at {last_ns} ns: frames must be recorded in time order"
    )]
    TimeWentBack {
        /// The rejected frame's time.
        t_ns: u64,
        /// The previous frame's time.
        last_ns: u64,
    },
    /// A number is NaN or infinite: JSON cannot hold it, so it could not be read back.
    #[error(
        "{what} is {value} (at {t_ns} ns): recordings hold finite numbers only; leave an unknown value out"
    )]
    NotFinite {
        /// Which number.
        what: String,
        /// Its value.
        value: f64,
        /// The frame's time (0 for the scene).
        t_ns: u64,
    },
}

/// Why a recording could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// There is no such file.
    #[error("{}: no such file", path.display())]
    Missing {
        /// The file.
        path: PathBuf,
    },
    /// The file exists but could not be opened.
    #[error("cannot open {}: {source}", path.display())]
    Open {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file does not start with the MCAP magic bytes.
    #[error("not an MCAP file (it does not start with the MCAP magic bytes)")]
    NotMcap,
    /// An MCAP file without the `/vitro/scene` and `/vitro/frame` channels.
    #[error(
        "an MCAP file without the /vitro/scene and /vitro/frame channels: not a Vitro recording"
    )]
    NotVitro,
    /// A Vitro recording whose scene message is missing.
    #[error("the recording has no scene message")]
    NoScene,
    /// Reading failed.
    #[error("reading the recording: {0}")]
    Io(#[from] std::io::Error),
    /// A malformed MCAP record.
    #[error("malformed MCAP: {0}")]
    Mcap(#[from] mcap::McapError),
    /// A malformed recording.
    #[error("malformed recording: {0}")]
    Corrupt(String),
    /// A chunk compressed in a way this reader does not decode.
    #[error("a chunk is compressed with {0:?}, which this reader does not decode (zstd or none)")]
    Compression(String),
    /// A scene or frame message that does not decode.
    #[error("the {what} message at {t_ns} ns does not decode: {source}")]
    Decode {
        /// `"scene"` or `"frame"`.
        what: &'static str,
        /// Its log time.
        t_ns: u64,
        /// Why.
        source: serde_json::Error,
    },
}
