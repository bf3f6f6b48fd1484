//! Terrain viewsheds: which cells an observer sees.
//!
//! A cell is seen (1) if the sight line from the observer's eye (ground + observer height at
//! the observer's position) to a target standing on the cell centre (ground + target height)
//! crosses no terrain triangle ([`LosScene`], ends trimmed by
//! [`END_TOLERANCE`](crate::los::END_TOLERANCE)). Cells without data stay no-data.
//!
//! ```
//! use vitro_site::terrain::Terrain;
//! use vitro_site::viewshed::viewshed;
//! // A wall 100 m high along column 5 of a flat 10 x 3 grid: the far side is hidden.
//! let t = Terrain::from_fn(10, 3, 10.0, |x, _| if (x - 55.0).abs() < 1.0 { 100.0 } else { 0.0 }).unwrap();
//! let v = viewshed(&t, [15.0, 15.0], 2.0, 0.0).unwrap();
//! assert_eq!(v.get(3, 1), Some(1.0));
//! assert_eq!(v.get(8, 1), Some(0.0));
//! ```

use crate::los::{LosError, LosScene};
use crate::terrain::{Grid, Terrain, TerrainError};
use std::path::Path;

/// Why a viewshed could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum ViewshedError {
    /// The observer stands where there is no ground.
    #[error("observer at {0:?} is not over the terrain")]
    ObserverOffTerrain([f64; 2]),
    /// Reading or writing the grid failed.
    #[error(transparent)]
    Terrain(#[from] TerrainError),
    /// Building the ground mesh failed.
    #[error(transparent)]
    Los(#[from] LosError),
    /// Writing the mask failed.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The output file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
}

/// The 0/1 viewshed of `terrain` for an observer at georeferenced `observer` (the grid file's
/// own coordinates, e.g. UTM), `observer_height` metres above the ground, looking at targets
/// `target_height` metres above each cell centre.
pub fn viewshed(
    terrain: &Terrain,
    observer: [f64; 2],
    observer_height: f64,
    target_height: f64,
) -> Result<Grid, ViewshedError> {
    let scene = LosScene::terrain_only(terrain)?;
    viewshed_in(&scene, terrain, observer, observer_height, target_height)
}

/// [`viewshed`] against an existing scene (e.g. one that also holds buildings).
pub fn viewshed_in(
    scene: &LosScene,
    terrain: &Terrain,
    observer: [f64; 2],
    observer_height: f64,
    target_height: f64,
) -> Result<Grid, ViewshedError> {
    let g = terrain.grid();
    let [ox, oy] = g.to_local(observer);
    let ground = terrain
        .height(ox, oy)
        .ok_or(ViewshedError::ObserverOffTerrain(observer))?;
    let eye = [ox, oy, ground + observer_height];
    let mut out = Grid::filled(g.ncols, g.nrows, g.cellsize, g.origin, f64::NAN);
    for row in 0..g.nrows {
        for col in 0..g.ncols {
            let Some(h) = g.get(col, row) else { continue };
            let [x, y] = g.cell_centre(col, row);
            let seen = scene.visible(eye, [x, y, h + target_height]);
            out.set(col, row, if seen { 1.0 } else { 0.0 });
        }
    }
    Ok(out)
}

/// Counts of a computed viewshed.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ViewshedSummary {
    /// Cells seen.
    pub visible: usize,
    /// Cells with data.
    pub cells: usize,
}

/// Reads a terrain file (ESRI ASCII grid or GeoTIFF), computes the viewshed and writes it as
/// an ESRI ASCII grid to `out`.
pub fn viewshed_file(
    input: impl AsRef<Path>,
    observer: [f64; 2],
    observer_height: f64,
    target_height: f64,
    out: impl AsRef<Path>,
) -> Result<ViewshedSummary, ViewshedError> {
    let terrain = Terrain::load(input)?;
    let mask = viewshed(&terrain, observer, observer_height, target_height)?;
    let out = out.as_ref();
    std::fs::write(out, mask.to_asc()).map_err(|source| ViewshedError::Write {
        path: out.display().to_string(),
        source,
    })?;
    let cells = mask.values.iter().filter(|v| !v.is_nan()).count();
    let visible = mask.values.iter().filter(|&&v| v == 1.0).count();
    Ok(ViewshedSummary { visible, cells })
}
