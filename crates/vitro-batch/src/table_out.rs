//! Writing the result tables of a directory: `summary` (and `series`) as CSV, and as
//! Parquet with the `parquet` feature.

use crate::journal::RunRecord;
use crate::manifest::Manifest;
use crate::table::{series, summary};
use crate::write_file::write_atomic;
use std::path::{Path, PathBuf};

/// Why a table could not be written.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    /// Writing a file failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

/// Writes `summary.csv` (and `series.csv` if series are kept), plus their Parquet copies
/// with the `parquet` feature, into `dir`; returns the files written.
pub fn write_tables(
    dir: &Path,
    manifest: &Manifest,
    records: &[RunRecord],
) -> Result<Vec<PathBuf>, TableError> {
    let mut tables = vec![("summary", summary(manifest, records))];
    if !manifest.keep.series.is_empty() {
        tables.push(("series", series(manifest, records)));
    }
    let mut written = Vec::new();
    for (name, table) in &tables {
        let path = dir.join(format!("{name}.csv"));
        let fail = |message: String| TableError::Write {
            path: path.clone(),
            message,
        };
        let bytes = table.to_csv().map_err(|e| fail(e.to_string()))?;
        write_atomic(&path, &bytes).map_err(|e| fail(e.to_string()))?;
        written.push(path.clone());
        #[cfg(feature = "parquet")]
        {
            let path = dir.join(format!("{name}.parquet"));
            let bytes =
                crate::parquet_out::to_parquet(table).map_err(|message| TableError::Write {
                    path: path.clone(),
                    message,
                })?;
            write_atomic(&path, &bytes).map_err(|e| TableError::Write {
                path: path.clone(),
                message: e.to_string(),
            })?;
            written.push(path);
        }
    }
    Ok(written)
}
