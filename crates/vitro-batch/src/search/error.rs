//! [`SearchError`]: why a search could not run.

use crate::exec::BatchError;
use std::path::PathBuf;

/// Why a search could not run.
#[derive(Debug, thiserror::Error)]
pub enum SearchError {
    /// The experiment has no `[search]` table.
    #[error("{0} has no [search] table: nothing to search")]
    NoSearch(PathBuf),
    /// The directory, journal, manifest or tables failed.
    #[error(transparent)]
    Batch(#[from] BatchError),
    /// A file could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl From<crate::manifest::ManifestError> for SearchError {
    fn from(e: crate::manifest::ManifestError) -> Self {
        SearchError::Batch(e.into())
    }
}

impl From<crate::journal::JournalError> for SearchError {
    fn from(e: crate::journal::JournalError) -> Self {
        SearchError::Batch(e.into())
    }
}

impl From<crate::table_out::TableError> for SearchError {
    fn from(e: crate::table_out::TableError) -> Self {
        SearchError::Batch(e.into())
    }
}

impl SearchError {
    /// Whether the user's input is at fault.
    pub fn is_input(&self) -> bool {
        match self {
            SearchError::NoSearch(_) => true,
            SearchError::Batch(e) => e.is_input(),
            SearchError::Write { .. } => false,
        }
    }
}
