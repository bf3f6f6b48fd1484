//! Calibration of the aircraft's discrete level (the lattice) from their continuous levels:
//! the fixed-wing UAV's kinematic level, the helicopters' rotor dynamics.
//!
//! # What the lattice gets wrong
//!
//! A lattice maneuver takes its cell step at the commanded speed: the aircraft is at cruise
//! speed from the first instant, turns 45° per cell at no cost, and a helicopter stops dead
//! in the last cell. The continuous levels accelerate from a hover (the helicopter's tilt
//! limit bounds its acceleration), brake before a sharp turn (a helicopter slows to
//! `cruise × cos(turn)` at a waypoint) or fly round it on a bounded bank (the fixed-wing
//! aircraft overshoots and turns back on its turn circle, and a waypoint behind it costs a
//! loop), climb at a bounded rate with a lag, and brake to a stop at the last waypoint; and
//! the lattice zig-zags over its cells where the continuous aircraft flies straight.
//!
//! # The model
//!
//! A waypoint command's concrete flight time is fitted, per aircraft type, as
//!
//! ```text
//! T = alpha * T_profile + beta * rest + kappa * turn_rad + gamma * vertical_m
//!     + delta * start_turn_rad
//! ```
//!
//! with `T_profile` the route's time at the commanded speed (each leg its horizontal length
//! over the speed, or its height change over the lattice's climb rate if longer), `rest` 1
//! for a start from a hover, `turn_rad` the route's heading changes at its waypoints,
//! `vertical_m` the metres climbed and descended between them, and `start_turn_rad` the turn
//! from the aircraft's heading onto the first leg ([`AirFeatures`]). Each term is a cost the
//! lattice leaves out: acceleration and the stop (beta), the turns at waypoints (kappa),
//! climbs (gamma), the turn onto the route (delta); alpha takes the zig-zag and the cruise.
//!
//! A calibrated lattice flies each waypoint command at an effective speed, decided when the
//! command is engaged from the aircraft's cell and heading then: the speed at which the
//! maneuvers it will fly to the last waypoint take the predicted time `T`
//! ([`maneuvers`](crate::autopilot::plan::maneuvers): the cells a lattice aircraft flies
//! do not depend on its speed, only their times do), within
//! [[`STRETCH_MIN`](super::STRETCH_MIN), [`STRETCH_MAX`](super::STRETCH_MAX)] times the lattice's own time at the commanded speed. So the lattice's own
//! detours (its zig-zag over the cells, a fixed-wing aircraft's loops) are not the model's to
//! predict: the fit's target is the concrete time itself. Without a calibration, or without
//! an `[[aircraft]]` fit for the type, the lattice flies uncalibrated (the same trace hash).

use super::Residuals;
use crate::entity::Level;
use crate::entity::air::AirKind;
use crate::entity::route::wrap_angle;
use crate::types::TypeBook;
use serde::{Deserialize, Serialize};

/// Legs shorter than this in plan have no heading, metres.
const MIN_LEG_M: f64 = 1.0;

/// What a waypoint command's flight time depends on, beyond its profile time.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AirFeatures {
    /// The route's time at the commanded speed (and the lattice's climb rate), seconds.
    pub profile_s: f64,
    /// The route's length in plan, metres.
    pub length_m: f64,
    /// 1 for a start from a hover, else 0.
    pub rest: f64,
    /// Sum of the heading changes at the waypoints, radians.
    pub turn_rad: f64,
    /// Metres climbed and descended between the waypoints.
    pub vertical_m: f64,
    /// The turn from the start heading onto the first leg, radians.
    pub start_turn_rad: f64,
}

impl AirFeatures {
    /// The features of flying `points` at `speed` (m/s; climbs at `climb` m/s) from `start`
    /// heading `heading` (radians), at rest or not.
    pub fn of(
        start: [f64; 3],
        heading: f64,
        rest: bool,
        points: &[[f64; 3]],
        speed: f64,
        climb: f64,
    ) -> Self {
        let mut f = AirFeatures {
            rest: if rest { 1.0 } else { 0.0 },
            ..Self::default()
        };
        let mut prev = start;
        let mut last: Option<f64> = None;
        for (i, &p) in points.iter().enumerate() {
            let h = libm::hypot(p[0] - prev[0], p[1] - prev[1]);
            let dz = (p[2] - prev[2]).abs();
            f.length_m += h;
            f.vertical_m += dz;
            f.profile_s += (h / speed.max(1e-6)).max(dz / climb.max(1e-6));
            if h >= MIN_LEG_M {
                let b = libm::atan2(p[1] - prev[1], p[0] - prev[0]);
                match last {
                    Some(b0) => f.turn_rad += wrap_angle(b - b0).abs(),
                    None if i == 0 => f.start_turn_rad = wrap_angle(b - heading).abs(),
                    None => {}
                }
                last = Some(b);
            }
            prev = p;
        }
        f
    }

