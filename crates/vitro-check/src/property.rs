//! The standard properties of the cross-level check.

use super::{Family, Property, Run, Verdict};
use vitro_site::site::Site;
use vitro_tactical::entity::Level;

/// The standard properties, in report order.
pub fn standard() -> Vec<Box<dyn Property>> {
    vec![
        Box::new(Arrives),
        Box::new(NeverForbidden),
        Box::new(NearEstimate),
        Box::new(Continuous { slack: 0.05 }),
        Box::new(HoldsAltitude { band: 3.0 }),
        Box::new(AboveMinSpeed),
    ]
}

/// The goal is reached. Value: the arrival time, seconds (NaN if none).
pub struct Arrives;

impl Property for Arrives {
    fn name(&self) -> &str {
        "arrives"
    }
    fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
        Some(Verdict {
            pass: run.arrival.is_some(),
            value: run.arrival.unwrap_or(f64::NAN),
            limit: "goal reached".into(),
        })
    }
}

/// A ground body (vehicle or trooper) never stands in a forbidden zone. Value: the number of
/// samples inside one. (For a physical vehicle, its reference point: the ground under the
/// chassis centre.)
pub struct NeverForbidden;

impl Property for NeverForbidden {
    fn name(&self) -> &str {
        "never forbidden"
    }
    fn evaluate(&self, run: &Run, site: &Site) -> Option<Verdict> {
        if !matches!(run.family, Family::Ground | Family::Troop) {
            return None;
        }
        let inside = run
            .samples
            .iter()
            .filter(|s| site.is_forbidden([s.pos[0], s.pos[1]]))
            .count();
        Some(Verdict {
            pass: inside == 0,
            value: inside as f64,
            limit: "0 samples in a zone".into(),
        })
    }
}

/// The tolerance on the arrival time at `level` of `family`, relative and absolute (s),
/// with why.
pub fn tolerance(family: Family, level: Level) -> (f64, f64) {
    match (family, level) {
        // The same speed profile integrated in 0.1 s steps.
        (Family::Ground, Level::Interpolated) => (0.02, 2.0),
        // A controller tracking the profile on a rigid body with tyres and suspension: lags
        // when accelerating and in corners.
        (Family::Ground, _) => (0.12, 5.0),
        // Turning on the spot at corners.
        (Family::Troop, _) => (0.03, 5.0),
        // Lattice maneuvers zig-zag over the cells; the kinematic aircraft flies straight
        // but turns on a radius.
        (Family::Ctol, _) => (0.15, 10.0),
        // The lattice has no acceleration: the rigid body accelerates, brakes at each
        // corner and stops at the end.
        (Family::Vtol, _) => (0.25, 15.0),
    }
}

/// The arrival time is within [`tolerance`] of the discrete estimate (the reference
/// level's arrival). Value: the relative difference `(t − t_ref) / t_ref`. Not applied to
/// the reference level itself.
pub struct NearEstimate;

impl Property for NearEstimate {
    fn name(&self) -> &str {
        "arrival near estimate"
    }
    fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
        let reference = run.reference?;
        let (rel, abs) = tolerance(run.family, run.level);
        let limit = format!("|t - {reference:.1} s| <= {:.0}% + {abs} s", rel * 100.0);
        Some(match run.arrival {
            Some(t) => Verdict {
                pass: (t - reference).abs() <= rel * reference + abs,
                value: (t - reference) / reference,
                limit,
            },
            None => Verdict {
                pass: false,
                value: f64::NAN,
                limit,
            },
        })
    }
}

/// No jump in the trajectory is longer (in plan) than the type's top speed times the time
/// between the samples plus `slack` metres. Value: the worst ratio of a jump to its bound
/// (at most 1 when it holds).
pub struct Continuous {
    /// Allowance for rounding, metres.
    pub slack: f64,
}

impl Property for Continuous {
    fn name(&self) -> &str {
        "continuous"
    }
    fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
        let worst = run
            .samples
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                let jump = libm::hypot(b.pos[0] - a.pos[0], b.pos[1] - a.pos[1]);
                jump / (run.max_speed * (b.t - a.t) + self.slack)
            })
            .fold(0.0, f64::max);
        Some(Verdict {
            pass: worst <= 1.0,
            value: worst,
            limit: format!("jump <= {:.1} m/s x dt + {} m", run.max_speed, self.slack),
        })
    }
}

