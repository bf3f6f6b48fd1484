//! Sectors: an area cut into a grid of rectangles, the tracks a UAV flies to search one
//! (a boustrophedon, "lawnmower" pattern), the order it visits several, and the orbit a
//! fixed-wing UAV flies round a target. Plain geometry in town metres.
//!
//! ```
//! use vitro_surveillance::sector::{grid, sweep};
//!
//! // A 1000 x 600 m area in sectors of at most 400 m: 3 columns, 2 rows.
//! let sectors = grid([0.0, 0.0, 1000.0, 600.0], 400.0, 10);
//! assert_eq!(sectors.len(), 6);
//! assert_eq!(sectors[0].id, 10);
//! assert_eq!(sectors[5].area, [2000.0 / 3.0, 300.0, 1000.0, 600.0]);
//! // Two tracks 150 m apart cover a 300 m tall sector, entered from its nearest corner.
//! let tracks = sweep([0.0, 0.0, 400.0, 300.0], 150.0, [500.0, 0.0]);
//! assert_eq!(tracks, [[400.0, 75.0], [0.0, 75.0], [0.0, 225.0], [400.0, 225.0]]);
//! ```

use serde::{Deserialize, Serialize};

/// A rectangle, town metres `[x_min, y_min, x_max, y_max]`.
pub type Rect = [f64; 4];

/// One sector to search.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sector {
    /// Its number (unique in a run).
    pub id: u32,
    /// Its area.
    pub area: Rect,
}

/// Columns and rows of the grid that cuts `area` into cells of at most `side` metres.
fn dims(area: Rect, side: f64) -> Option<(usize, usize)> {
    let (w, h) = (area[2] - area[0], area[3] - area[1]);
    if !(w > 0.0 && h > 0.0 && side > 0.0 && w.is_finite() && h.is_finite()) {
        return None;
    }
    let n = |len: f64| libm::ceil(len / side).max(1.0) as usize;
    Some((n(w), n(h)))
}

/// The number of sectors [`grid`] makes (0 for an empty or invalid area).
pub fn grid_size(area: Rect, side: f64) -> usize {
    dims(area, side).map_or(0, |(nx, ny)| nx.saturating_mul(ny))
}

/// `area` cut into the fewest equal columns and rows of at most `side` metres, numbered
/// from `first` row by row from the south-west corner.
pub fn grid(area: Rect, side: f64, first: u32) -> Vec<Sector> {
    let Some((nx, ny)) = dims(area, side) else {
        return Vec::new();
    };
    let (w, h) = (
        (area[2] - area[0]) / nx as f64,
        (area[3] - area[1]) / ny as f64,
    );
    let mut out = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = |k: usize| {
                if k == nx {
                    area[2]
                } else {
                    area[0] + k as f64 * w
                }
            };
            let y = |k: usize| {
                if k == ny {
                    area[3]
                } else {
                    area[1] + k as f64 * h
                }
            };
            out.push(Sector {
                id: first + out.len() as u32,
                area: [x(i), y(j), x(i + 1), y(j + 1)],
            });
        }
    }
    out
}

/// The centre of a rectangle.
pub fn centre(r: Rect) -> [f64; 2] {
    [(r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0]
}

/// Distance between two points, as the square root of the sum of the squares. Not
/// [`vitro_site::geo::dist`] (`hypot`): the two differ in the last bit for about one pair of
/// points in ten, and the mission's bids and choices compare these distances, so its runs
/// keep this formula.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    libm::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]))
}