    /// The regressors of the model: profile time, rest, turn, vertical, start turn.
    pub fn row(&self) -> [f64; 5] {
        [
            self.profile_s,
            self.rest,
            self.turn_rad,
            self.vertical_m,
            self.start_turn_rad,
        ]
    }
}

/// One fitted aircraft model: an aircraft type's lattice against its continuous level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AirFit {
    /// The aircraft type key (`procerus`, `vidar`, `skeldar`).
    pub entity: String,
    /// The abstract level (`discrete`: the lattice).
    pub level: String,
    /// The concrete level it predicts (`kinematic` or `dynamic`).
    pub concrete: String,
    /// Seconds of concrete time per second of profile time.
    pub alpha: f64,
    /// Seconds per start from a hover (and the stop at the end).
    pub beta: f64,
    /// Seconds per radian of heading change at the waypoints.
    pub kappa: f64,
    /// Seconds per metre climbed or descended.
    pub gamma: f64,
    /// Seconds per radian of turn from the start heading onto the route.
    pub delta: f64,
    /// Flights fitted.
    pub flights: usize,
    /// Residuals on the fitted flights (lattice without / with calibration against the
    /// concrete level).
    pub fit_residuals: Residuals,
    /// Residuals on held-out flights, measured by flying the calibrated lattice.
    pub held_out: Residuals,
}

impl AirFit {
    /// The predicted concrete time of a flight with features `f`, seconds.
    pub fn predict(&self, f: &AirFeatures) -> f64 {
        let r = f.row();
        self.alpha * r[0]
            + self.beta * r[1]
            + self.kappa * r[2]
            + self.gamma * r[3]
            + self.delta * r[4]
    }

    /// Checks that every parameter is finite.
    pub(crate) fn check(&self) -> Result<(), String> {
        let ok = [self.alpha, self.beta, self.kappa, self.gamma, self.delta]
            .iter()
            .all(|x| x.is_finite());
        if ok {
            Ok(())
        } else {
            Err(format!(
                "aircraft fit {} at {}: a parameter is not finite",
                self.entity, self.level
            ))
        }
    }
}

/// One sample flight and its times at each level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlightRecord {
    /// The aircraft type key.
    pub entity: String,
    /// `fit` (used by the fit) or `held_out` (evaluation only).
    pub set: String,
    /// Waypoints.
    pub waypoints: usize,
    /// Its features, as the lattice sees them at the start.
    pub features: AirFeatures,
    /// The concrete level's time, seconds.
    pub concrete_s: f64,
    /// The lattice's time without calibration, seconds.
    pub before_s: f64,
    /// The lattice's time with calibration, seconds.
    pub after_s: f64,
}

/// The calibration's key of an aircraft type.
pub fn air_key(kind: AirKind) -> &'static str {
    match kind {
        AirKind::Ctol(k) => k.key(),
        AirKind::Vtol(k) => k.key(),
    }
}

/// The continuous (concrete) level of an aircraft type.
pub fn concrete_level(kind: AirKind) -> Level {
    match kind {
        AirKind::Ctol(_) => Level::Kinematic,
        AirKind::Vtol(_) => Level::Dynamic,
    }
}

/// The speeds the lattice flies an aircraft type at: the envelope (lowest, highest), the
/// cruise speed and the lattice's climb rate (m/s).
pub fn envelope(types: &TypeBook, kind: AirKind) -> ((f64, f64), f64, f64) {
    match kind {
        AirKind::Ctol(k) => {
            let t = types.ctol(k);
            ((t.min_speed, t.max_speed), t.cruise_speed, f64::INFINITY)
        }
        AirKind::Vtol(k) => {
            let t = types.vtol(k);
            ((0.1, t.max_speed), t.cruise_speed, t.max_climb)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn features_of_a_route() {
        // East 100 m, then north 100 m and 10 m up, from a hover facing 1 rad left of east.
        let pts = [[100.0, 0.0, 50.0], [100.0, 100.0, 60.0]];
        let f = AirFeatures::of([0.0, 0.0, 50.0], 1.0, true, &pts, 10.0, 2.0);
        assert!((f.length_m - 200.0).abs() < 1e-9);
        assert!((f.profile_s - 20.0).abs() < 1e-9);
        assert!((f.turn_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        assert!((f.start_turn_rad - 1.0).abs() < 1e-9);
        assert_eq!((f.rest, f.vertical_m), (1.0, 10.0));
        // A climb slower than the leg: the climb rate sets the leg's time.
        let f = AirFeatures::of([0.0; 3], 0.0, false, &[[10.0, 0.0, 30.0]], 10.0, 3.0);
        assert!((f.profile_s - 10.0).abs() < 1e-9);
    }
}
