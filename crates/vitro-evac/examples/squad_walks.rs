//! Squad walks over the default mission's town, with and without an escorted VIP, calm and
//! in contact, at the directed level and at the discrete level with a calibration: where a
//! calibrated discrete squad is early or late against the directed one.
//!
//! `cargo run --release -p vitro-evac --example squad_walks -- [CALIBRATION] [TRIPS] [MIN_M MAX_M]`
//!
//! Prints one line per walk variant: walks that arrived at both levels, the sums of their
//! times and the ratio directed / discrete.

use std::sync::Arc;
use vitro_calibrate::squad::{Walk, walk};
use vitro_calibrate::trips::{Sampling, sample};
use vitro_evac::Mission;
use vitro_tactical::calibration::Calibration;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::discrete::NodeKind;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::TroopKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let cal_path = std::env::args()
        .nth(1)
        .unwrap_or(format!("{root}/scenarios/calibration/evacuation.toml"));
    let n: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(12);
    let arg = |i: usize, d: f64| {
        std::env::args()
            .nth(i)
            .and_then(|s| s.parse().ok())
            .unwrap_or(d)
    };
    let walk_m = (arg(3, 60.0), arg(4, 500.0));
    let cal = Arc::new(Calibration::read(std::path::Path::new(&cal_path))?);
    let m = Mission::from_file(format!("{root}/scenarios/evacuation.toml"), None)?;
    let plain = Setup::new(m.brief.site.clone());
    let with = Setup {
        calibration: Some(cal),
        ..plain.clone()
    };
    let trips = sample(
        &plain,
        &Sampling {
            fit_per_type: n,
            held_out_per_type: 0,
            kinds: vec![NodeKind::Troop(TroopKind::Blue)],
            seed: 3,
            walk_m,
            ..Sampling::default()
        },
    );
    println!("escort | contact | n | directed s | discrete cal s | ratio");
    for escort in [false, true] {
        for contact in [false, true] {
            let (mut c, mut d, mut k) = (0.0, 0.0, 0);
            for &trip in &trips {
                let w = Walk {
                    trip,
                    contact,
                    escort,
                };
                let a = walk(&plain, &w, Level::Directed)?;
                let b = walk(&with, &w, Level::Discrete)?;
                if let (Some(a), Some(b)) = (a, b) {
                    if std::env::var_os("SQUAD_WALKS_EACH").is_some() {
                        println!("  {:?} -> {:?}: {a:.1} {b:.1}", trip.from, trip.to);
                    }
                    c += a;
                    d += b;
                    k += 1;
                }
            }
            println!(
                "{escort} | {contact} | {k} | {c:.0} | {d:.0} | {:.3}",
                c / d.max(1e-9)
            );
        }
    }
    Ok(())
}
