//! The terrain layer: elevation tint, hillshade, contours.

use super::canvas::View;
use crate::terrain::Terrain;
use tiny_skia::Pixmap;

/// Elevation tint: green lowlands, tan slopes, brown tops (`t` in 0..1).
pub(super) fn tint(t: f64) -> [f64; 3] {
    let stops = [
        [0.0, 170.0, 200.0, 140.0],
        [0.45, 226.0, 222.0, 170.0],
        [0.8, 206.0, 176.0, 130.0],
        [1.0, 190.0, 160.0, 140.0],
    ];
    let t = t.clamp(0.0, 1.0);
    for w in stops.windows(2) {
        let (a, b) = (w[0], w[1]);
        if t <= b[0] {
            let f = (t - a[0]) / (b[0] - a[0]);
            return [1, 2, 3].map(|i| a[i] + f * (b[i] - a[i]));
        }
    }
    [190.0, 160.0, 140.0]
}

/// Hillshade at every grid cell (Horn's slope, light from the north-west at 45°), 0..1.
fn hillshade(terrain: &Terrain) -> Vec<f64> {
    let g = terrain.grid();
    let (nc, nr) = (g.ncols as isize, g.nrows as isize);
    let at = |c: isize, r: isize, d: f64| {
        g.get(c.clamp(0, nc - 1) as usize, r.clamp(0, nr - 1) as usize)
            .unwrap_or(d)
    };
    let (az, alt) = (315f64.to_radians(), 45f64.to_radians());
    let mut out = vec![0.5; g.values.len()];
    for r in 0..nr {
        for c in 0..nc {
            let Some(h) = g.get(c as usize, r as usize) else {
                continue;
            };
            let z = |dc: isize, dr: isize| at(c + dc, r + dr, h);
            // Rows run south to north, so +r is north.
            let dzdx = ((z(1, 1) + 2.0 * z(1, 0) + z(1, -1))
                - (z(-1, 1) + 2.0 * z(-1, 0) + z(-1, -1)))
                / (8.0 * g.cellsize);
            let dzdy = ((z(-1, 1) + 2.0 * z(0, 1) + z(1, 1))
                - (z(-1, -1) + 2.0 * z(0, -1) + z(1, -1)))
                / (8.0 * g.cellsize);
            // Surface normal (-dzdx, -dzdy, 1), light direction from azimuth (clockwise from
            // north) and altitude.
            let l = [
                libm::cos(alt) * libm::sin(az),
                libm::cos(alt) * libm::cos(az),
                libm::sin(alt),
            ];
            let n = libm::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
            let shade = (-dzdx * l[0] - dzdy * l[1] + l[2]) / n;
            out[(r * nc + c) as usize] = shade.clamp(0.0, 1.0);
        }
    }
    out
}

/// Bilinear interpolation of per-cell values at local (x, y).
fn bilinear(terrain: &Terrain, vals: &[f64], x: f64, y: f64) -> f64 {
    let g = terrain.grid();
    let u = (x / g.cellsize - 0.5).clamp(0.0, (g.ncols - 1) as f64);
    let v = (y / g.cellsize - 0.5).clamp(0.0, (g.nrows - 1) as f64);
    let i = (u.floor() as usize).min(g.ncols - 2);
    let j = (v.floor() as usize).min(g.nrows - 2);
    let (fx, fy) = (u - i as f64, v - j as f64);
    let k = |c: usize, r: usize| vals[r * g.ncols + c];
    k(i, j) * (1.0 - fx) * (1.0 - fy)
        + k(i + 1, j) * fx * (1.0 - fy)
        + k(i, j + 1) * (1.0 - fx) * fy
        + k(i + 1, j + 1) * fx * fy
}

pub(super) fn draw_terrain(pix: &mut Pixmap, view: &View, terrain: &Terrain) {
    let (w, h) = (pix.width() as usize, pix.height() as usize);
    let shade = hillshade(terrain);
    let heights: Vec<Option<f64>> = (0..w * h)
        .map(|k| {
            let p = view.world((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
            terrain.height(p[0], p[1])
        })
        .collect();
    let (lo, hi) = heights
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = (hi - lo).max(1.0);
    let band = |v: f64, step: f64| libm::floor(v / step) as i64;
    let data = pix.data_mut();
    for k in 0..w * h {
        let (px, py) = (k % w, k / w);
        let rgb = match heights[k] {
            None => [235.0, 235.0, 235.0],
            Some(v) => {
                let p = view.world(px as f64 + 0.5, py as f64 + 0.5);
                let s = bilinear(terrain, &shade, p[0], p[1]);
                let mut c = tint((v - lo) / span).map(|x| x * (0.62 + 0.5 * s));
                // Contours where the 10 m band changes towards the right or down neighbour.
                let next = [
                    (px + 1 < w).then(|| heights[k + 1]).flatten(),
                    (py + 1 < h).then(|| heights[k + w]).flatten(),
                ];
                for n in next.into_iter().flatten() {
                    if band(v, 50.0) != band(n, 50.0) {
                        c = c.map(|x| x * 0.62);
                    } else if band(v, 10.0) != band(n, 10.0) {
                        c = c.map(|x| x * 0.82);
                    }
                }
                c
            }
        };
        for i in 0..3 {
            data[k * 4 + i] = rgb[i].clamp(0.0, 255.0) as u8;
        }
        data[k * 4 + 3] = 255;
    }
}
