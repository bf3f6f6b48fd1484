//! The calibration of the abstract levels, as the environment applies it: a per-type timing
//! model, fitted on sample trips driven and walked at a concrete level over a scenario's own
//! town, that the abstract levels then follow. This module holds the file ([`Calibration`]),
//! the model and its application ([`stretched`], [`Calibration::air_command`]); the fitting
//! itself (the sample trips, flights and squad walks, the least squares) is `vitro-calibrate`.
//!
//! # The model
//!
//! Every level plans the same track and speed profile ([`Track::plan_vehicle`],
//! [`Track::plan_walk`]); the discrete level hops along the profile's times, the interpolated
//! level follows its speeds. The concrete level is slower than the profile for reasons the
//! profile does not model: the speed controller's lag when it pulls away and when it creeps
//! to a stop, the pure-pursuit line through corners, grade feed-forward errors, a walker's
//! turn on the spot. A trip's concrete time is fitted, per entity type and abstract level, as
//!
//! ```text
//! T = alpha * T_profile + beta + kappa * turn_rad + gamma * climb_m
//!     + delta * start_turn_rad + epsilon * start_excess_sq
//! ```
//!
//! with `T_profile` the profile's time, `beta` the fixed cost of a start and a stop,
//! `turn_rad` the sum of the path's heading changes at its vertices (radians), `climb_m`
//! the metres climbed, `start_turn_rad` the turn from the body's heading at the start onto
//! the path and `start_excess_sq` the square of that turn's excess over [`START_KNEE`]
//! ([`Features`]). A rigid body that stands turned off its way by up to about 45° swings
//! onto it while it pulls away; beyond that it drives off sideways at a creep until it has
//! turned, and the cost grows with the square of the excess (`--example start_turns` of
//! `vitro-evac` measures it: 0.5 s at 45°, 3.6 s at 90°, 14.5 s at 135° for the truck). A calibrated abstract level stretches the track's
//! profile uniformly by `k = T / T_profile` (times × k, speeds ÷ k, k clamped to
//! [[`STRETCH_MIN`], [`STRETCH_MAX`]]): the discrete level's hops then sum to the predicted
//! time; the interpolated level, which has its own lag, is fitted against its own
//! uncalibrated time (`T_physical × T_profile / T_interpolated`) so that its stretched run
//! lands on the concrete time.
//!
//! The aircraft's lattice is calibrated against their continuous levels by a model of the
//! same shape ([`air`]), fitted on sample flights (`vitro_calibrate::flights`).
//!
//! A calibration is made for one map and terrain ([`site_fingerprint`]) and one type set
//! ([`types_fingerprint`]); a scenario that names a calibration made for another is refused.

pub mod air;
mod command;
mod residuals;

pub use command::effective_speed;
pub use residuals::{Residuals, median};

use crate::entity::Level;
use crate::entity::discrete::NodeKind;
use crate::entity::route::{Track, wrap_angle};
use crate::types::TypeBook;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Smallest stretch a calibration applies to a profile.
pub const STRETCH_MIN: f64 = 0.5;
/// Largest stretch a calibration applies to a profile.
pub const STRETCH_MAX: f64 = 3.0;
/// The start turn, radians, above which a standing rigid body's turn onto its way costs
/// more than its swing while it pulls away: 45°, where the measured cost bends upwards
/// (the model's `start_excess_sq` regressor is the square of the excess over it).
pub const START_KNEE: f64 = std::f64::consts::FRAC_PI_4;
/// Version of the calibration file format.
pub const FORMAT: u32 = 1;

/// Why a calibration cannot be read or used.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// The file could not be read.
    #[error("cannot read the calibration {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The file is not a calibration.
    #[error("{path} is not a calibration file: {message}")]
    Parse {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The calibration was made on another map or terrain.
    #[error(
        "the calibration was made on another map or terrain (site fingerprint {found}, this scenario's is {expected}; calibration map {map}): run `vitro calibrate` on this scenario"
    )]
    OtherSite {
        /// This scenario's fingerprint.
        expected: String,
        /// The calibration's.
        found: String,
        /// The calibration's map name.
        map: String,
    },
    /// The calibration was made for another type set.
    #[error(
        "the calibration was made for another type set (types fingerprint {found}, this build's is {expected}): run `vitro calibrate` again"
    )]
    OtherTypes {
        /// This build's fingerprint.
        expected: String,
        /// The calibration's.
        found: String,
    },
    /// The file's format version is not this one's.
    #[error("calibration format {found}, expected {FORMAT}")]
    Format {
        /// The file's version.
        found: u32,
    },
}

