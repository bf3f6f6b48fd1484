//! Routes on the street graphs: the fine track of a path and the time-optimal speed profile
//! along it.
//!
//! - [`Track`]: a planned path (on a [`FreeGraph`]) as world points at most [`TRACK_STEP`]
//!   apart on the ground (or bridge deck), with the node each point belongs to, a speed
//!   limit at each point, and the time the profile reaches it.
//! - Ground vehicles: [`Track::plan_vehicle`] runs a forward pass (traction, engine power,
//!   rolling resistance, drag, grade: [`GroundType::accel_limit`]) and a backward pass
//!   (braking), under the street limits and the corner speeds of
//!   [`GroundType::corner_speed`]. Its arrival time is the *discrete estimate*.
//! - Troops: [`Track::plan_walk`] gives each piece the Pandolf walking speed for the load and
//!   the grade ([`TroopParams::walking_speed`]).

use super::roads::{FreeGraph, RouteError};
use super::stretch::piece;
pub use super::stretch::{TRACK_STEP, dist3};
use crate::types::{GroundType, SpeedLimits, TroopParams};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::env::NodeId;
#[cfg(test)]
use vitro_site::geo::dist;
use vitro_site::site::Site;

/// A planned path as a fine polyline with its speed profile.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Track {
    /// World points, at most [`TRACK_STEP`] apart.
    pub pts: Vec<[f64; 3]>,
    /// Distance along the track at each point (3D), metres.
    pub s: Vec<f64>,
    /// Speed limit at each point (street limit, corner), m/s: before profiling.
    pub limit: Vec<f64>,
    /// Profile speed at each point, m/s.
    pub v: Vec<f64>,
    /// Profile time at each point, seconds from the start.
    pub t: Vec<f64>,
    /// The path's nodes with the index of their point, in order.
    pub nodes: Vec<(usize, NodeId)>,
}

impl Track {
    /// The points of `path` on the free graph of `mode`: each street segment's ground (or deck)
    /// path, resampled to [`TRACK_STEP`] (its [`Stretch`](super::stretch::Stretch), shared
    /// by every trip over it), with its street class's speed limit and the corner speeds
    /// left unset (infinite), and the pieces between the points. The ground speed limit is
    /// `limits` (`None`: no limit).
    fn geometry(
        site: &Site,
        roads: &FreeGraph,
        path: &[NodeId],
        limits: Option<&SpeedLimits>,
    ) -> Result<(Track, Pieces), RouteError> {
        let sg = site.map.streets(roads.mode);
        let Some(&first) = path.first() else {
            return Ok((Track::default(), Pieces::default()));
        };
        let start = sg.pos(first).ok_or(RouteError::NoNode(first))?;
        // Each step's stretch, its speed cap and the node it ends at, found first: the
        // track's lists are then sized once (grown a push at a time, their reallocations
        // and the fresh pages they touched were a third of planning a car's trip).
        let mut steps = Vec::with_capacity(path.len().saturating_sub(1));
        for w in path.windows(2) {
            let (a, b) = (w[0], w[1]);
            let edge = roads
                .graph
                .neighbors(a)
                .filter(|(t, _, _)| *t == b)
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .map(|(_, _, e)| *e)
                .ok_or(RouteError::NoPath { from: a, to: b })?;
            let seg = &sg.segments[edge.segment as usize];
            let stretch = roads
                .stretch(site, edge.segment as usize, edge.forward)
                .ok_or(RouteError::NoPath { from: a, to: b })?;
            let cap = limits.map_or(f64::INFINITY, |l| l.for_class(&seg.class));
            steps.push((stretch, cap, b));
        }
        let points = 1 + steps.iter().map(|(st, _, _)| st.pts.len()).sum::<usize>();
        let mut tr = Track {
            pts: Vec::with_capacity(points),
            s: Vec::with_capacity(points),
            limit: Vec::with_capacity(points),
            nodes: Vec::with_capacity(path.len()),
            ..Track::default()
        };
        let mut pieces = Pieces {
            heading: Vec::with_capacity(points - 1),
            run: Vec::with_capacity(points - 1),
        };
        let z0 = site.ground(site.to_world(start)).unwrap_or(0.0);
        let w0 = site.to_world(start);
        tr.pts.push([w0[0], w0[1], z0]);
        tr.limit.push(f64::INFINITY);
        tr.s.push(0.0);
        tr.nodes.push((0, first));
        for (stretch, cap, b) in steps {
            if let (Some(&prev), Some(&next)) = (tr.pts.last(), stretch.pts.first()) {
                // The piece from the track so far onto this stretch, then the stretch's own.
                let (h, r) = piece(prev, next);
                pieces.heading.push(h);
                pieces.run.push(r);
                let mut s = tr.s.last().copied().unwrap_or(0.0) + dist3(prev, next);
                tr.s.push(s);
                for &d in &stretch.len3 {
                    s += d;
                    tr.s.push(s);
                }
                pieces.heading.extend_from_slice(&stretch.heading);
                pieces.run.extend_from_slice(&stretch.run);
            }
            for &p in &stretch.pts {
                if let Some(last) = tr.limit.last_mut() {
                    *last = last.min(cap);
                }
                tr.pts.push(p);
                tr.limit.push(cap);
            }
            tr.nodes.push((tr.pts.len() - 1, b));
        }
        Ok((tr, pieces))
    }