/// The tracks that search `r`: parallel east–west lines `spacing` apart (at least one),
/// each crossed end to end, alternating direction, entered at the corner nearest `from`.
pub fn sweep(r: Rect, spacing: f64, from: [f64; 2]) -> Vec<[f64; 2]> {
    let h = r[3] - r[1];
    let k = libm::ceil(h / spacing.max(1.0)).max(1.0) as usize;
    let flip_x = dist(from, [r[2], r[1]]).min(dist(from, [r[2], r[3]]))
        < dist(from, [r[0], r[1]]).min(dist(from, [r[0], r[3]]));
    let flip_y = dist(from, [r[0], r[3]]).min(dist(from, [r[2], r[3]]))
        < dist(from, [r[0], r[1]]).min(dist(from, [r[2], r[1]]));
    let mut out = Vec::with_capacity(2 * k);
    for i in 0..k {
        let row = if flip_y { k - 1 - i } else { i };
        let y = r[1] + (row as f64 + 0.5) * h / k as f64;
        let (a, b) = if (i % 2 == 0) != flip_x {
            (r[0], r[2])
        } else {
            (r[2], r[0])
        };
        out.push([a, y]);
        out.push([b, y]);
    }
    out
}

/// The length of [`sweep`]'s tracks (without the legs between sectors).
pub fn sweep_length(r: Rect, spacing: f64) -> f64 {
    let tracks = sweep(r, spacing, [r[0], r[1]]);
    tracks.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// The order in which to visit `sectors` from `from`: each time the nearest centre left
/// (ties by id).
pub fn tour(from: [f64; 2], sectors: &[Sector]) -> Vec<Sector> {
    let mut left: Vec<Sector> = sectors.to_vec();
    let mut at = from;
    let mut out = Vec::with_capacity(left.len());
    while !left.is_empty() {
        let best = (0..left.len())
            .min_by(|&a, &b| {
                dist(at, centre(left[a].area))
                    .total_cmp(&dist(at, centre(left[b].area)))
                    .then(left[a].id.cmp(&left[b].id))
            })
            .unwrap_or(0);
        let s = left.swap_remove(best);
        at = centre(s.area);
        out.push(s);
    }
    out
}

/// `n` points on a circle of `radius` round `c`, counter-clockwise from east.
pub fn orbit(c: [f64; 2], radius: f64, n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            [c[0] + radius * libm::cos(a), c[1] + radius * libm::sin(a)]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_covers_the_area_exactly() {
        let area = [-500.0, -300.0, 700.0, 500.0];
        let g = grid(area, 400.0, 0);
        assert_eq!(g.len(), grid_size(area, 400.0));
        assert_eq!(g.len(), 3 * 2);
        let total: f64 = g
            .iter()
            .map(|s| (s.area[2] - s.area[0]) * (s.area[3] - s.area[1]))
            .sum();
        assert!((total - 1200.0 * 800.0).abs() < 1e-6);
        assert!(g.iter().all(|s| s.area[2] - s.area[0] <= 400.0 + 1e-9));
        assert!(grid([0.0, 0.0, 0.0, 1.0], 100.0, 0).is_empty());
        assert_eq!(grid_size([0.0, 0.0, f64::NAN, 1.0], 100.0), 0);
    }

    #[test]
    fn sweeps_enter_at_the_nearest_corner_and_cover_every_track() {
        let r = [0.0, 0.0, 400.0, 400.0];
        for from in [
            [-10.0, -10.0],
            [410.0, -10.0],
            [-10.0, 410.0],
            [410.0, 410.0],
        ] {
            let s = sweep(r, 100.0, from);
            assert_eq!(s.len(), 8);
            let corner_gap = dist(s[0], from);
            assert!(corner_gap < 80.0, "{from:?} -> {:?}", s[0]);
            let mut ys: Vec<f64> = s.iter().map(|p| p[1]).collect();
            ys.sort_by(f64::total_cmp);
            ys.dedup();
            assert_eq!(ys, [50.0, 150.0, 250.0, 350.0]);
        }
        assert_eq!(sweep_length(r, 100.0), 4.0 * 400.0 + 3.0 * 100.0);
    }

    #[test]
    fn a_tour_goes_to_the_nearest_sector_first() {
        let g = grid([0.0, 0.0, 1200.0, 400.0], 400.0, 0);
        let order: Vec<u32> = tour([1300.0, 200.0], &g).iter().map(|s| s.id).collect();
        assert_eq!(order, [2, 1, 0]);
        let o = orbit([0.0, 0.0], 100.0, 4);
        assert!((o[1][1] - 100.0).abs() < 1e-9);
    }
}