/// What a trip's time depends on, beyond its profile time.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Features {
    /// The profile's time, seconds (the uncalibrated discrete estimate).
    pub profile_s: f64,
    /// Path length, metres.
    pub length_m: f64,
    /// Sum of the heading changes at the path's vertices, radians.
    pub turn_rad: f64,
    /// Metres climbed.
    pub climb_m: f64,
    /// The turn from the body's heading at the start onto the path's first piece, radians
    /// (0 in a file made before it).
    #[serde(default)]
    pub start_turn_rad: f64,
}

impl Features {
    /// The features of a planned track.
    pub fn of(track: &Track) -> Self {
        let pts = &track.pts;
        let mut turn = 0.0;
        let mut climb = 0.0;
        let mut last: Option<f64> = None;
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            climb += (b[2] - a[2]).max(0.0);
            if libm::hypot(b[0] - a[0], b[1] - a[1]) < 1e-6 {
                continue;
            }
            let h = libm::atan2(b[1] - a[1], b[0] - a[0]);
            if let Some(h0) = last {
                turn += wrap_angle(h - h0).abs();
            }
            last = Some(h);
        }
        Features {
            profile_s: track.duration(),
            length_m: track.length(),
            turn_rad: turn,
            climb_m: climb,
            start_turn_rad: 0.0,
        }
    }

    /// The features of a planned track that a body heading `heading` (radians) starts on.
    pub fn starting(track: &Track, heading: f64) -> Self {
        Features {
            start_turn_rad: wrap_angle(track.heading_at(0.0) - heading).abs(),
            ..Self::of(track)
        }
    }

    /// The square of the start turn's excess over [`START_KNEE`], radians².
    pub fn start_excess_sq(&self) -> f64 {
        let x = (self.start_turn_rad - START_KNEE).max(0.0);
        x * x
    }

    /// The regressors of the model: profile time, 1, turn, climb, start turn, the start
    /// turn's squared excess.
    pub fn row(&self) -> [f64; 6] {
        [
            self.profile_s,
            1.0,
            self.turn_rad,
            self.climb_m,
            self.start_turn_rad,
            self.start_excess_sq(),
        ]
    }
}

/// One fitted model: an entity type at an abstract level against the concrete level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fit {
    /// The entity type: a vehicle type key (`car`, `cargo_truck`, `mdars`) or a trooper
    /// type key with `_trooper` (`blue_trooper`, `red_trooper`, `vip_trooper`).
    pub entity: String,
    /// The abstract level the fit is for.
    pub level: String,
    /// The concrete level it predicts.
    pub concrete: String,
    /// Seconds of concrete time per second of profile time.
    pub alpha: f64,
    /// Seconds per trip (a start and a stop).
    pub beta: f64,
    /// Seconds per radian of heading change.
    pub kappa: f64,
    /// Seconds per metre climbed.
    pub gamma: f64,
    /// Seconds per radian of turn from the start heading onto the path (0 in a file made
    /// before it).
    #[serde(default)]
    pub delta: f64,
    /// Seconds per radian² of the start turn's excess over [`START_KNEE`] (0 in a file made
    /// before it).
    #[serde(default)]
    pub epsilon: f64,
    /// Trips fitted.
    pub trips: usize,
    /// Trips of the fitted set the outlier screen left out
    /// (`vitro_calibrate::fit::screened_fit`; their residuals still count in
    /// `fit_residuals`).
    #[serde(default)]
    pub excluded: usize,
    /// Residuals on the fitted trips (abstract level without / with calibration against the
    /// concrete level).
    pub fit_residuals: Residuals,
    /// Residuals on held-out trips, measured by running the calibrated abstract level.
    pub held_out: Residuals,
}

/// The fitted pace of squad walks at an abstract level (`vitro_calibrate::squad`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SquadFit {
    /// The abstract level (`discrete`).
    pub level: String,
    /// The concrete level it predicts (`directed`).
    pub concrete: String,
    /// Stretch of the leader's hops at normal pace.
    pub normal: f64,
    /// Stretch of the leader's hops at slow pace.
    pub slow: f64,
    /// Walks fitted (calm and in contact).
    pub walks: usize,
    /// Walk times without / with the stretches against the concrete level's, calm walks.
    pub calm: Residuals,
    /// The same, walks in contact.
    pub contact: Residuals,
    /// The same, the walks in contact with a VIP in the squad's last slot (held out: the fit
    /// does not use them; empty in a file made before them).
    #[serde(default)]
    pub escorted: Residuals,
}

