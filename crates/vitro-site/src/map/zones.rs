//! Forbidden zones: buildings and water, each grown by a buffer, in an R-tree.
//!
//! A point is forbidden if it lies inside a zone's polygon or closer than the zone's buffer to
//! its boundary. The boundary itself (distance exactly equal to the buffer) is free.

use super::TownMap;
use crate::geo::{P2, Polygon, closest_on_segment, dist};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, Envelope, RTree, RTreeObject};
use serde::{Deserialize, Serialize};

/// Buffers around forbidden areas, metres.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ZoneConfig {
    /// Clearance kept from every building wall.
    pub building_buffer: f64,
    /// Clearance kept from every water edge.
    pub water_buffer: f64,
}

impl Default for ZoneConfig {
    /// 2 m from buildings, 1 m from water.
    fn default() -> Self {
        ZoneConfig {
            building_buffer: 2.0,
            water_buffer: 1.0,
        }
    }
}

/// What a zone is made of.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ZoneKind {
    /// A building footprint (index into [`TownMap::buildings`]).
    Building(usize),
    /// A water area (index into [`TownMap::water`]).
    Water(usize),
}

#[derive(Clone, Debug)]
struct Zone {
    poly: Polygon,
    buffer: f64,
    kind: ZoneKind,
}

impl Zone {
    fn forbids(&self, p: P2, tol: f64) -> bool {
        if self.poly.contains(p) {
            return self.buffer > 0.0 || self.poly.boundary_distance(p) > tol;
        }
        self.poly.boundary_distance(p) < self.buffer - tol
    }
}

/// How far a returned free point is pushed off the zone boundary, metres.
const NUDGE: f64 = 1e-3;

/// Forbidden zones of a town with a spatial index.
///
/// ```
/// use vitro_site::map::{ForbiddenZones, MapConfig, TownMap, ZoneConfig};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/maps/kotka.osm.pbf");
/// let town = TownMap::load(path, &MapConfig::default()).unwrap();
/// let zones = ForbiddenZones::new(&town, &ZoneConfig::default());
/// let inside = town.buildings[0].footprint.centroid();
/// assert!(zones.is_forbidden(inside));
/// let free = zones.nearest_free(inside);
/// assert!(!zones.is_forbidden(free));
/// ```
#[derive(Clone, Debug)]
pub struct ForbiddenZones {
    zones: Vec<Zone>,
    tree: RTree<GeomWithData<Rectangle<P2>, usize>>,
}

/// A piece of a buffered zone boundary.
#[derive(Copy, Clone, Debug)]
enum Piece {
    Seg(P2, P2),
    Arc(P2, f64),
}

impl Piece {
    fn closest(&self, p: P2) -> Option<P2> {
        match *self {
            Piece::Seg(a, b) => Some(closest_on_segment(p, a, b)),
            Piece::Arc(c, r) => {
                let d = dist(p, c);
                (d > 0.0).then(|| [c[0] + (p[0] - c[0]) * r / d, c[1] + (p[1] - c[1]) * r / d])
            }
        }
    }
}

impl ForbiddenZones {
    /// The zones of `town` (every building and water area) with the buffers of `config`.
    pub fn new(town: &TownMap, config: &ZoneConfig) -> Self {
        let b = town.buildings.iter().enumerate().map(|(i, b)| Zone {
            poly: b.footprint.clone(),
            buffer: config.building_buffer.max(0.0),
            kind: ZoneKind::Building(i),
        });
        let w = town.water.iter().enumerate().map(|(i, w)| Zone {
            poly: w.area.clone(),
            buffer: config.water_buffer.max(0.0),
            kind: ZoneKind::Water(i),
        });
        Self::from_zones(b.chain(w).collect())
    }

    fn from_zones(zones: Vec<Zone>) -> Self {
        let rects = zones
            .iter()
            .enumerate()
            .map(|(i, z)| {
                let [x0, y0, x1, y1] = z.poly.bbox();
                let r = z.buffer;
                GeomWithData::new(
                    Rectangle::from_corners([x0 - r, y0 - r], [x1 + r, y1 + r]),
                    i,
                )
            })
            .collect();
        ForbiddenZones {
            zones,
            tree: RTree::bulk_load(rects),
        }
    }

    /// Number of zones.
    pub fn len(&self) -> usize {
        self.zones.len()
    }
    /// True if there are no zones.
    pub fn is_empty(&self) -> bool {
        self.zones.is_empty()
    }

