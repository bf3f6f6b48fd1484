//! Reading a single-band GeoTIFF elevation model.

use super::error::TerrainError;
use super::grid::Grid;
use std::io::{Read, Seek};
use tiff::decoder::{Decoder, DecodingResult};
use tiff::tags::Tag;

/// GeoKey of the raster type (1 = pixel is area, 2 = pixel is point).
const GT_RASTER_TYPE_GEO_KEY: u16 = 1025;

/// Reads a GeoTIFF: samples as heights, origin and cell size from `ModelTiepointTag` and
/// `ModelPixelScaleTag`. Integer and float single-band samples are accepted.
///
/// Cells of value 0 connected (4-neighbour) to the border are no-data, as left by
/// re-projection; a 0 inside the valid area stays a height of 0. A `GDAL_NODATA` value is not
/// read (the border rule covers the files this crate ships).
pub(crate) fn read<R: Read + Seek>(reader: R) -> Result<Grid, TerrainError> {
    let mut dec = Decoder::new(reader)?;
    let (w, h) = dec.dimensions()?;
    let (ncols, nrows) = (w as usize, h as usize);
    let scale = dec
        .find_tag(Tag::ModelPixelScaleTag)?
        .ok_or_else(|| TerrainError::Missing("GeoTIFF ModelPixelScaleTag".into()))?
        .into_f64_vec()?;
    let tie = dec
        .find_tag(Tag::ModelTiepointTag)?
        .ok_or_else(|| TerrainError::Missing("GeoTIFF ModelTiepointTag".into()))?
        .into_f64_vec()?;
    if scale.len() < 2 || tie.len() < 6 {
        return Err(TerrainError::Invalid(
            "GeoTIFF georeference tags too short".into(),
        ));
    }
    let (sx, sy) = (scale[0], scale[1]);
    if sx.is_nan() || sx <= 0.0 || (sx - sy).abs() > 1e-9 * sx {
        return Err(TerrainError::Invalid(format!(
            "cells must be square, got {sx} x {sy}"
        )));
    }
    let pixel_is_point = dec
        .find_tag(Tag::GeoKeyDirectoryTag)?
        .map(|v| v.into_u16_vec())
        .transpose()?
        .is_some_and(|keys| {
            keys.chunks_exact(4)
                .skip(1)
                .any(|k| k[0] == GT_RASTER_TYPE_GEO_KEY && k[3] == 2)
        });
    // Model coordinate of raster point (i, j); with pixel-is-point it names a pixel centre.
    let (i, j, x, y) = (tie[0], tie[1], tie[3], tie[4]);
    let shift = if pixel_is_point { 0.5 } else { 0.0 };
    let left = x - (i + shift) * sx;
    let top = y + (j + shift) * sy;
    let origin = [left, top - nrows as f64 * sy];

    let samples: Vec<f64> = match dec.read_image()? {
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        _ => {
            return Err(TerrainError::Invalid(
                "unsupported GeoTIFF sample type".into(),
            ));
        }
    };
    if samples.len() != ncols * nrows {
        return Err(TerrainError::Invalid(format!(
            "GeoTIFF has {} samples for {ncols} x {nrows} cells (one band expected)",
            samples.len()
        )));
    }
    // File rows run north to south; the grid stores south to north.
    let mut values = vec![0.0; ncols * nrows];
    for r in 0..nrows {
        let src = &samples[r * ncols..(r + 1) * ncols];
        values[(nrows - 1 - r) * ncols..(nrows - r) * ncols].copy_from_slice(src);
    }
    let mut grid = Grid {
        ncols,
        nrows,
        cellsize: sx,
        origin,
        values,
    };
    mask_border_zeros(&mut grid);
    Ok(grid)
}

/// Turns the zero cells reachable from the border through zero cells into no-data.
pub(crate) fn mask_border_zeros(g: &mut Grid) {
    let (nc, nr) = (g.ncols, g.nrows);
    let mut stack: Vec<usize> = Vec::new();
    for c in 0..nc {
        stack.push(c);
        stack.push((nr - 1) * nc + c);
    }
    for r in 0..nr {
        stack.push(r * nc);
        stack.push(r * nc + nc - 1);
    }
    while let Some(k) = stack.pop() {
        if g.values[k] != 0.0 {
            continue;
        }
        g.values[k] = f64::NAN;
        let (r, c) = (k / nc, k % nc);
        if c > 0 {
            stack.push(k - 1);
        }
        if c + 1 < nc {
            stack.push(k + 1);
        }
        if r > 0 {
            stack.push(k - nc);
        }
        if r + 1 < nr {
            stack.push(k + nc);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_border_connected_zeros_are_masked() {
        let mut g = Grid::filled(5, 4, 1.0, [0.0, 0.0], 7.0);
        g.set(0, 0, 0.0);
        g.set(1, 0, 0.0);
        g.set(1, 1, 0.0); // connected to the border through (1, 0)
        g.set(3, 2, 0.0); // an interior zero: a real height
        mask_border_zeros(&mut g);
        assert_eq!(g.get(0, 0), None);
        assert_eq!(g.get(1, 1), None);
        assert_eq!(g.get(3, 2), Some(0.0));
        assert_eq!(g.get(2, 2), Some(7.0));
    }
}