/// One sample trip and its times at each level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TripRecord {
    /// The entity type (as in [`Fit::entity`]).
    pub entity: String,
    /// `fit` (used by the fit) or `held_out` (evaluation only).
    pub set: String,
    /// Start node (drive or walk graph).
    pub from: u32,
    /// Goal node.
    pub to: u32,
    /// The street classes the path uses, `+` separated.
    pub classes: String,
    /// True if the path crosses a bridge.
    pub bridge: bool,
    /// Its features.
    pub features: Features,
    /// Concrete level's time, seconds.
    pub concrete_s: f64,
    /// Each abstract level's time without calibration, seconds (by level name).
    pub before_s: std::collections::BTreeMap<String, f64>,
    /// Each abstract level's time with calibration, seconds (by level name; measured runs).
    pub after_s: std::collections::BTreeMap<String, f64>,
}

/// A calibration file: the fits and the trips they came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// Format version ([`FORMAT`]).
    pub format: u32,
    /// The model, in words.
    pub model: String,
    /// The scenario it was made from, as named.
    pub scenario: String,
    /// The map's file name.
    pub map: String,
    /// Fingerprint of the map, the terrain and the offset ([`site_fingerprint`]).
    pub site_fingerprint: String,
    /// Fingerprint of the type set ([`types_fingerprint`]).
    pub types_fingerprint: String,
    /// The concrete level.
    pub from: String,
    /// Seed of the trip sample.
    pub seed: u64,
    /// Wall-clock seconds `vitro calibrate` took (information only).
    pub wall_s: f64,
    /// Runs that did not reach their goal (a body that stalled): their trips are left out.
    #[serde(default)]
    pub unfinished: usize,
    /// The fits, one per (entity type, abstract level).
    #[serde(rename = "fit")]
    pub fits: Vec<Fit>,
    /// The squads' pace at the abstract levels (`vitro_calibrate::squad`); none in a file
    /// made before it.
    #[serde(rename = "squad", default)]
    pub squads: Vec<SquadFit>,
    /// The sample trips.
    #[serde(rename = "trip", default)]
    pub trips: Vec<TripRecord>,
    /// The aircraft's lattice fits ([`air`]); none in a file made before them.
    #[serde(rename = "aircraft", default)]
    pub aircraft: Vec<air::AirFit>,
    /// The sample flights of the aircraft fits.
    #[serde(rename = "flight", default)]
    pub flights: Vec<air::FlightRecord>,
}

/// The calibration's entity key of a node-level body kind.
pub fn entity_key(kind: NodeKind) -> String {
    match kind {
        NodeKind::Ground(k) => k.key().to_owned(),
        NodeKind::Troop(k) => format!("{}_trooper", k.key()),
    }
}

