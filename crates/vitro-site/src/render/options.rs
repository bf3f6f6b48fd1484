//! What a map picture shows and why it could not be drawn.

use crate::site::SiteError;

/// Why a map could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The town could not be set on the terrain.
    #[error(transparent)]
    Site(#[from] SiteError),
    /// The requested image is empty or too large.
    #[error("bad image size {0} x {1}")]
    Size(u32, u32),
    /// The embedded font is unreadable.
    #[error("the embedded font cannot be read")]
    Font,
    /// Encoding or writing the PNG failed.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The output file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// What to draw and how big.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width, pixels (the height follows the town's aspect).
    pub width: u32,
    /// Margin around the town's extent, metres.
    pub margin: f64,
    /// World rectangle `[min_x, min_y, max_x, max_y]` to draw instead of the town's extent
    /// plus margin (a close-up).
    pub window: Option<[f64; 4]>,
    /// Title line of the legend.
    pub title: String,
    /// Attribution lines, bottom right (the OpenStreetMap line is always added).
    pub attribution: Vec<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1600,
            margin: 60.0,
            window: None,
            title: "Town on terrain".into(),
            attribution: Vec::new(),
        }
    }
}

/// The attribution the map data requires.
pub const OSM_ATTRIBUTION: &str = "Map data \u{a9} OpenStreetMap contributors, ODbL 1.0";