/// A helicopter stays within `band` metres of its commanded altitude. Value: the largest
/// deviation, metres.
pub struct HoldsAltitude {
    /// Allowed deviation, metres.
    pub band: f64,
}

impl Property for HoldsAltitude {
    fn name(&self) -> &str {
        "holds altitude"
    }
    fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
        if run.family != Family::Vtol {
            return None;
        }
        let z = run.altitude?;
        let worst = run
            .samples
            .iter()
            .map(|s| (s.pos[2] - z).abs())
            .fold(0.0, f64::max);
        Some(Verdict {
            pass: worst <= self.band,
            value: worst,
            limit: format!("<= {} m from {z:.1} m", self.band),
        })
    }
}

/// A fixed-wing aircraft never flies below its minimum speed. Value: the lowest speed, m/s.
pub struct AboveMinSpeed;

impl Property for AboveMinSpeed {
    fn name(&self) -> &str {
        "above min speed"
    }
    fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
        let min = run.min_speed?;
        let lowest = run
            .samples
            .iter()
            .map(|s| s.speed)
            .fold(f64::INFINITY, f64::min);
        Some(Verdict {
            pass: lowest >= min - 1e-9,
            value: lowest,
            limit: format!(">= {min} m/s"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Sample;

    fn run(samples: &[(f64, f64, f64)]) -> Run {
        Run {
            entity: "test".into(),
            family: Family::Ctol,
            level: Level::Kinematic,
            samples: samples
                .iter()
                .map(|&(t, x, speed)| Sample {
                    t,
                    pos: [x, 0.0, 100.0],
                    speed,
                })
                .collect(),
            arrival: Some(110.0),
            reference: Some(100.0),
            max_speed: 10.0,
            min_speed: Some(5.0),
            altitude: Some(101.0),
            sim_seconds: 0.0,
            wall_seconds: 0.0,
            events: 0,
        }
    }

    fn site() -> Site {
        let map = vitro_site::map::TownMap::from_buildings(vec![]);
        let t = vitro_site::terrain::Terrain::flat(10, 10, 10.0, 0.0).unwrap();
        Site::new(map, t, &vitro_site::site::SiteConfig::default()).unwrap()
    }

    #[test]
    fn jumps_faster_than_the_top_speed_fail() {
        let s = site();
        let ok = run(&[(0.0, 0.0, 6.0), (1.0, 10.0, 6.0), (3.0, 30.0, 6.0)]);
        let v = Continuous { slack: 0.05 }.evaluate(&ok, &s).unwrap();
        assert!(v.pass && v.value < 1.0);
        let bad = run(&[(0.0, 0.0, 6.0), (1.0, 10.2, 6.0)]);
        assert!(!Continuous { slack: 0.05 }.evaluate(&bad, &s).unwrap().pass);
    }

    #[test]
    fn min_speed_and_estimate_and_scope() {
        let s = site();
        let r = run(&[(0.0, 0.0, 6.0), (1.0, 5.0, 4.9)]);
        let v = AboveMinSpeed.evaluate(&r, &s).unwrap();
        assert!(!v.pass && v.value == 4.9);
        // 10 % late against a 15 % + 10 s tolerance.
        let v = NearEstimate.evaluate(&r, &s).unwrap();
        assert!(v.pass && (v.value - 0.1).abs() < 1e-12);
        // Altitude and zones apply to helicopters and ground bodies only.
        assert!(HoldsAltitude { band: 3.0 }.evaluate(&r, &s).is_none());
        assert!(NeverForbidden.evaluate(&r, &s).is_none());
        let mut h = r.clone();
        h.family = Family::Vtol;
        let v = HoldsAltitude { band: 3.0 }.evaluate(&h, &s).unwrap();
        assert!(v.pass && v.value == 1.0);
        h.arrival = None;
        assert!(!Arrives.evaluate(&h, &s).unwrap().pass);
        assert!(!NearEstimate.evaluate(&h, &s).unwrap().pass);
    }
}