impl Calibration {
    /// Reads a calibration file.
    pub fn read(path: &Path) -> Result<Self, CalibrationError> {
        let text = std::fs::read_to_string(path).map_err(|e| CalibrationError::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::parse(&text).map_err(|message| CalibrationError::Parse {
            path: path.display().to_string(),
            message,
        })
    }

    /// Parses a calibration from TOML.
    pub fn parse(text: &str) -> Result<Self, String> {
        let c: Calibration = toml::from_str(text).map_err(|e| e.to_string())?;
        if c.format != FORMAT {
            return Err(CalibrationError::Format { found: c.format }.to_string());
        }
        for f in &c.squads {
            if !(f.normal.is_finite() && f.slow.is_finite()) {
                return Err(format!("squad fit at {}: a stretch is not finite", f.level));
            }
        }
        for f in &c.aircraft {
            f.check()?;
        }
        for f in &c.fits {
            let ok = [f.alpha, f.beta, f.kappa, f.gamma, f.delta, f.epsilon]
                .iter()
                .all(|x| x.is_finite());
            if !ok {
                return Err(format!(
                    "fit {} at {}: a parameter is not finite",
                    f.entity, f.level
                ));
            }
        }
        Ok(c)
    }

    /// The file's text: a header comment, then the TOML.
    pub fn to_toml(&self) -> Result<String, String> {
        let body = toml::to_string(self).map_err(|e| e.to_string())?;
        Ok(format!(
            "# Vitro calibration: the abstract levels' trip times fitted to the {} level.\n\
             # Model, per entity type and abstract level:\n\
             #   T = alpha * T_profile + beta + kappa * turn_rad + gamma * climb_m\n\
             #       + delta * start_turn_rad + epsilon * max(0, start_turn_rad - pi/4)^2\n\
             # [[aircraft]]: the lattice's flight times fitted to the kinematic (fixed-wing)\n\
             # and dynamic (helicopter) levels: T = alpha * T_profile + beta * rest\n\
             #   + kappa * turn_rad + gamma * vertical_m + delta * start_turn_rad.\n\
             # [[squad]]: the stretch of a squad leader's discrete hops at its normal and\n\
             # slow pace, fitted on squad walks at the directed level (escorted: the same\n\
             # walks in contact with a VIP in the last slot, held out).\n\
             # A scenario uses it with `[fidelity] calibration = \"FILE\"` (same map, terrain\n\
             # and type set only). Residuals: % of the concrete time (bias signed, negative =\n\
             # the abstract level is optimistic); held_out: trips not used by the fit.\n\n{body}",
            self.from
        ))
    }

    /// Refuses a calibration made for another site or type set.
    pub fn check(&self, site: &str, types: &str) -> Result<(), CalibrationError> {
        if self.site_fingerprint != site {
            return Err(CalibrationError::OtherSite {
                expected: site.to_owned(),
                found: self.site_fingerprint.clone(),
                map: self.map.clone(),
            });
        }
        if self.types_fingerprint != types {
            return Err(CalibrationError::OtherTypes {
                expected: types.to_owned(),
                found: self.types_fingerprint.clone(),
            });
        }
        Ok(())
    }

    /// The fit of `entity` at `level`, if any.
    pub fn fit(&self, entity: &str, level: Level) -> Option<&Fit> {
        self.fits
            .iter()
            .find(|f| f.entity == entity && f.level == level.name())
    }

    /// The stretch of a squad leader's hop at `level` at its slow or normal pace, if the
    /// calibration has a squad fit there (`vitro_calibrate::squad`).
    pub fn pace_stretch(&self, level: Level, slow: bool) -> Option<f64> {
        let f = self.squads.iter().find(|f| f.level == level.name())?;
        let k = if slow { f.slow } else { f.normal };
        (k.is_finite() && k > 0.0).then(|| k.clamp(STRETCH_MIN, STRETCH_MAX))
    }

    /// The stretch of a track of `kind` at `level` for a body heading `heading` at its
    /// start ([`Fit::predict`] over the profile time), or `None` where there is no fit.
    pub fn stretch(
        &self,
        kind: NodeKind,
        level: Level,
        track: &Track,
        heading: f64,
    ) -> Option<f64> {
        let fit = self.fit(&entity_key(kind), level)?;
        let f = Features::starting(track, heading);
        if f.profile_s <= 0.0 {
            return None;
        }
        Some((fit.predict(&f) / f.profile_s).clamp(STRETCH_MIN, STRETCH_MAX))
    }
}

impl Fit {
    /// The predicted concrete time of a trip with features `f`, seconds.
    pub fn predict(&self, f: &Features) -> f64 {
        let r = f.row();
        self.alpha * r[0]
            + self.beta * r[1]
            + self.kappa * r[2]
            + self.gamma * r[3]
            + self.delta * r[4]
            + self.epsilon * r[5]
    }
}

/// `track` with its profile stretched by `k`: times × k, speeds ÷ k.
pub fn stretched(track: &Track, k: f64) -> Track {
    let mut t = track.clone();
    for x in &mut t.t {
        *x *= k;
    }
    for v in &mut t.v {
        *v /= k;
    }
    for l in &mut t.limit {
        *l /= k;
    }
    t
}

/// FNV-1a, 64 bits.
fn fnv(mut h: u64, bytes: &[u8]) -> u64 {
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// Fingerprint of a site: the map's and the terrain's bytes and the offset.
pub fn site_fingerprint(
    map: &Path,
    terrain: &Path,
    offset: Option<[f64; 2]>,
) -> Result<String, CalibrationError> {
    let read = |p: &Path| {
        std::fs::read(p).map_err(|e| CalibrationError::Read {
            path: p.display().to_string(),
            message: e.to_string(),
        })
    };
    let mut h = fnv(FNV_OFFSET, &read(map)?);
    h = fnv(h, &read(terrain)?);
    for x in offset.unwrap_or([0.0; 2]) {
        h = fnv(h, &x.to_bits().to_le_bytes());
    }
    Ok(format!("{h:016x}"))
}

/// Fingerprint of a type set (its parameters as TOML).
pub fn types_fingerprint(types: &TypeBook) -> String {
    let text = toml::to_string(types).unwrap_or_default();
    format!("{:016x}", fnv(FNV_OFFSET, text.as_bytes()))
}

#[cfg(test)]
mod tests;
