//! Stretches: one street segment's part of a planned track, in one direction, worked out
//! once and shared by every trip over the segment.
//!
//! A track ([`Track`](super::route::Track)) is the path's street segments one after the
//! other, each resampled to [`TRACK_STEP`] on the ground (or its bridge deck), with the
//! heading and length of every piece between consecutive points. All of that but the piece
//! joining two segments depends on the segment and the direction alone, and sampling the
//! terrain and the trigonometry were most of the cost of planning a car's trip. A
//! [`Stretches`] table keeps each (segment, direction)'s [`Stretch`] from its first use on:
//! a track built from stretches is the same, bit for bit, as one computed point by point
//! (the same operations on the same numbers).

use std::sync::OnceLock;
use vitro_site::geo::dist;
use vitro_site::map::Mode;
use vitro_site::site::Site;

/// Largest spacing of track points, metres.
pub const TRACK_STEP: f64 = 1.0;

/// Distance between two 3D points.
pub fn dist3(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
}

/// The heading (radians from east) and horizontal length of the piece from `a` to `b`.
#[inline]
pub(crate) fn piece(a: [f64; 3], b: [f64; 3]) -> (f64, f64) {
    (
        libm::atan2(b[1] - a[1], b[0] - a[0]),
        dist([a[0], a[1]], [b[0], b[1]]),
    )
}

/// A street segment's points on a track in one direction, and the pieces between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stretch {
    /// Each piece of the segment's 3D path ([`Site::segment_path`]) resampled to at most
    /// [`TRACK_STEP`] apart, without the path's first point (the track's previous point:
    /// the node it comes from).
    pub pts: Vec<[f64; 3]>,
    /// Heading of piece `j`, from point `j` to point `j + 1`, radians from east.
    pub heading: Vec<f64>,
    /// Horizontal length of piece `j`, metres.
    pub run: Vec<f64>,
    /// 3D length of piece `j`, metres.
    pub len3: Vec<f64>,
}

impl Stretch {
    /// Segment `segment` of the `mode` streets of `site`, from its first point to its last
    /// (`forward`) or back; empty if there is no such segment.
    pub fn of(site: &Site, mode: Mode, segment: usize, forward: bool) -> Self {
        let Some(seg) = site.map.streets(mode).segments.get(segment) else {
            return Stretch::default();
        };
        let mut path = site.segment_path(mode, segment).unwrap_or_default();
        if !forward {
            path.reverse();
        }
        let mut pts = Vec::new();
        for q in path.windows(2) {
            let (p0, p1) = (q[0], q[1]);
            let l = dist([p0[0], p0[1]], [p1[0], p1[1]]);
            let n = (l / TRACK_STEP).ceil().max(1.0) as usize;
            for k in 1..=n {
                let t = k as f64 / n as f64;
                let x = p0[0] + t * (p1[0] - p0[0]);
                let y = p0[1] + t * (p1[1] - p0[1]);
                let z = if seg.bridge {
                    p0[2] + t * (p1[2] - p0[2])
                } else {
                    site.ground([x, y]).unwrap_or(p0[2] + t * (p1[2] - p0[2]))
                };
                pts.push([x, y, z]);
            }
        }
        let (mut heading, mut run, mut len3) = (Vec::new(), Vec::new(), Vec::new());
        for w in pts.windows(2) {
            let (h, r) = piece(w[0], w[1]);
            heading.push(h);
            run.push(r);
            len3.push(dist3(w[0], w[1]));
        }
        Stretch {
            pts,
            heading,
            run,
            len3,
        }
    }
}

/// The stretches of one mode's segments, each worked out on first use (thread-safe: the
/// roads are shared by the runs of a batch).
#[derive(Clone, Debug, Default)]
pub struct Stretches(Vec<[OnceLock<Stretch>; 2]>);

impl Stretches {
    /// Room for `segments` segments, none worked out yet.
    pub fn new(segments: usize) -> Self {
        Stretches((0..segments).map(|_| Default::default()).collect())
    }

    /// The stretch of `segment` in direction `forward`, on `site` (the site these
    /// stretches are for) and its `mode` streets; `None` beyond the segments.
    pub fn get(&self, site: &Site, mode: Mode, segment: usize, forward: bool) -> Option<&Stretch> {
        let cell = &self.0.get(segment)?[usize::from(forward)];
        Some(cell.get_or_init(|| Stretch::of(site, mode, segment, forward)))
    }
}
