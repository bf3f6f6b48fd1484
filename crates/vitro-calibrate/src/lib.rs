//! # vitro-calibrate: fitting the abstract levels to a concrete one
//!
//! An abstract level (a vehicle hopping from node to node, a lattice aircraft) is fast to
//! run but does not know what slows a concrete one down: the speed controller's lag, the
//! line through corners, a standing body's turn onto its way. This crate measures it: it
//! samples trips over a scenario's own town ([`trips`]), drives and walks them at the
//! concrete level and at each abstract one, and fits per entity type the timing model of
//! `vitro_tactical::calibration` ([`fit`]); the same for squad walks ([`squad`]) and for the
//! aircraft's lattice against their continuous levels ([`flights`]). [`evaluate`] holds a
//! calibration to fresh trips. The file it writes is a
//! [`Calibration`](vitro_tactical::calibration::Calibration); the environment reads it and
//! applies it, this crate is needed only to make one (`vitro calibrate`).
//!
//! ```no_run
//! use vitro_calibrate::fit::{Stamp, calibrate};
//! use vitro_calibrate::trips::{Sampling, sample};
//! use vitro_tactical::entity::Level;
//! use vitro_tactical::setup::Setup;
//!
//! let setup = Setup::default_town().unwrap();
//! let trips = sample(&setup, &Sampling::default());
//! let to = [Level::Discrete, Level::Interpolated];
//! let cal = calibrate(&setup, &trips, &to, &Stamp::default(), 2, &|| {}).unwrap();
//! println!("{}", cal.to_toml().unwrap());
//! ```

pub mod evaluate;
pub mod fit;
pub mod flights;
pub mod squad;
pub mod trips;

#[cfg(test)]
mod tests;