    fn near(&self, p: P2, r: f64) -> impl Iterator<Item = &Zone> + '_ {
        let env = AABB::from_corners([p[0] - r, p[1] - r], [p[0] + r, p[1] + r]);
        let mut hits: Vec<usize> = self
            .tree
            .locate_in_envelope_intersecting(env)
            .map(|g| g.data)
            .collect();
        hits.sort_unstable();
        hits.into_iter().map(|i| &self.zones[i])
    }

    fn forbidden_tol(&self, p: P2, tol: f64) -> bool {
        self.near(p, 0.0).any(|z| z.forbids(p, tol))
    }

    /// True if `p` lies in a zone or within its buffer.
    pub fn is_forbidden(&self, p: P2) -> bool {
        self.forbidden_tol(p, 0.0)
    }

    /// True if any of `samples + 1` evenly spaced points from `a` to `b` (both ends
    /// included) is forbidden: [`is_forbidden`](Self::is_forbidden) of each point
    /// `a + k / samples * (b - a)`, `k = 0..=samples`, with one R-tree query for the whole
    /// segment rather than one per point.
    ///
    /// ```
    /// # use vitro_site::map::{ForbiddenZones, MapConfig, TownMap, ZoneConfig};
    /// # let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    /// # let town = TownMap::load(format!("{root}/data/maps/kotka.osm.pbf"), &MapConfig::default()).unwrap();
    /// let zones = ForbiddenZones::new(&town, &ZoneConfig::default());
    /// let (a, b) = ([-400.0, -50.0], [400.0, 80.0]);
    /// let one_by_one = (0..=64).any(|k| {
    ///     let t = k as f64 / 64.0;
    ///     zones.is_forbidden([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
    /// });
    /// assert_eq!(zones.forbidden_along(a, b, 64), one_by_one);
    /// ```
    pub fn forbidden_along(&self, a: P2, b: P2, samples: usize) -> bool {
        let samples = samples.max(1);
        // The segment's box, padded so that rounding in a sample point cannot put it
        // outside: every zone whose box holds a sample is a candidate.
        let pad = 1e-6 * (1.0 + a[0].abs().max(a[1].abs()).max(b[0].abs()).max(b[1].abs()));
        let env = AABB::from_corners(
            [a[0].min(b[0]) - pad, a[1].min(b[1]) - pad],
            [a[0].max(b[0]) + pad, a[1].max(b[1]) + pad],
        );
        let near: Vec<(&Rectangle<P2>, &Zone)> = (self.tree)
            .locate_in_envelope_intersecting(env)
            .map(|g| (g.geom(), &self.zones[g.data]))
            .collect();
        if near.is_empty() {
            return false;
        }
        (0..=samples).any(|k| {
            let t = k as f64 / samples as f64;
            let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let at = AABB::from_point(p);
            (near.iter()).any(|(r, z)| r.envelope().intersects(&at) && z.forbids(p, 0.0))
        })
    }

    /// The zones `p` lies in (or within the buffer of), in index order.
    pub fn zones_at(&self, p: P2) -> Vec<ZoneKind> {
        self.near(p, 0.0)
            .filter(|z| z.forbids(p, 0.0))
            .map(|z| z.kind)
            .collect()
    }

    /// The free point nearest to `p` (`p` itself if free), pushed 1 mm off the zone edge.
    ///
    /// Exact up to that nudge: the nearest free point lies on the boundary of the union of
    /// buffered zones, which is made of offset edges and arcs around vertices; the answer is
    /// the projection of `p` onto one of those pieces or a crossing of two of them. The search
    /// radius doubles until a free candidate is found within it.
    pub fn nearest_free(&self, p: P2) -> P2 {
        if !self.is_forbidden(p) {
            return p;
        }
        let max_buf = self.zones.iter().map(|z| z.buffer).fold(0.0, f64::max);
        let world = self.tree.root().envelope();
        let (lo, hi) = (world.lower(), world.upper());
        let span = dist(lo, hi) + 2.0 * max_buf + 1.0;
        let mut r = 2.0 * max_buf + 8.0;
        loop {
            if let Some(q) = self.nearest_free_within(p, r) {
                return q;
            }
            if r > 2.0 * span {
                // Unreachable in exact arithmetic: outside every zone's box is free.
                return [hi[0] + max_buf + 1.0, p[1]];
            }
            r *= 2.0;
        }
    }

    fn nearest_free_within(&self, p: P2, r: f64) -> Option<P2> {
        let mut pieces = Vec::new();
        for z in self.near(p, r) {
            for (a, b) in z.poly.edges() {
                if z.buffer == 0.0 {
                    pieces.push(Piece::Seg(a, b));
                    continue;
                }
                let l = dist(a, b);
                if l > 0.0 {
                    let n = [(b[1] - a[1]) / l * z.buffer, -(b[0] - a[0]) / l * z.buffer];
                    pieces.push(Piece::Seg(
                        [a[0] + n[0], a[1] + n[1]],
                        [b[0] + n[0], b[1] + n[1]],
                    ));
                    pieces.push(Piece::Seg(
                        [a[0] - n[0], a[1] - n[1]],
                        [b[0] - n[0], b[1] - n[1]],
                    ));
                }
                pieces.push(Piece::Arc(a, z.buffer));
            }
        }
        pieces.retain(|pc| pc.closest(p).is_some_and(|q| dist(p, q) <= r));
        let mut cands: Vec<P2> = pieces.iter().filter_map(|pc| pc.closest(p)).collect();
        for i in 0..pieces.len() {
            for j in i + 1..pieces.len() {
                crossings(pieces[i], pieces[j], &mut cands);
            }
        }
        cands.retain(|&c| dist(p, c) <= r);
        cands.sort_by(|a, b| dist(p, *a).total_cmp(&dist(p, *b)));
        cands
            .into_iter()
            .filter(|&c| !self.forbidden_tol(c, 1e-7))
            .find_map(|c| self.nudge_free(p, c))
    }

    /// Pushes a boundary point `c` off the zones by `NUDGE`: away from `p` first, then
    /// around.
    fn nudge_free(&self, p: P2, c: P2) -> Option<P2> {
        let d = dist(p, c);
        let away = if d > 0.0 {
            [(c[0] - p[0]) / d, (c[1] - p[1]) / d]
        } else {
            [1.0, 0.0]
        };
        let base = libm::atan2(away[1], away[0]);
        (0..16).find_map(|k| {
            let t = base + (k as f64) * std::f64::consts::PI / 8.0;
            let q = [c[0] + NUDGE * libm::cos(t), c[1] + NUDGE * libm::sin(t)];
            (!self.is_forbidden(q)).then_some(q)
        })
    }
}

