//! The calibration applied to the lattice: the command a calibrated lattice aircraft flies
//! ([`Calibration::air_command`]), at the speed that makes its maneuvers take the fitted
//! time ([`effective_speed`]).

use super::air::{AirFeatures, AirFit, air_key, envelope};
use super::{Calibration, STRETCH_MAX, STRETCH_MIN};
use crate::entity::Level;
use crate::entity::air::{AirKind, FlightCommand, LatticeBody};
use crate::types::TypeBook;

/// The speed (within `v / STRETCH_MAX ..= v / STRETCH_MIN`) at which maneuvers `legs`
/// (horizontal and vertical metres each, climbing at `climb` m/s) take `target` seconds;
/// `v` where there are none.
pub fn effective_speed(legs: &[[f64; 2]], v: f64, climb: f64, target: f64) -> f64 {
    let time = |u: f64| -> f64 {
        legs.iter()
            .map(|m| (m[0] / u).max(m[1] / climb.max(1e-6)))
            .sum()
    };
    let (mut fast, mut slow) = (v / STRETCH_MIN, v / STRETCH_MAX);
    if legs.is_empty() || !target.is_finite() || time(fast) >= target {
        return if legs.is_empty() { v } else { fast };
    }
    if time(slow) <= target {
        return slow;
    }
    // time(u) falls as u grows: bisect between a too slow and a too fast speed.
    for _ in 0..60 {
        let mid = 0.5 * (fast + slow);
        if time(mid) > target {
            slow = mid;
        } else {
            fast = mid;
        }
    }
    0.5 * (fast + slow)
}

impl Calibration {
    /// The lattice fit of aircraft type `kind`, if any.
    pub fn air_fit(&self, kind: AirKind) -> Option<&AirFit> {
        let key = air_key(kind);
        self.aircraft
            .iter()
            .find(|f| f.entity == key && f.level == Level::Discrete.name())
    }

    /// The command a calibrated lattice flies for `cmd` given to aircraft `b` (None where the
    /// calibration has no fit for its type: `cmd` as given). Waypoints: the commanded speed
    /// (within the envelope) divided by the predicted stretch; straight flight: the
    /// commanded speed within the envelope. The lattice flies a calibrated command's speed
    /// as it stands.
    pub fn air_command(
        &self,
        types: &TypeBook,
        b: &LatticeBody,
        cmd: &FlightCommand,
    ) -> Option<FlightCommand> {
        let fit = self.air_fit(b.kind)?;
        let ((lo, hi), cruise, climb) = envelope(types, b.kind);
        Some(match cmd {
            FlightCommand::Straight {
                heading,
                altitude,
                speed,
            } => FlightCommand::Straight {
                heading: *heading,
                altitude: *altitude,
                speed: Some(speed.unwrap_or(cruise).clamp(lo, hi)),
            },
            FlightCommand::Waypoints { points, speed } => {
                let v = speed.unwrap_or(cruise).clamp(lo, hi);
                let (cell, dir) = b.moving_to.unwrap_or((b.cell, b.dir));
                let heading = f64::from(dir) * std::f64::consts::FRAC_PI_4;
                let rest = b.moving_to.is_none() && b.speed == 0.0;
                let f = AirFeatures::of(b.lattice.point(cell), heading, rest, points, v, climb);
                let ctol = matches!(b.kind, AirKind::Ctol(_));
                let legs = crate::autopilot::plan::maneuvers(&b.lattice, ctol, cell, dir, points)
                    .unwrap_or_default();
                FlightCommand::Waypoints {
                    points: points.clone(),
                    speed: Some(effective_speed(&legs, v, climb, fit.predict(&f))),
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::Residuals;
    use crate::entity::air::Lattice;
    use crate::types::VtolKind;

    #[test]
    fn a_calibrated_lattice_flies_waypoints_at_the_stretched_speed() {
        let types = TypeBook::builtin();
        let kind = AirKind::Vtol(VtolKind::Vidar);
        let lattice = Lattice::for_vtol(types.vtol(VtolKind::Vidar));
        let b = LatticeBody {
            kind,
            lattice,
            cell: [0, 0, 10],
            dir: 0,
            speed: 0.0,
            moving_to: None,
            pending: None,
        };
        let mut cal = Calibration::parse(
            "format = 1\nmodel = \"m\"\nscenario = \"s\"\nmap = \"m\"\n\
             site_fingerprint = \"0\"\ntypes_fingerprint = \"0\"\nfrom = \"physical\"\n\
             seed = 1\nwall_s = 0.0\nfit = []\n",
        )
        .unwrap();
        let cmd = FlightCommand::Waypoints {
            points: vec![[240.0, 0.0, 50.0]],
            speed: None,
        };
        // No aircraft fit: the command is left alone.
        assert_eq!(cal.air_command(types, &b, &cmd), None);
        cal.aircraft.push(AirFit {
            entity: "vidar".into(),
            level: "discrete".into(),
            concrete: "dynamic".into(),
            alpha: 1.0,
            beta: 10.0,
            kappa: 0.0,
            gamma: 0.0,
            delta: 0.0,
            flights: 1,
            fit_residuals: Residuals::default(),
            held_out: Residuals::default(),
        });
        // 240 m (12 cells) at 12 m/s = 20 s, and 10 s for the start: 1.5 times slower.
        let Some(FlightCommand::Waypoints { speed, .. }) = cal.air_command(types, &b, &cmd) else {
            panic!("a waypoint command");
        };
        assert!((speed.unwrap() - 8.0).abs() < 1e-9, "{speed:?}");
        // Under way, no start cost.
        let moving = LatticeBody { speed: 12.0, ..b };
        let Some(FlightCommand::Waypoints { speed, .. }) = cal.air_command(types, &moving, &cmd)
        else {
            panic!("a waypoint command");
        };
        assert!((speed.unwrap() - 12.0).abs() < 1e-9, "{speed:?}");
    }
}
