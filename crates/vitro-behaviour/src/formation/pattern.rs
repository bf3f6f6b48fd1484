//! Formation patterns, the leader's trail, and where each member's slot is.

use serde::{Deserialize, Serialize};
use vitro_site::geo::{P2, dist};

/// A formation pattern.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Pattern {
    /// Single file behind the leader.
    File,
    /// A column of twos behind the leader: pairs half a spacing either side of its trail.
    Column,
    /// Line abreast: members alternately right and left of the leader.
    Line,
    /// A wedge (arrowhead) with the leader at its point.
    Wedge,
}

impl Pattern {
    /// Every pattern.
    pub const ALL: [Pattern; 4] = [
        Pattern::File,
        Pattern::Column,
        Pattern::Line,
        Pattern::Wedge,
    ];

    /// The name in rule programs and messages: `file`, `column`, `line`, `wedge`.
    pub fn name(self) -> &'static str {
        match self {
            Pattern::File => "file",
            Pattern::Column => "column",
            Pattern::Line => "line",
            Pattern::Wedge => "wedge",
        }
    }

    /// The pattern called `name`.
    pub fn from_name(name: &str) -> Option<Pattern> {
        Pattern::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The slot of member `k` (1, 2, ...; 0 reads as 1) in the leader's frame, metres
    /// `(forward, left)`, at `spacing` metres between neighbours:
    ///
    /// - file: `(-k s, 0)`;
    /// - column: pair `r = ⌈k/2⌉` at `(-r s, ∓s/2)` (odd k right, even k left);
    /// - line: `(0, ∓r s)`;
    /// - wedge: `(-r s, ∓r s)`.
    ///
    /// ```
    /// use vitro_behaviour::formation::Pattern;
    /// assert_eq!(Pattern::Wedge.offset(3, 5.0), [-10.0, -10.0]);
    /// assert_eq!(Pattern::Column.offset(2, 4.0), [-4.0, 2.0]);
    /// ```
    pub fn offset(self, k: usize, spacing: f64) -> P2 {
        let k = k.max(1);
        let row = k.div_ceil(2) as f64;
        let side = if k % 2 == 1 { -1.0 } else { 1.0 };
        match self {
            Pattern::File => [-(k as f64) * spacing, 0.0],
            Pattern::Column => [-row * spacing, side * spacing / 2.0],
            Pattern::Line => [0.0, side * row * spacing],
            Pattern::Wedge => [-row * spacing, side * row * spacing],
        }
    }
}

impl std::fmt::Display for Pattern {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Minimum spacing of trail points, metres.
const TRAIL_STEP: f64 = 0.5;

/// The way the leader walked: its recent positions, oldest first, kept up to a length.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trail {
    pts: Vec<P2>,
}

impl Trail {
    /// An empty trail.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records the leader at `p` (if it moved at least half a metre), keeping at most `keep`
    /// metres of trail.
    pub fn record(&mut self, p: P2, keep: f64) {
        if self.pts.last().is_some_and(|&q| dist(p, q) < TRAIL_STEP) {
            return;
        }
        self.pts.push(p);
        let mut len = 0.0;
        let mut cut = 0;
        for i in (1..self.pts.len()).rev() {
            len += dist(self.pts[i], self.pts[i - 1]);
            if len > keep {
                cut = i - 1;
                break;
            }
        }
        if cut > 0 {
            self.pts.drain(..cut);
        }
    }

    /// The points, oldest first.
    pub fn points(&self) -> &[P2] {
        &self.pts
    }

    /// Forgets the points after the first `n`.
    pub fn truncate(&mut self, n: usize) {
        self.pts.truncate(n);
    }

    /// The point `back` metres behind `from` along the trail (walking from `from` to the
    /// newest point, then to older ones), with the direction of travel there (radians from
    /// east); straight back along `heading` beyond the trail's oldest point.
    pub fn behind(&self, from: P2, heading: f64, back: f64) -> (P2, f64) {
        let mut here = from;
        let mut dir = heading;
        let mut left = back.max(0.0);
        for &q in self.pts.iter().rev() {
            let d = dist(here, q);
            if d < 1e-9 {
                continue;
            }
            // Travel direction on this piece: from q (older) to here (newer).
            dir = libm::atan2(here[1] - q[1], here[0] - q[0]);
            if d >= left {
                let f = left / d;
                return (
                    [
                        here[0] + f * (q[0] - here[0]),
                        here[1] + f * (q[1] - here[1]),
                    ],
                    dir,
                );
            }
            left -= d;
            here = q;
        }
        (
            [
                here[0] - left * libm::cos(dir),
                here[1] - left * libm::sin(dir),
            ],
            dir,
        )
    }
}

/// Where member `k`'s slot is, before obstacles, for a leader at `leader` with `heading` who
/// walked `trail`: `(base, slot)`, the slot and the point of the leader's way it is measured
/// from.
///
/// With a `facing` (the bearing to a threat), the slot is the rigid offset in the frame
/// turned to `facing`, from the leader. Without, a slot behind the leader (`forward < 0`) is
/// `left` metres across the trail from its base, `|forward|` metres back along the trail; a
/// slot abreast or ahead is the rigid offset in the frame of the leader's heading.
pub fn slot_point(
    pattern: Pattern,
    k: usize,
    spacing: f64,
    leader: P2,
    heading: f64,
    trail: &Trail,
    facing: Option<f64>,
) -> (P2, P2) {
    let [fwd, left] = pattern.offset(k, spacing);
    match facing {
        Some(f) => (leader, across(leader, f, fwd, left)),
        None if fwd < 0.0 => {
            let (p, d) = trail.behind(leader, heading, -fwd);
            (p, across(p, d, 0.0, left))
        }
        None => (leader, across(leader, heading, fwd, left)),
    }
}

