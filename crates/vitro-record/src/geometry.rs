//! Small geometry for drawing a scene: ground heights and polygon triangulation.

use crate::frame::Heightmap;

impl Heightmap {
    /// Ground height at world `(x, y)`, bilinear between samples; `None` outside the grid.
    ///
    /// ```
    /// use vitro_record::Heightmap;
    /// let h = Heightmap { nx: 2, ny: 2, origin: [0.0, 0.0], cell: 10.0,
    ///                     z: vec![0.0, 10.0, 0.0, 10.0] };
    /// assert_eq!(h.height_at(5.0, 5.0), Some(5.0));
    /// assert_eq!(h.height_at(-1.0, 5.0), None);
    /// ```
    pub fn height_at(&self, x: f64, y: f64) -> Option<f64> {
        if self.nx == 0 || self.ny == 0 || self.z.len() < self.nx * self.ny || self.cell <= 0.0 {
            return None;
        }
        let u = (x - self.origin[0]) / self.cell;
        let v = (y - self.origin[1]) / self.cell;
        let (max_u, max_v) = ((self.nx - 1) as f64, (self.ny - 1) as f64);
        if !(0.0..=max_u).contains(&u) || !(0.0..=max_v).contains(&v) {
            return None;
        }
        // In range, so the casts are exact and in bounds.
        let (i, j) = (
            (u as usize).min(self.nx.saturating_sub(2)),
            (v as usize).min(self.ny.saturating_sub(2)),
        );
        let (fu, fv) = (u - i as f64, v - j as f64);
        let at = |i: usize, j: usize| {
            let (i, j) = (i.min(self.nx - 1), j.min(self.ny - 1));
            f64::from(self.z[j * self.nx + i])
        };
        let bottom = at(i, j) * (1.0 - fu) + at(i + 1, j) * fu;
        let top = at(i, j + 1) * (1.0 - fu) + at(i + 1, j + 1) * fu;
        Some(bottom * (1.0 - fv) + top * fv)
    }
}

/// Twice the signed area of a ring (positive: counter-clockwise).
fn signed_area2(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn inside_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0
}

/// Triangles covering a simple polygon (ear clipping), as index triples into `ring`, each
/// counter-clockwise. A closing point equal to the first is ignored. Degenerate rings (fewer
/// than three points) give no triangles; a ring ear clipping cannot finish (self-crossing)
/// is finished as a fan.
///
/// ```
/// use vitro_record::geometry::triangulate;
/// // An L shape: 6 corners, 4 triangles.
/// let l = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
/// assert_eq!(triangulate(&l).len(), 4);
/// ```
pub fn triangulate(ring: &[[f64; 2]]) -> Vec<[usize; 3]> {
    let mut n = ring.len();
    if n >= 2 && ring[0] == ring[n - 1] {
        n -= 1;
    }
    let ring = &ring[..n];
    if n < 3 {
        return Vec::new();
    }
    let mut left: Vec<usize> = (0..n).collect();
    if signed_area2(ring) < 0.0 {
        left.reverse();
    }
    let mut out = Vec::with_capacity(n - 2);
    while left.len() > 3 {
        let m = left.len();
        let ear = (0..m).find(|&k| {
            let (ia, ib, ic) = (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
            let (a, b, c) = (ring[ia], ring[ib], ring[ic]);
            // A convex corner with no other corner inside its triangle.
            cross(a, b, c) > 0.0
                && !left
                    .iter()
                    .any(|&j| j != ia && j != ib && j != ic && inside_triangle(ring[j], a, b, c))
        });
        let Some(k) = ear else { break };
        out.push([left[(k + m - 1) % m], left[k], left[(k + 1) % m]]);
        left.remove(k);
    }
    // Three left, or stuck on a self-crossing ring: finish as a fan.
    for k in 1..left.len().saturating_sub(1) {
        out.push([left[0], left[k], left[k + 1]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(ring: &[[f64; 2]], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|t| cross(ring[t[0]], ring[t[1]], ring[t[2]]) / 2.0)
            .sum()
    }

    #[test]
    fn triangles_cover_concave_polygons_of_either_orientation() {
        let l = vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let t = triangulate(&l);
        assert_eq!(t.len(), 4);
        assert!((area(&l, &t) - 3.0).abs() < 1e-12);
        assert!(t.iter().all(|t| cross(l[t[0]], l[t[1]], l[t[2]]) > 0.0));
        let mut cw = l.clone();
        cw.reverse();
        let t = triangulate(&cw);
        assert!((area(&cw, &t) - 3.0).abs() < 1e-12);
        // Closed ring: the repeated point is ignored.
        let mut closed = l.clone();
        closed.push(l[0]);
        assert_eq!(triangulate(&closed).len(), 4);
        assert!(triangulate(&[[0.0, 0.0], [1.0, 1.0]]).is_empty());
    }

    #[test]
    fn heights_interpolate_inside_and_stop_outside() {
        let h = Heightmap {
            nx: 3,
            ny: 2,
            origin: [10.0, 20.0],
            cell: 5.0,
            z: vec![0.0, 1.0, 2.0, 10.0, 11.0, 12.0],
        };
        assert_eq!(h.height_at(10.0, 20.0), Some(0.0));
        assert_eq!(h.height_at(20.0, 25.0), Some(12.0));
        assert_eq!(h.height_at(12.5, 22.5), Some(5.5));
        assert_eq!(h.height_at(20.1, 25.0), None);
        let empty = Heightmap {
            nx: 0,
            ny: 0,
            origin: [0.0; 2],
            cell: 1.0,
            z: vec![],
        };
        assert_eq!(empty.height_at(0.0, 0.0), None);
    }
}
