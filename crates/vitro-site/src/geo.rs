//! Plane geometry: the local projection, polygons and their queries.
//!
//! Coordinates are metres in a local frame: `x` east, `y` north. Trigonometry goes through
//! `libm` so results match across machines.

use serde::{Deserialize, Serialize};

/// A point or vector in the plane, metres.
pub type P2 = [f64; 2];

/// WGS 84 semi-major axis, metres.
const WGS84_A: f64 = 6_378_137.0;
/// WGS 84 first eccentricity squared.
const WGS84_E2: f64 = 6.694_379_990_14e-3;

/// Local projection from (lat, lon) degrees to metres around a centre point.
///
/// Equirectangular on the local tangent plane: `x = N·cos(lat0)·Δlon`, `y = M·Δlat`, with
/// `N` and `M` the WGS 84 prime-vertical and meridional radii of curvature at the centre.
/// Over a town (a few km) the distortion stays under a few centimetres per kilometre.
///
/// ```
/// use vitro_site::geo::LocalProjection;
/// let p = LocalProjection::new(60.0, 27.0);
/// let [x, y] = p.project(60.001, 27.0);
/// assert!(x.abs() < 1e-9 && (y - 111.4).abs() < 0.5);
/// let [lat, lon] = p.unproject([x, y]);
/// assert!((lat - 60.001).abs() < 1e-12 && (lon - 27.0).abs() < 1e-12);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalProjection {
    /// Centre latitude, degrees.
    pub lat0: f64,
    /// Centre longitude, degrees.
    pub lon0: f64,
    /// Metres per degree of longitude at the centre.
    kx: f64,
    /// Metres per degree of latitude at the centre.
    ky: f64,
}

impl LocalProjection {
    /// A projection centred on (`lat0`, `lon0`) degrees.
    pub fn new(lat0: f64, lon0: f64) -> Self {
        let phi = lat0.to_radians();
        let s = libm::sin(phi);
        let w = 1.0 - WGS84_E2 * s * s;
        let n = WGS84_A / libm::sqrt(w);
        let m = WGS84_A * (1.0 - WGS84_E2) / (w * libm::sqrt(w));
        let deg = std::f64::consts::PI / 180.0;
        LocalProjection {
            lat0,
            lon0,
            kx: n * libm::cos(phi) * deg,
            ky: m * deg,
        }
    }
    /// (lat, lon) degrees to local metres.
    pub fn project(&self, lat: f64, lon: f64) -> P2 {
        [(lon - self.lon0) * self.kx, (lat - self.lat0) * self.ky]
    }
    /// Local metres back to (lat, lon) degrees.
    pub fn unproject(&self, p: P2) -> [f64; 2] {
        [self.lat0 + p[1] / self.ky, self.lon0 + p[0] / self.kx]
    }
}

/// Euclidean distance between two points.
pub fn dist(a: P2, b: P2) -> f64 {
    libm::hypot(a[0] - b[0], a[1] - b[1])
}

/// Length of a polyline (sum of its segment lengths).
pub fn polyline_length(pts: &[P2]) -> f64 {
    pts.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// The point of segment `a`-`b` closest to `p`.
pub fn closest_on_segment(p: P2, a: P2, b: P2) -> P2 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    if l2 == 0.0 {
        return a;
    }
    let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0);
    [a[0] + t * d[0], a[1] + t * d[1]]
}

/// Twice the signed area of a ring (positive if counter-clockwise).
fn signed_area2(ring: &[P2]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

/// A polygon with holes. Rings are open (the first point is not repeated); the outer ring
/// runs counter-clockwise and holes clockwise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Polygon {
    /// The outer boundary.
    pub outer: Vec<P2>,
    /// Holes (e.g. courtyards, islands).
    pub holes: Vec<Vec<P2>>,
}

