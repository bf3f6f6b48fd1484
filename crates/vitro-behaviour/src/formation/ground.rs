//! How the leader tells a street from open ground (see the [module docs](super)): the free
//! distance across its route, left and right, at a few points ahead.

use super::FormationParams;
use super::sense::SideClearance;
use serde::{Deserialize, Serialize};
use vitro::sim::Context;
use vitro_site::geo::{P2, dist};
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::Message;

/// Where the leader probes the ground, metres ahead along its route.
pub const PROBES: [f64; 4] = [0.0, 5.0, 10.0, 15.0];

/// What the ground ahead of the leader is (see the [module docs](super)).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Ground {
    /// Walls close on both sides.
    Narrow,
    /// Walls on both sides.
    Street,
    /// Not walled in on both sides.
    Open,
}

impl Ground {
    /// The name in the leader program: `narrow`, `street`, `open`.
    pub fn name(self) -> &'static str {
        match self {
            Ground::Narrow => "narrow",
            Ground::Street => "street",
            Ground::Open => "open",
        }
    }
}

/// The probes along a route (`pts`, the next point to reach `next`) for a body at `me`:
/// where it stands and [`PROBES`] metres further along, each with the route's direction
/// there (`heading` where the route gives none).
pub(crate) fn along(pts: &[[f64; 3]], next: usize, me: P2, heading: f64) -> Vec<(P2, f64)> {
    let mut probes = vec![(me, heading)];
    let mut along = 0.0;
    let mut prev = me;
    let mut marks = PROBES.iter().skip(1).peekable();
    for i in next.min(pts.len())..pts.len() {
        let q = [pts[i][0], pts[i][1]];
        along += dist(prev, q);
        prev = q;
        while marks.peek().is_some_and(|&&m| m <= along) {
            marks.next();
            let a = pts[i.saturating_sub(1)];
            let b = pts[(i + 1).min(pts.len() - 1)];
            let dir = if dist([a[0], a[1]], [b[0], b[1]]) > 1e-9 {
                libm::atan2(b[1] - a[1], b[0] - a[0])
            } else {
                heading
            };
            probes.push((q, dir));
        }
    }
    if let Some(first) = probes.get(1).map(|&(_, d)| d) {
        probes[0].1 = first;
    }
    probes
}

/// The probes straight ahead of a body at `me` facing `heading`.
pub(crate) fn ahead(me: P2, heading: f64) -> Vec<(P2, f64)> {
    let (s, c) = (libm::sin(heading), libm::cos(heading));
    PROBES
        .iter()
        .map(|&d| ([me[0] + d * c, me[1] + d * s], heading))
        .collect()
}

/// The ground at `probes`: narrow if two or more are narrow, a street if two or more are
/// walled in, open if none is, `previous` with a single walled probe of several.
pub(crate) fn look<M: Message>(
    cx: &mut Context<'_, Tactical<M>>,
    probes: &[(P2, f64)],
    params: &FormationParams,
    previous: Ground,
) -> Ground {
    let reach = params.street_reach;
    let (mut narrow, mut walled) = (0, 0);
    for &(at, heading) in probes {
        let [l, r] = cx.sense(&SideClearance { at, heading, reach });
        if l < reach && r < reach {
            walled += 1;
            if l + r <= params.narrow_width {
                narrow += 1;
            }
        }
    }
    let need = probes.len().min(2);
    if narrow >= need {
        Ground::Narrow
    } else if walled >= need {
        Ground::Street
    } else if walled == 0 {
        Ground::Open
    } else {
        // One walled probe of several: not enough to call it a street, nor to leave one.
        previous
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probes_follow_the_route() {
        // A route east along y = 0, then north up x = 10, points a metre apart.
        let mut pts: Vec<[f64; 3]> = (0..=10).map(|x| [f64::from(x), 0.0, 0.0]).collect();
        pts.extend((1..=20).map(|y| [10.0, f64::from(y), 0.0]));
        let p = along(&pts, 1, [0.0, 0.0], 0.0);
        assert_eq!(p.len(), 4);
        assert_eq!(p[0], ([0.0, 0.0], 0.0));
        assert_eq!(p[1].0, [5.0, 0.0]);
        assert_eq!(p[2].0, [10.0, 0.0]);
        // 15 m along: 5 m up the northward leg, looking north.
        assert_eq!(p[3].0, [10.0, 5.0]);
        assert!((p[3].1 - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Near the end of the route: fewer probes.
        assert_eq!(along(&pts, 25, [10.0, 14.0], 1.0).len(), 2);
        assert_eq!(along(&pts, 28, [10.0, 17.0], 1.0).len(), 1);
        let a = ahead([1.0, 1.0], std::f64::consts::FRAC_PI_2);
        assert!((a[3].0[1] - 16.0).abs() < 1e-12 && (a[3].0[0] - 1.0).abs() < 1e-12);
    }
}