    /// Plans `path` for a ground vehicle of type `ty`: street limits, corner speeds, then the
    /// forward (acceleration) and backward (braking) passes. Starts and ends at rest.
    pub fn plan_vehicle(
        site: &Site,
        roads: &FreeGraph,
        path: &[NodeId],
        ty: &GroundType,
        limits: &SpeedLimits,
    ) -> Result<Track, RouteError> {
        let (mut tr, pieces) = Self::geometry(site, roads, path, Some(limits))?;
        let n = tr.pts.len();
        let vmax = ty.max_speed();
        for l in &mut tr.limit {
            *l = l.min(vmax);
        }
        // Corner speeds at the vertices where the heading changes.
        for i in 1..n.saturating_sub(1) {
            let turn = wrap_angle(pieces.heading[i] - pieces.heading[i - 1]);
            if turn.abs() > 1e-6 {
                let room = turn_room(&pieces, i);
                tr.limit[i] = tr.limit[i].min(ty.corner_speed(turn, room));
            }
        }
        let mut v = vec![0.0; n];
        // Forward pass: v² grows by 2 a ds, a from power, traction, resistances and grade.
        for i in 1..n {
            let ds = tr.s[i] - tr.s[i - 1];
            let slope = rise_over_run(tr.pts[i - 1], tr.pts[i], pieces.run[i - 1]);
            let a = ty.accel_limit(v[i - 1], slope).max(0.0);
            let reach = libm::sqrt(v[i - 1] * v[i - 1] + 2.0 * a * ds);
            v[i] = reach.min(tr.limit[i]);
        }
        if let Some(last) = v.last_mut() {
            *last = 0.0;
        }
        // Backward pass: braking at max_decel.
        for i in (0..n.saturating_sub(1)).rev() {
            let ds = tr.s[i + 1] - tr.s[i];
            let reach = libm::sqrt(v[i + 1] * v[i + 1] + 2.0 * ty.max_decel * ds);
            v[i] = v[i].min(reach);
        }
        // A vehicle that cannot climb a grade at all crawls up at a walking pace instead of
        // never arriving: keep the profile positive away from the two ends (none on a track of
        // one point or two).
        let inner = 1..n.saturating_sub(1);
        if !inner.is_empty() {
            for (vi, li) in v[inner.clone()].iter_mut().zip(&tr.limit[inner]) {
                if *vi < 0.5 {
                    *vi = 0.5f64.min(*li);
                }
            }
        }
        tr.t = times(&tr.s, &v);
        tr.v = v;
        Ok(tr)
    }

    /// Plans `path` for a trooper carrying `load` kg: each piece at the Pandolf walking speed
    /// for its grade.
    pub fn plan_walk(
        site: &Site,
        roads: &FreeGraph,
        path: &[NodeId],
        troops: &TroopParams,
        load: f64,
    ) -> Result<Track, RouteError> {
        let (mut tr, pieces) = Self::geometry(site, roads, path, None)?;
        let n = tr.pts.len();
        let mut v = vec![0.0; n];
        let mut t = vec![0.0; n];
        for i in 1..n {
            let grade = 100.0 * rise_over_run(tr.pts[i - 1], tr.pts[i], pieces.run[i - 1]);
            let speed = troops.walking_speed(load, grade);
            v[i] = speed;
            t[i] = t[i - 1] + (tr.s[i] - tr.s[i - 1]) / speed;
            tr.limit[i] = speed;
        }
        if n > 1 {
            v[0] = v[1];
            tr.limit[0] = v[1];
        }
        tr.v = v;
        tr.t = t;
        Ok(tr)
    }