impl Polygon {
    /// A polygon from rings in any orientation, closed or open. `None` if the outer ring has
    /// fewer than three distinct points or no area.
    pub fn new(outer: Vec<P2>, holes: Vec<Vec<P2>>) -> Option<Self> {
        let outer = normalize_ring(outer, true)?;
        let holes = holes
            .into_iter()
            .filter_map(|h| normalize_ring(h, false))
            .collect();
        Some(Polygon { outer, holes })
    }
    /// All rings: outer first, then holes.
    pub fn rings(&self) -> impl Iterator<Item = &[P2]> + '_ {
        std::iter::once(self.outer.as_slice()).chain(self.holes.iter().map(Vec::as_slice))
    }
    /// All boundary edges (of every ring) as point pairs.
    pub fn edges(&self) -> impl Iterator<Item = (P2, P2)> + '_ {
        self.rings()
            .flat_map(|r| (0..r.len()).map(move |i| (r[i], r[(i + 1) % r.len()])))
    }
    /// Area, holes subtracted.
    pub fn area(&self) -> f64 {
        self.rings().map(signed_area2).sum::<f64>() / 2.0
    }
    /// Area centroid of the outer ring.
    pub fn centroid(&self) -> P2 {
        let r = &self.outer;
        let n = r.len();
        let (mut cx, mut cy, mut a2) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let (p, q) = (r[i], r[(i + 1) % n]);
            let c = p[0] * q[1] - q[0] * p[1];
            cx += (p[0] + q[0]) * c;
            cy += (p[1] + q[1]) * c;
            a2 += c;
        }
        if a2.abs() < 1e-12 {
            let k = n as f64;
            return [
                r.iter().map(|p| p[0]).sum::<f64>() / k,
                r.iter().map(|p| p[1]).sum::<f64>() / k,
            ];
        }
        [cx / (3.0 * a2), cy / (3.0 * a2)]
    }
    /// Bounding box `[min_x, min_y, max_x, max_y]`.
    pub fn bbox(&self) -> [f64; 4] {
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for p in &self.outer {
            b[0] = b[0].min(p[0]);
            b[1] = b[1].min(p[1]);
            b[2] = b[2].max(p[0]);
            b[3] = b[3].max(p[1]);
        }
        b
    }
    /// True if `p` is strictly inside (even-odd rule over all rings).
    pub fn contains(&self, p: P2) -> bool {
        let mut inside = false;
        for ring in self.rings() {
            let n = ring.len();
            for i in 0..n {
                let (a, b) = (ring[i], ring[(i + 1) % n]);
                if (a[1] > p[1]) != (b[1] > p[1]) {
                    let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                    if p[0] < x {
                        inside = !inside;
                    }
                }
            }
        }
        inside
    }
    /// Distance from `p` to the boundary (any ring).
    pub fn boundary_distance(&self, p: P2) -> f64 {
        self.edges()
            .map(|(a, b)| dist(p, closest_on_segment(p, a, b)))
            .fold(f64::INFINITY, f64::min)
    }
    /// Triangles covering the outer ring (ear clipping), as index triples into `outer`.
    /// Holes are not cut out (a roof over a courtyard stays closed).
    pub fn triangulate_outer(&self) -> Vec<[usize; 3]> {
        ear_clip(&self.outer)
    }
}

/// Drops a closing duplicate and consecutive duplicates, orients the ring.
fn normalize_ring(mut ring: Vec<P2>, ccw: bool) -> Option<Vec<P2>> {
    ring.dedup();
    if ring.len() > 1 && ring.first() == ring.last() {
        ring.pop();
    }
    if ring.len() < 3 {
        return None;
    }
    let a = signed_area2(&ring);
    if a == 0.0 || !a.is_finite() {
        return None;
    }
    if (a > 0.0) != ccw {
        ring.reverse();
    }
    Some(ring)
}

fn cross(o: P2, a: P2, b: P2) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Ear clipping of a counter-clockwise simple ring. O(n²) per ring: footprints are small.
/// Degenerate rings (self-intersecting) fall back to a fan over the remaining vertices.
fn ear_clip(ring: &[P2]) -> Vec<[usize; 3]> {
    let mut idx: Vec<usize> = (0..ring.len()).collect();
    let mut tris = Vec::with_capacity(ring.len().saturating_sub(2));
    while idx.len() > 3 {
        let n = idx.len();
        let ear = (0..n).find(|&i| {
            let (a, b, c) = (
                ring[idx[(i + n - 1) % n]],
                ring[idx[i]],
                ring[idx[(i + 1) % n]],
            );
            if cross(a, b, c) <= 0.0 {
                return false;
            }
            idx.iter().all(|&j| {
                let p = ring[j];
                p == a
                    || p == b
                    || p == c
                    || cross(a, b, p) < 0.0
                    || cross(b, c, p) < 0.0
                    || cross(c, a, p) < 0.0
            })
        });
        match ear {
            Some(i) => {
                tris.push([idx[(i + n - 1) % n], idx[i], idx[(i + 1) % n]]);
                idx.remove(i);
            }
            None => {
                for k in 1..n - 1 {
                    tris.push([idx[0], idx[k], idx[k + 1]]);
                }
                return tris;
            }
        }
    }
    if idx.len() == 3 {
        tris.push([idx[0], idx[1], idx[2]]);
    }
    tris
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_shape_area_contains_and_triangles() {
        // An L: 2x2 square minus its top-right 1x1 quarter, given clockwise and closed.
        let l = vec![
            [0.0, 0.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
            [0.0, 0.0],
        ];
        let p = Polygon::new(l, vec![]).unwrap();
        assert_eq!(p.outer.len(), 6);
        assert!((p.area() - 3.0).abs() < 1e-12);
        assert!(p.contains([0.5, 1.5]) && !p.contains([1.5, 1.5]));
        let tris = p.triangulate_outer();
        assert_eq!(tris.len(), 4);
        let area: f64 = tris
            .iter()
            .map(|t| cross(p.outer[t[0]], p.outer[t[1]], p.outer[t[2]]) / 2.0)
            .sum();
        assert!((area - 3.0).abs() < 1e-12);
        assert!((p.boundary_distance([0.5, 0.5]) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn holes_are_outside() {
        let sq = |a: f64, b: f64| vec![[a, a], [b, a], [b, b], [a, b]];
        let p = Polygon::new(sq(0.0, 10.0), vec![sq(4.0, 6.0)]).unwrap();
        assert!(p.contains([1.0, 1.0]) && !p.contains([5.0, 5.0]));
        assert!((p.area() - 96.0).abs() < 1e-9);
        assert!(Polygon::new(vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], vec![]).is_none());
    }
}