/// `p` moved `fwd` metres along `dir` and `left` metres to its left.
fn across(p: P2, dir: f64, fwd: f64, left: f64) -> P2 {
    let (s, c) = (libm::sin(dir), libm::cos(dir));
    [p[0] + fwd * c - left * s, p[1] + fwd * s + left * c]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn near(a: P2, b: P2) -> bool {
        dist(a, b) < 1e-9
    }

    #[test]
    fn every_pattern_keeps_members_a_spacing_apart() {
        for p in Pattern::ALL {
            for n in 1..=6 {
                // The leader is slot 0 at the origin.
                let mut pts = vec![[0.0, 0.0]];
                pts.extend((1..=n).map(|k| p.offset(k, 5.0)));
                for i in 0..pts.len() {
                    for j in 0..i {
                        let d = dist(pts[i], pts[j]);
                        assert!(
                            d >= 5.0 - 1e-9,
                            "{p} with {n}: slots {j} and {i} {d} m apart"
                        );
                    }
                }
            }
            assert_eq!(Pattern::from_name(p.name()), Some(p));
        }
    }

    #[test]
    fn pattern_shapes() {
        let s = 4.0;
        // File: on the axis, behind, one spacing per member.
        for k in 1..=4 {
            assert_eq!(Pattern::File.offset(k, s), [-(k as f64) * s, 0.0]);
        }
        // Line: abreast, right then left, outward.
        let line: Vec<P2> = (1..=4).map(|k| Pattern::Line.offset(k, s)).collect();
        assert_eq!(line, [[0.0, -4.0], [0.0, 4.0], [0.0, -8.0], [0.0, 8.0]]);
        // Wedge: each row farther back and farther out.
        let wedge: Vec<P2> = (1..=4).map(|k| Pattern::Wedge.offset(k, s)).collect();
        assert_eq!(
            wedge,
            [[-4.0, -4.0], [-4.0, 4.0], [-8.0, -8.0], [-8.0, 8.0]]
        );
        // Column: pairs behind, half a spacing either side.
        let col: Vec<P2> = (1..=4).map(|k| Pattern::Column.offset(k, s)).collect();
        assert_eq!(col, [[-4.0, -2.0], [-4.0, 2.0], [-8.0, -2.0], [-8.0, 2.0]]);
    }

    #[test]
    fn rigid_slots_turn_with_the_frame() {
        let t = Trail::new();
        // Facing north: behind is south, right is east.
        let (b, w) = slot_point(Pattern::Wedge, 1, 5.0, [10.0, 20.0], FRAC_PI_2, &t, None);
        assert!(near(b, [10.0, 15.0]), "{b:?}");
        assert!(near(w, [15.0, 15.0]), "{w:?}");
        // Line facing a threat to the west, whatever the heading: members north and south.
        let l1 = slot_point(
            Pattern::Line,
            1,
            5.0,
            [0.0, 0.0],
            0.3,
            &t,
            Some(std::f64::consts::PI),
        )
        .1;
        let l2 = slot_point(
            Pattern::Line,
            2,
            5.0,
            [0.0, 0.0],
            0.3,
            &t,
            Some(std::f64::consts::PI),
        )
        .1;
        assert!(
            near(l1, [0.0, 5.0]) && near(l2, [0.0, -5.0]),
            "{l1:?} {l2:?}"
        );
    }

    #[test]
    fn slots_behind_follow_the_trail_round_a_corner() {
        // The leader walked north up x = 0, then turned east: it is at (6, 10).
        let mut t = Trail::new();
        for y in 0..=10 {
            t.record([0.0, f64::from(y)], 100.0);
        }
        for x in 1..=6 {
            t.record([f64::from(x), 10.0], 100.0);
        }
        // 10 m back: 6 m back along y = 10 to the corner, then 4 m down x = 0.
        let f = slot_point(Pattern::File, 2, 5.0, [6.0, 10.0], 0.0, &t, None).1;
        assert!(near(f, [0.0, 6.0]), "{f:?}");
        // Column member 1: 5 m back, still on the eastward piece, 2.5 m right (south).
        let (b1, c1) = slot_point(Pattern::Column, 1, 5.0, [6.0, 10.0], 0.0, &t, None);
        assert!(near(b1, [1.0, 10.0]), "{b1:?}");
        assert!(near(c1, [1.0, 7.5]), "{c1:?}");
        // Column member 3: 10 m back, on the northward piece, 2.5 m right (east).
        let c3 = slot_point(Pattern::Column, 3, 5.0, [6.0, 10.0], 0.0, &t, None).1;
        assert!(near(c3, [2.5, 6.0]), "{c3:?}");
        // Beyond the trail: straight back along the oldest piece.
        let far = slot_point(Pattern::File, 6, 5.0, [6.0, 10.0], 0.0, &t, None).1;
        assert!(near(far, [0.0, -14.0]), "{far:?}");
    }

    #[test]
    fn trail_keeps_its_length() {
        let mut t = Trail::new();
        for i in 0..100 {
            t.record([f64::from(i), 0.0], 20.0);
        }
        let len: f64 = t.points().windows(2).map(|w| dist(w[0], w[1])).sum();
        assert!((20.0..=21.0).contains(&len), "{len}");
        // Points closer than half a metre are not recorded.
        let n = t.points().len();
        t.record([99.2, 0.0], 20.0);
        assert_eq!(t.points().len(), n);
    }
}
