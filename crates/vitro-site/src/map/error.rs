//! Why a map could not be read.

/// Why a map could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// The file could not be opened.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The PBF decoder failed.
    #[error("invalid .osm.pbf data: {0}")]
    Pbf(#[from] osmpbf::Error),
    /// The data decoded but makes no sense.
    #[error("malformed map: {0}")]
    Malformed(String),
    /// The file holds no nodes.
    #[error("the map holds no nodes")]
    Empty,
}
