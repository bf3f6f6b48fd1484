//! The default mission's drive legs as calibration trips: each leg (drive-graph node to
//! node) run alone at the physical level and at the abstract levels with and without the
//! calibration, beside the calibration's prediction; a check that what the mission's truck
//! drives is what the calibration fitted.
//!
//! `cargo run --release -p vitro-evac --example leg_trips -- [CALIBRATION]`

use std::sync::Arc;
use vitro::env::NodeId;
use vitro_calibrate::trips::{self, Trip};
use vitro_evac::Mission;
use vitro_site::map::Mode;
use vitro_tactical::calibration::{Calibration, Features};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::discrete::NodeKind;
use vitro_tactical::entity::route::wrap_angle;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::GroundKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let cal_path = std::env::args()
        .nth(1)
        .unwrap_or(format!("{root}/scenarios/calibration/evacuation.toml"));
    let cal = Arc::new(Calibration::read(std::path::Path::new(&cal_path))?);
    let m = Mission::from_file(format!("{root}/scenarios/evacuation.toml"), None)?;
    let b = &m.brief;
    let setup = Setup::new(b.site.clone());
    let drive = b.roads.of(Mode::Drive);
    let start_town = b.site.to_town([b.places[0][0], b.places[0][1]]);
    let start = drive.nearest_connected(start_town).ok_or("no start node")?;
    let mut stops: Vec<(String, NodeId)> = vec![("start".into(), start)];
    for (i, &n) in b.legs_out.iter().enumerate() {
        stops.push((format!("out {}", i + 1), n));
    }
    for (i, &n) in b.legs_back.iter().enumerate() {
        stops.push((format!("back {}", i + 1), n));
    }
    let kind = NodeKind::Ground(GroundKind::CargoTruck);
    println!(
        "leg | start turn rad | profile s | physical s | discrete s | discrete cal s | interp s | interp cal s | predicted s"
    );
    // The truck is placed heading east (0); each later leg starts where the last ended.
    let mut heading = 0.0;
    for w in stops.windows(2) {
        let mut t = Trip {
            kind,
            from: w[0].1,
            to: w[1].1,
            fit: false,
            start_off: 0.0,
        };
        let tr = trips::track(&setup, &t)?;
        t.start_off = wrap_angle(heading - tr.heading_at(0.0));
        heading = tr.heading_at(tr.length());
        let f: Features = trips::features(&setup, &t)?;
        let run = |l, c: Option<Arc<Calibration>>| {
            trips::run(&setup, &t, l, c)
                .ok()
                .flatten()
                .unwrap_or(f64::NAN)
        };
        let pred = cal
            .fit("cargo_truck", Level::Discrete)
            .map_or(f64::NAN, |fit| fit.predict(&f));
        println!(
            "{} | {:.2} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1}",
            w[1].0,
            f.start_turn_rad,
            f.profile_s,
            run(Level::Physical, None),
            run(Level::Discrete, None),
            run(Level::Discrete, Some(cal.clone())),
            run(Level::Interpolated, None),
            run(Level::Interpolated, Some(cal.clone())),
            pred
        );
    }
    Ok(())
}
