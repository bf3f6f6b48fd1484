//! Air support of the HVT hunt: once its convoy task is over (the truck at the extraction
//! point), an aircraft flies over the place the hunt lead names in its
//! `Signal(`[`SEARCH`]`, "x y")` broadcasts, so that its camera (air vision: wide range, all
//! round) finds the target and its contact reports keep the pursuers' belief narrow.

use super::hunt::SEARCH;
use crate::radio::Radio;
use serde::{Deserialize, Serialize};

/// Radius of the orbit flown around the search point, metres.
const ORBIT_M: f64 = 120.0;

/// What an aircraft knows of the hunt: the latest search point, if any.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Overwatch {
    /// The latest search point (world x, y).
    pub point: Option<[f64; 2]>,
}

impl Overwatch {
    /// Takes a radio message; true if it named a new search point.
    pub fn hear(&mut self, body: &Radio) -> bool {
        let Radio::Signal(kind, args) = body else {
            return false;
        };
        if kind != SEARCH {
            return false;
        }
        let mut it = args.split_whitespace().map(str::parse::<f64>);
        let (Some(Ok(x)), Some(Ok(y)), None) = (it.next(), it.next(), it.next()) else {
            return false;
        };
        if !(x.is_finite() && y.is_finite()) || self.point == Some([x, y]) {
            return false;
        }
        self.point = Some([x, y]);
        true
    }

    /// An orbit around the search point: four points `ORBIT_M` from it, the `slot`-th
    /// aircraft starting a quarter turn after the previous one (so several aircraft spread
    /// round it). Ground heights are left to the caller.
    pub fn orbit(&self, slot: usize) -> Vec<[f64; 2]> {
        let Some([x, y]) = self.point else {
            return Vec::new();
        };
        (0..4)
            .map(|i| {
                let a = std::f64::consts::FRAC_PI_2 * ((i + slot) % 4) as f64;
                [x + ORBIT_M * libm::cos(a), y + ORBIT_M * libm::sin(a)]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hears_search_points_only() {
        let mut o = Overwatch::default();
        assert!(!o.hear(&Radio::Signal("arrived".into(), String::new())));
        assert!(!o.hear(&Radio::Signal(SEARCH.into(), "1.0".into())));
        assert!(!o.hear(&Radio::Signal(SEARCH.into(), "1 2 3".into())));
        assert!(!o.hear(&Radio::Signal(SEARCH.into(), "x 2".into())));
        assert!(!o.hear(&Radio::Signal(SEARCH.into(), "NaN 2".into())));
        assert!(o.point.is_none() && o.orbit(0).is_empty());
        assert!(o.hear(&Radio::Signal(SEARCH.into(), "10.5 -3".into())));
        assert_eq!(o.point, Some([10.5, -3.0]));
        // The same point again is no news.
        assert!(!o.hear(&Radio::Signal(SEARCH.into(), "10.5 -3".into())));
    }

    #[test]
    fn orbits_are_round_the_point_and_spread() {
        let o = Overwatch {
            point: Some([100.0, 200.0]),
        };
        let a = o.orbit(0);
        let b = o.orbit(1);
        assert_eq!(a.len(), 4);
        for p in &a {
            let r = libm::hypot(p[0] - 100.0, p[1] - 200.0);
            assert!((r - ORBIT_M).abs() < 1e-9);
        }
        assert!(libm::hypot(a[0][0] - b[0][0], a[0][1] - b[0][1]) > 1.0);
        assert!(libm::hypot(a[1][0] - b[0][0], a[1][1] - b[0][1]) < 1e-9);
    }
}
