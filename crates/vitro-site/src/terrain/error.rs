//! Why a terrain could not be read or built.

/// Why a terrain could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TerrainError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// A syntax error in an ASCII grid.
    #[error("line {line}, column {column}: {what}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// 1-based column (characters).
        column: usize,
        /// What is wrong.
        what: String,
    },
    /// Something required is absent.
    #[error("missing {0}")]
    Missing(String),
    /// The grid is well-formed but unusable.
    #[error("invalid grid: {0}")]
    Invalid(String),
    /// The TIFF decoder failed.
    #[error("GeoTIFF: {0}")]
    Tiff(#[from] tiff::TiffError),
}