    /// Total length, metres.
    pub fn length(&self) -> f64 {
        self.s.last().copied().unwrap_or(0.0)
    }
    /// Profile time to the end, seconds (the discrete estimate).
    pub fn duration(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0)
    }
    /// The last node of the path.
    pub fn goal(&self) -> Option<NodeId> {
        self.nodes.last().map(|&(_, n)| n)
    }
    /// The index of the last point at or before distance `s` (binary search).
    pub fn index_at(&self, s: f64) -> usize {
        self.s.partition_point(|&x| x <= s).saturating_sub(1)
    }
    /// The point at distance `s` along the track (clamped to its ends).
    pub fn point_at(&self, s: f64) -> [f64; 3] {
        let Some(&last) = self.pts.last() else {
            return [0.0; 3];
        };
        if s >= self.length() {
            return last;
        }
        let i = self.index_at(s.max(0.0));
        let (a, b) = (self.pts[i], self.pts[(i + 1).min(self.pts.len() - 1)]);
        let l = self.s.get(i + 1).map_or(0.0, |&s1| s1 - self.s[i]);
        let t = if l > 0.0 {
            ((s - self.s[i]) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        [
            a[0] + t * (b[0] - a[0]),
            a[1] + t * (b[1] - a[1]),
            a[2] + t * (b[2] - a[2]),
        ]
    }
    /// The profile speed at distance `s`, interpolated in v² between points (exact for the
    /// constant-acceleration pieces the profile is made of).
    pub fn speed_at(&self, s: f64) -> f64 {
        if self.v.is_empty() {
            return 0.0;
        }
        if s >= self.length() {
            return self.v[self.v.len() - 1];
        }
        let i = self.index_at(s.max(0.0));
        let j = (i + 1).min(self.v.len() - 1);
        let l = self.s[j] - self.s[i];
        let t = if l > 0.0 {
            ((s - self.s[i]) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (self.v[i], self.v[j]);
        libm::sqrt(a * a + t * (b * b - a * a))
    }
    /// The node passed last at distance `s`.
    pub fn node_at(&self, s: f64) -> Option<NodeId> {
        let i = self.index_at(s);
        self.nodes
            .iter()
            .take_while(|&&(k, _)| k <= i)
            .last()
            .map(|&(_, n)| n)
    }
    /// Heading of the track (radians from east) at distance `s`.
    pub fn heading_at(&self, s: f64) -> f64 {
        let n = self.pts.len();
        if n < 2 {
            return 0.0;
        }
        let i = self.index_at(s).min(n - 2);
        let (a, b) = (self.pts[i], self.pts[i + 1]);
        libm::atan2(b[1] - a[1], b[0] - a[0])
    }
}

/// GoToNode / WalkToNode on a continuous level: the planned track and how far along it the
/// body is.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Follow {
    /// The goal node.
    pub goal: NodeId,
    /// Distance along the track reached, metres.
    pub s: f64,
    /// Index of the next track point to steer to.
    pub next: usize,
    /// The plan (not part of the state digest: it is a function of the command).
    #[serde(skip)]
    pub track: Arc<Track>,
}

/// Rise over run from `a` to `b` (0 for a vertical or zero step).
#[cfg(test)]
fn slope(a: [f64; 3], b: [f64; 3]) -> f64 {
    rise_over_run(a, b, dist([a[0], a[1]], [b[0], b[1]]))
}

/// [`slope`] from `a` to `b` with their horizontal distance `run` known.
#[inline]
fn rise_over_run(a: [f64; 3], b: [f64; 3], run: f64) -> f64 {
    if run > 1e-9 { (b[2] - a[2]) / run } else { 0.0 }
}

/// The pieces of a polyline: piece `k` goes from point `k` to point `k + 1`.
#[derive(Debug, Default, PartialEq)]
struct Pieces {
    /// Heading of each piece, radians from east.
    heading: Vec<f64>,
    /// Horizontal length of each piece, metres.
    run: Vec<f64>,
}

impl Pieces {
    /// The horizontal length of the pieces `ks` (in walking order) up to the first whose
    /// heading is not the first one's.
    #[inline]
    fn straight_run(&self, ks: impl Iterator<Item = usize>) -> f64 {
        let mut len = 0.0;
        let mut h0 = None;
        for k in ks {
            let h = self.heading[k];
            if !same_heading(h, *h0.get_or_insert(h)) {
                break;
            }
            len += self.run[k];
        }
        len
    }

    /// The pieces of `pts`, each worked out from its two points (what
    /// [`Track::geometry`] gives, built from stretches).
    #[cfg(test)]
    fn of(pts: &[[f64; 3]]) -> Self {
        let (heading, run) = pts.windows(2).map(|w| piece(w[0], w[1])).unzip();
        Pieces { heading, run }
    }
}

/// An angle in (-π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let r = a - tau * libm::floor((a + std::f64::consts::PI) / tau);
    if r <= -std::f64::consts::PI {
        r + tau
    } else {
        r
    }
}

/// Room for a fillet at vertex `i` of the polyline of `pieces`: half the shorter of the two
/// straight runs on either side (runs of collinear resampled points count as one).
fn turn_room(pieces: &Pieces, i: usize) -> f64 {
    // The run before vertex `i` ends with piece `i - 1`, the run after it starts with piece `i`.
    let before = pieces.straight_run((0..i).rev());
    let after = pieces.straight_run(i..pieces.heading.len());
    before.min(after) / 2.0
}

/// True if headings `h` and `h0` are within 1e-6 rad (NaN counts as the same: a run stops
/// only at a measured turn).
#[inline]
fn same_heading(h: f64, h0: f64) -> bool {
    let d = wrap_angle(h - h0).abs();
    d <= 1e-6 || d.is_nan()
}

/// Cumulative times of a profile: constant acceleration on each piece, so a piece takes
/// `2 ds / (v0 + v1)`.
fn times(s: &[f64], v: &[f64]) -> Vec<f64> {
    let mut t = vec![0.0; s.len()];
    for i in 1..s.len() {
        let ds = s[i] - s[i - 1];
        let vm = v[i - 1] + v[i];
        t[i] = t[i - 1] + if vm > 1e-9 { 2.0 * ds / vm } else { 0.0 };
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_wrap_into_half_open_range() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-12);
        assert!((wrap_angle(-2.0 * PI + 0.1) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn constant_acceleration_times() {
        // From rest at 2 m/s² over 4 m: v = 4 m/s, t = 2 s.
        let t = times(&[0.0, 4.0], &[0.0, 4.0]);
        assert!((t[1] - 2.0).abs() < 1e-12);
    }

    /// The room and corner turn as computed before [`Pieces`]: two `atan2` per step, at
    /// every vertex and along every run.
    fn reference(pts: &[[f64; 3]], i: usize) -> (f64, f64) {
        let heading = |a: [f64; 3], b: [f64; 3]| libm::atan2(b[1] - a[1], b[0] - a[0]);
        let run = |dir: i64| {
            let mut len = 0.0;
            let mut k = i as i64;
            let h0 = if dir < 0 {
                heading(pts[i - 1], pts[i])
            } else {
                heading(pts[i], pts[i + 1])
            };
            loop {
                let j = k + dir;
                if j < 0 || j as usize >= pts.len() {
                    break;
                }
                let (a, b) = (pts[k as usize], pts[j as usize]);
                let h = if dir < 0 {
                    heading(b, a)
                } else {
                    heading(a, b)
                };
                if wrap_angle(h - h0).abs() > 1e-6 {
                    break;
                }
                len += dist([a[0], a[1]], [b[0], b[1]]);
                k = j;
            }
            len
        };
        let turn = wrap_angle(heading(pts[i], pts[i + 1]) - heading(pts[i - 1], pts[i]));
        (turn, run(-1).min(run(1)) / 2.0)
    }

    #[test]
    fn pieces_give_the_same_bits_as_the_step_by_step_computation() {
        // A resampled polyline: straight runs (collinear points off by rounding), corners
        // both ways, a curve of short pieces, a U-turn, a zero-length piece, grades.
        let corners = [
            [0.0, 0.0],
            [37.3, 0.0],
            [37.3, 12.9],
            [20.1, 30.7],
            [22.0, 31.0],
            [23.5, 31.8],
            [24.6, 33.1],
            [25.0, 34.9],
            [25.0, 34.9],
            [-3.3, 60.2],
            [10.0, 60.2],
            [-7.5, 60.2],
        ];
        let mut pts = vec![[0.0, 0.0, 0.0]];
        for w in corners.windows(2) {
            let (p0, p1) = (w[0], w[1]);
            let n = (dist(p0, p1) / TRACK_STEP).ceil().max(1.0) as usize;
            for k in 1..=n {
                let t = k as f64 / n as f64;
                let (x, y) = (p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1]));
                pts.push([x, y, 0.03 * x - 0.01 * y]);
            }
        }
        let pieces = Pieces::of(&pts);
        let mut turns = 0;
        for i in 1..pts.len() - 1 {
            let turn = wrap_angle(pieces.heading[i] - pieces.heading[i - 1]);
            let (want_turn, want_room) = reference(&pts, i);
            assert_eq!(turn.to_bits(), want_turn.to_bits(), "turn at {i}");
            assert_eq!(
                turn_room(&pieces, i).to_bits(),
                want_room.to_bits(),
                "room at {i}"
            );
            turns += usize::from(turn.abs() > 1e-6);
            let (a, b) = (pts[i - 1], pts[i]);
            assert_eq!(
                rise_over_run(a, b, pieces.run[i - 1]).to_bits(),
                slope(a, b).to_bits()
            );
        }
        assert!(turns >= 8, "the polyline turns: {turns}");
    }

    #[test]
    fn room_spans_collinear_runs() {
        let pts: Vec<[f64; 3]> = (0..=10)
            .map(|i| [i as f64, 0.0, 0.0])
            .chain((1..=4).map(|j| [10.0, j as f64, 0.0]))
            .collect();
        // A right angle at x = 10: 10 m before, 4 m after: room 2 m.
        assert!((turn_room(&Pieces::of(&pts), 10) - 2.0).abs() < 1e-12);
    }
}