/// Appends the crossing points of two boundary pieces.
fn crossings(a: Piece, b: Piece, out: &mut Vec<P2>) {
    match (a, b) {
        (Piece::Seg(p, q), Piece::Seg(r, s)) => {
            let d1 = [q[0] - p[0], q[1] - p[1]];
            let d2 = [s[0] - r[0], s[1] - r[1]];
            let den = d1[0] * d2[1] - d1[1] * d2[0];
            if den.abs() < 1e-12 {
                return;
            }
            let w = [r[0] - p[0], r[1] - p[1]];
            let t = (w[0] * d2[1] - w[1] * d2[0]) / den;
            let u = (w[0] * d1[1] - w[1] * d1[0]) / den;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                out.push([p[0] + t * d1[0], p[1] + t * d1[1]]);
            }
        }
        (Piece::Seg(p, q), Piece::Arc(c, r)) | (Piece::Arc(c, r), Piece::Seg(p, q)) => {
            let d = [q[0] - p[0], q[1] - p[1]];
            let f = [p[0] - c[0], p[1] - c[1]];
            let aa = d[0] * d[0] + d[1] * d[1];
            if aa == 0.0 {
                return;
            }
            let bb = 2.0 * (f[0] * d[0] + f[1] * d[1]);
            let cc = f[0] * f[0] + f[1] * f[1] - r * r;
            let disc = bb * bb - 4.0 * aa * cc;
            if disc < 0.0 {
                return;
            }
            let sq = libm::sqrt(disc);
            for t in [(-bb - sq) / (2.0 * aa), (-bb + sq) / (2.0 * aa)] {
                if (0.0..=1.0).contains(&t) {
                    out.push([p[0] + t * d[0], p[1] + t * d[1]]);
                }
            }
        }
        (Piece::Arc(c1, r1), Piece::Arc(c2, r2)) => {
            let d = dist(c1, c2);
            if d == 0.0 || d > r1 + r2 || d < (r1 - r2).abs() {
                return;
            }
            let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
            let h = libm::sqrt((r1 * r1 - a * a).max(0.0));
            let e = [(c2[0] - c1[0]) / d, (c2[1] - c1[1]) / d];
            let m = [c1[0] + a * e[0], c1[1] + a * e[1]];
            out.push([m[0] - h * e[1], m[1] + h * e[0]]);
            out.push([m[0] + h * e[1], m[1] - h * e[0]]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Polygon {
        Polygon::new(vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]], vec![]).unwrap()
    }

    fn zones(polys: Vec<Polygon>, buffer: f64) -> ForbiddenZones {
        ForbiddenZones::from_zones(
            polys
                .into_iter()
                .enumerate()
                .map(|(i, poly)| Zone {
                    poly,
                    buffer,
                    kind: ZoneKind::Building(i),
                })
                .collect(),
        )
    }

    #[test]
    fn buffer_and_inside() {
        let z = zones(vec![square(0.0, 0.0, 10.0)], 2.0);
        assert!(z.is_forbidden([5.0, 5.0]));
        assert!(z.is_forbidden([11.9, 5.0]));
        assert!(!z.is_forbidden([12.1, 5.0]));
        // Corner: distance from (10,10) is the buffer radius, round.
        assert!(!z.is_forbidden([11.5, 11.5]));
        assert!(z.is_forbidden([11.4, 11.4]));
    }

    #[test]
    fn nearest_free_from_inside_and_between() {
        let z = zones(vec![square(0.0, 0.0, 10.0)], 2.0);
        let q = z.nearest_free([9.0, 5.0]);
        assert!(
            (q[0] - 12.0).abs() < 2e-3 && (q[1] - 5.0).abs() < 1e-9,
            "{q:?}"
        );
        // Two squares 3 m apart with a 2 m buffer: the gap is closed; from the gap the way
        // out is along the gap to its open end or straight out sideways.
        let z = zones(vec![square(0.0, 0.0, 10.0), square(13.0, 0.0, 10.0)], 2.0);
        let p = [11.5, 9.0];
        assert!(z.is_forbidden(p));
        let q = z.nearest_free(p);
        assert!(!z.is_forbidden(q));
        // Nearest exit: the point above the gap at distance 2 from both corners (10,10) and
        // (13,10): (11.5, 10 + sqrt(4 - 2.25)).
        let want = [11.5, 10.0 + (4.0f64 - 2.25).sqrt()];
        assert!(dist(q, want) < 2e-3, "{q:?} vs {want:?}");
    }

    #[test]
    fn nearest_free_is_never_farther_than_brute_force() {
        let z = zones(
            vec![
                square(0.0, 0.0, 10.0),
                square(12.0, 3.0, 6.0),
                square(4.0, 12.5, 8.0),
            ],
            1.5,
        );
        for (i, p) in [[5.0, 5.0], [11.0, 6.0], [8.0, 11.0], [15.0, 6.0]]
            .into_iter()
            .enumerate()
        {
            let q = z.nearest_free(p);
            assert!(!z.is_forbidden(q), "case {i}");
            // Brute force: the nearest free point on a fine polar grid.
            let mut best = f64::INFINITY;
            for ri in 1..=600 {
                let rr = ri as f64 * 0.02;
                for k in 0..720 {
                    let t = k as f64 * std::f64::consts::PI / 360.0;
                    let c = [p[0] + rr * libm::cos(t), p[1] + rr * libm::sin(t)];
                    if !z.is_forbidden(c) {
                        best = best.min(rr);
                    }
                }
                if best < f64::INFINITY {
                    break;
                }
            }
            assert!(
                dist(p, q) <= best + 2e-3,
                "case {i}: {} > {best}",
                dist(p, q)
            );
        }
    }

    #[test]
    fn along_a_segment_is_each_sample_point() {
        // A grid of buffered squares and segments in every direction, some grazing a
        // corner between two samples: the one-query answer is the point-by-point one.
        let polys = (0..5)
            .flat_map(|i| (0..5).map(move |j| square(30.0 * i as f64, 30.0 * j as f64, 12.0)))
            .collect();
        let z = zones(polys, 1.5);
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 170.0 - 20.0
        };
        let (mut hit, mut miss) = (0, 0);
        for _ in 0..2000 {
            let (a, b) = ([next(), next()], [next(), next()]);
            let n = (dist(a, b) / 3.0).ceil().max(1.0) as usize;
            let each = (0..=n).any(|k| {
                let t = k as f64 / n as f64;
                z.is_forbidden([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
            });
            assert_eq!(
                z.forbidden_along(a, b, n),
                each,
                "{a:?} -> {b:?}, {n} samples"
            );
            if each { hit += 1 } else { miss += 1 }
        }
        // Both answers occur often enough for the comparison to mean something.
        assert!(hit > 200 && miss > 200, "{hit} forbidden, {miss} free");
        // Short segments that fit between zones, and a point-like one.
        assert!(!z.forbidden_along([20.0, 20.0], [25.0, 25.0], 4));
        assert!(z.forbidden_along([5.0, 5.0], [5.0, 5.0], 1));
    }
}
