//! The cost of a start turn, measured: the calibration's cargo-truck trips (or another
//! vehicle type's) driven at the physical level from a standing start turned off the way by
//! each angle of a grid, against the same trip started on the way. Prints, per angle, the
//! mean and the range over the trips of the extra time, and the interpolated level's.
//!
//! `cargo run --release -p vitro-evac --example start_turns -- [CALIBRATION] [ENTITY] [TRIPS]`

use std::sync::Arc;
use vitro::env::NodeId;
use vitro_calibrate::trips::{self, Trip, par_map};
use vitro_evac::Mission;
use vitro_tactical::calibration::Calibration;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::discrete::NodeKind;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::GroundKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let args: Vec<String> = std::env::args().collect();
    let cal_path = args
        .get(1)
        .cloned()
        .unwrap_or(format!("{root}/scenarios/calibration/evacuation.toml"));
    let entity = args.get(2).cloned().unwrap_or("cargo_truck".into());
    let n: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(12);
    let cal = Arc::new(Calibration::read(std::path::Path::new(&cal_path))?);
    let kind = GroundKind::ALL
        .iter()
        .copied()
        .find(|k| k.key() == entity)
        .ok_or("not a vehicle type")?;
    let m = Mission::from_file(format!("{root}/scenarios/evacuation.toml"), None)?;
    let setup = Setup::new(m.brief.site.clone());
    let base: Vec<Trip> = cal
        .trips
        .iter()
        .filter(|t| t.entity == entity)
        .take(n)
        .map(|t| Trip {
            kind: NodeKind::Ground(kind),
            from: NodeId(t.from),
            to: NodeId(t.to),
            fit: false,
            start_off: 0.0,
        })
        .collect();
    let grid: Vec<f64> = (0..=12).map(|i| f64::from(i) * 15.0).collect();
    let mut jobs = Vec::new();
    for (i, _) in base.iter().enumerate() {
        for &deg in &grid {
            for sign in [1.0, -1.0] {
                if deg == 0.0 && sign < 0.0 {
                    continue;
                }
                for level in [Level::Physical, Level::Interpolated] {
                    jobs.push((i, sign * deg, level));
                }
            }
        }
    }
    let out = par_map(
        &jobs,
        2,
        |&(i, deg, level)| {
            let t = Trip {
                start_off: deg.to_radians(),
                ..base[i]
            };
            trips::run(&setup, &t, level, None).ok().flatten()
        },
        &|| {},
    );
    let time = |i: usize, deg: f64, level: Level| {
        jobs.iter()
            .zip(&out)
            .find(|((j, d, l), _)| *j == i && *d == deg && *l == level)
            .and_then(|(_, r)| *r)
    };
    println!(
        "start turn deg | physical extra s: mean [min, max] | interpolated extra s: mean | trips"
    );
    for &deg in &grid {
        let mut ph = Vec::new();
        let mut ip = Vec::new();
        for i in 0..base.len() {
            for sign in [1.0, -1.0] {
                if deg == 0.0 && sign < 0.0 {
                    continue;
                }
                if let (Some(a), Some(b)) = (
                    time(i, sign * deg, Level::Physical),
                    time(i, 0.0, Level::Physical),
                ) {
                    ph.push(a - b);
                }
                if let (Some(a), Some(b)) = (
                    time(i, sign * deg, Level::Interpolated),
                    time(i, 0.0, Level::Interpolated),
                ) {
                    ip.push(a - b);
                }
            }
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
        let lo = ph.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ph.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        println!(
            "{deg:5.0} | {:6.2} [{lo:6.2}, {hi:6.2}] | {:6.2} | {}",
            mean(&ph),
            mean(&ip),
            ph.len()
        );
    }
    Ok(())
}
