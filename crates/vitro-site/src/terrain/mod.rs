//! Terrain: an elevation grid (ESRI ASCII grid or GeoTIFF), bilinear heights, a ground mesh.
//!
//! Local frame: metres from the grid's lower-left corner, `x` east, `y` north, `z` up. Heights
//! are samples at cell centres, so the ground is defined over the rectangle spanned by the
//! centres ([`Terrain::extent`]).
//!
//! ```
//! use vitro_site::terrain::Terrain;
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/terrain/valley_64x64_90m.asc");
//! let t = Terrain::load(path).unwrap();
//! let h = t.height(2880.0, 2880.0).unwrap();
//! assert!((242.0..=442.0).contains(&h));
//! assert_eq!(t.height(-5.0, 100.0), None);
//! ```

mod error;
mod geotiff;
mod grid;

pub use error::TerrainError;
pub use grid::Grid;

use std::path::Path;

/// Ground vertices and triangles (index triples), local metres.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from above.
    pub triangles: Vec<[u32; 3]>,
}

/// An elevation model with height queries.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    grid: Grid,
}

impl Terrain {
    /// A terrain from a grid of heights; at least 2 x 2 cells.
    pub fn new(grid: Grid) -> Result<Self, TerrainError> {
        if grid.ncols < 2 || grid.nrows < 2 || grid.values.len() != grid.ncols * grid.nrows {
            return Err(TerrainError::Invalid(format!(
                "a terrain needs at least 2 x 2 cells, got {} x {}",
                grid.ncols, grid.nrows
            )));
        }
        if grid.cellsize.is_nan() || grid.cellsize <= 0.0 {
            return Err(TerrainError::Invalid("cell size must be positive".into()));
        }
        Ok(Terrain { grid })
    }

    /// A flat terrain at `height`, `ncols` x `nrows` cells of `cellsize` metres.
    pub fn flat(
        ncols: usize,
        nrows: usize,
        cellsize: f64,
        height: f64,
    ) -> Result<Self, TerrainError> {
        Self::new(Grid::filled(ncols, nrows, cellsize, [0.0, 0.0], height))
    }

    /// A terrain whose height at each cell centre `(x, y)` (local metres) is `f(x, y)`.
    pub fn from_fn(
        ncols: usize,
        nrows: usize,
        cellsize: f64,
        f: impl Fn(f64, f64) -> f64,
    ) -> Result<Self, TerrainError> {
        let mut g = Grid::filled(ncols, nrows, cellsize, [0.0, 0.0], 0.0);
        for row in 0..nrows {
            for col in 0..ncols {
                let [x, y] = g.cell_centre(col, row);
                g.set(col, row, f(x, y));
            }
        }
        Self::new(g)
    }

    /// Parses an ESRI ASCII grid.
    pub fn parse_asc(text: &str) -> Result<Self, TerrainError> {
        Self::new(Grid::parse_asc(text)?)
    }

