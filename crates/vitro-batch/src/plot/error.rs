//! [`PlotError`]: why plots could not be made.

use crate::journal::JournalError;
use crate::manifest::{MANIFEST_FILE, ManifestError};
use std::path::PathBuf;

/// Why plots could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The directory holds no results.
    #[error("{0} is not a result directory (no {MANIFEST_FILE})")]
    NotResults(PathBuf),
    /// A metric was asked for that the results do not keep.
    #[error("unknown metric `{name}`; kept metrics: {kept}")]
    UnknownMetric {
        /// The name.
        name: String,
        /// What is kept.
        kept: String,
    },
    /// The success metric is not boolean.
    #[error("success metric `{0}` is not a boolean metric")]
    NotBoolean(String),
    /// Reading the results failed.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// Reading the manifest failed.
    #[error(transparent)]
    Manifest(#[from] ManifestError),
    /// Drawing or writing a plot failed.
    #[error("cannot draw {path}: {message}")]
    Draw {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl PlotError {
    /// Whether the user's input is at fault.
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            PlotError::NotResults(_) | PlotError::UnknownMetric { .. } | PlotError::NotBoolean(_)
        )
    }
}