    /// Loads a terrain file: `.tif`/`.tiff` as GeoTIFF, anything else as an ESRI ASCII grid.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, TerrainError> {
        let path = path.as_ref();
        let io = |source| TerrainError::Io {
            path: path.display().to_string(),
            source,
        };
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if matches!(ext.as_deref(), Some("tif" | "tiff")) {
            let file = std::fs::File::open(path).map_err(io)?;
            Self::new(geotiff::read(std::io::BufReader::new(file))?)
        } else {
            Self::parse_asc(&std::fs::read_to_string(path).map_err(io)?)
        }
    }

    /// The grid of heights.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The rectangle `[min_x, min_y, max_x, max_y]` (local metres) where the ground is defined:
    /// from the first to the last cell centre.
    pub fn extent(&self) -> [f64; 4] {
        let h = self.grid.cellsize / 2.0;
        let [w, n] = self.grid.size();
        [h, h, w - h, n - h]
    }

    /// Ground height at local (`x`, `y`) by bilinear interpolation of the four surrounding
    /// cell centres; `None` outside [`extent`](Self::extent) or next to no-data.
    pub fn height(&self, x: f64, y: f64) -> Option<f64> {
        let g = &self.grid;
        let u = x / g.cellsize - 0.5;
        let v = y / g.cellsize - 0.5;
        let (umax, vmax) = ((g.ncols - 1) as f64, (g.nrows - 1) as f64);
        if !(0.0..=umax).contains(&u) || !(0.0..=vmax).contains(&v) {
            return None;
        }
        let i = (u.floor() as usize).min(g.ncols - 2);
        let j = (v.floor() as usize).min(g.nrows - 2);
        let (fx, fy) = (u - i as f64, v - j as f64);
        let h00 = g.get(i, j)?;
        let h10 = g.get(i + 1, j)?;
        let h01 = g.get(i, j + 1)?;
        let h11 = g.get(i + 1, j + 1)?;
        Some(
            h00 * (1.0 - fx) * (1.0 - fy)
                + h10 * fx * (1.0 - fy)
                + h01 * (1.0 - fx) * fy
                + h11 * fx * fy,
        )
    }

    /// Ground height on the [`mesh`](Self::mesh) itself (piecewise linear over its
    /// triangles): what line of sight and physics see. Differs from the bilinear
    /// [`height`](Self::height) by at most [`mesh_deviation`](Self::mesh_deviation).
    pub fn surface_height(&self, x: f64, y: f64) -> Option<f64> {
        let g = &self.grid;
        let u = x / g.cellsize - 0.5;
        let v = y / g.cellsize - 0.5;
        let (umax, vmax) = ((g.ncols - 1) as f64, (g.nrows - 1) as f64);
        if !(0.0..=umax).contains(&u) || !(0.0..=vmax).contains(&v) {
            return None;
        }
        let i = (u.floor() as usize).min(g.ncols - 2);
        let j = (v.floor() as usize).min(g.nrows - 2);
        let (fx, fy) = (u - i as f64, v - j as f64);
        let a = g.get(i, j)?;
        let b = g.get(i + 1, j)?;
        let c = g.get(i + 1, j + 1)?;
        let d = g.get(i, j + 1)?;
        let m2 = (a + b + c + d) / 2.0;
        // The fan triangle holding the point, each written as edge ramp + rise to the middle.
        Some(if fy <= fx && fy <= 1.0 - fx {
            a + (b - a) * fx + (m2 - a - b) * fy
        } else if fy >= fx && fy >= 1.0 - fx {
            d + (c - d) * fx + (m2 - c - d) * (1.0 - fy)
        } else if fx >= fy {
            b + (c - b) * fy + (m2 - b - c) * (1.0 - fx)
        } else {
            a + (d - a) * fy + (m2 - a - d) * fx
        })
    }

    /// The ground mesh: for every cell square between four valid centres, four triangles
    /// fanned around a middle vertex at the bilinear height (the mean of the corners).
    ///
    /// The mesh is exact along cell edges and differs from [`height`](Self::height) by at most
    /// `|h00 + h11 - h10 - h01| / 16` inside a square (half a fan triangle's diagonal).
    pub fn mesh(&self) -> Mesh {
        let g = &self.grid;
        let (nc, nr) = (g.ncols, g.nrows);
        let mut index = vec![u32::MAX; nc * nr];
        let mut mesh = Mesh::default();
        let mut corner = |mesh: &mut Mesh, c: usize, r: usize| -> u32 {
            let k = r * nc + c;
            if index[k] == u32::MAX {
                index[k] = mesh.vertices.len() as u32;
                let [x, y] = g.cell_centre(c, r);
                mesh.vertices.push([x, y, g.values[k]]);
            }
            index[k]
        };
        for r in 0..nr - 1 {
            for c in 0..nc - 1 {
                let hs = [
                    g.get(c, r),
                    g.get(c + 1, r),
                    g.get(c + 1, r + 1),
                    g.get(c, r + 1),
                ];
                let [Some(a), Some(b), Some(cc), Some(d)] = hs else {
                    continue;
                };
                let ids = [
                    corner(&mut mesh, c, r),
                    corner(&mut mesh, c + 1, r),
                    corner(&mut mesh, c + 1, r + 1),
                    corner(&mut mesh, c, r + 1),
                ];
                let [x, y] = g.cell_centre(c, r);
                let h = g.cellsize / 2.0;
                let m = mesh.vertices.len() as u32;
                mesh.vertices.push([x + h, y + h, (a + b + cc + d) / 4.0]);
                for k in 0..4 {
                    mesh.triangles.push([ids[k], ids[(k + 1) % 4], m]);
                }
            }
        }
        mesh
    }

    /// The ground mesh as a parry3d [`TriMesh`](parry3d::shape::TriMesh) (`f32`, local
    /// metres), for physics colliders.
    pub fn trimesh(&self) -> Result<parry3d::shape::TriMesh, TerrainError> {
        let m = self.mesh();
        let v = m
            .vertices
            .iter()
            .map(|p| parry3d::math::Vector::new(p[0] as f32, p[1] as f32, p[2] as f32))
            .collect();
        parry3d::shape::TriMesh::new(v, m.triangles)
            .map_err(|e| TerrainError::Invalid(format!("ground mesh: {e:?}")))
    }

    /// The largest gap between the mesh and the bilinear surface over the grid, metres.
    pub fn mesh_deviation(&self) -> f64 {
        let g = &self.grid;
        let mut worst: f64 = 0.0;
        for r in 0..g.nrows - 1 {
            for c in 0..g.ncols - 1 {
                if let (Some(a), Some(b), Some(cc), Some(d)) = (
                    g.get(c, r),
                    g.get(c + 1, r),
                    g.get(c + 1, r + 1),
                    g.get(c, r + 1),
                ) {
                    worst = worst.max((a + cc - b - d).abs() / 16.0);
                }
            }
        }
        worst
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_is_exact_on_a_plane_and_at_centres() {
        let t = Terrain::from_fn(4, 3, 10.0, |x, y| 2.0 * x - y + 7.0).unwrap();
        for &(x, y) in &[(5.0, 5.0), (12.5, 17.0), (35.0, 25.0), (20.0, 10.0)] {
            let h = t.height(x, y).unwrap();
            assert!((h - (2.0 * x - y + 7.0)).abs() < 1e-9, "{x},{y}");
        }
        assert_eq!(t.height(4.9, 5.0), None);
        assert_eq!(t.height(35.1, 5.0), None);
        assert_eq!(t.mesh_deviation(), 0.0);
        let m = t.mesh();
        assert_eq!(m.triangles.len(), 3 * 2 * 4);
        assert_eq!(t.trimesh().unwrap().indices().len(), 3 * 2 * 4);
        assert_eq!(m.vertices.len(), 12 + 6);
    }

    #[test]
    fn bilinear_on_a_saddle_and_no_data() {
        // h = x*y sampled at centres: bilinear reproduces it exactly.
        let mut g = Grid::filled(3, 3, 1.0, [0.0, 0.0], 0.0);
        for r in 0..3 {
            for c in 0..3 {
                let [x, y] = g.cell_centre(c, r);
                g.set(c, r, x * y);
            }
        }
        g.set(2, 2, f64::NAN);
        let t = Terrain::new(g).unwrap();
        assert!((t.height(1.2, 0.9).unwrap() - 1.08).abs() < 1e-12);
        assert_eq!(t.height(2.2, 2.2), None);
        assert_eq!(t.mesh().triangles.len(), 3 * 4);
        assert!(t.mesh_deviation() > 0.0);
    }

    #[test]
    fn tiny_grids_are_refused() {
        assert!(Terrain::flat(1, 5, 1.0, 0.0).is_err());
    }
}
