//! One route across the real town at every level: a car driven at the discrete,
//! interpolated and physical levels, and the same route flown by the fixed-wing UAV
//! (kinematic) and a helicopter (rotor dynamics); drawn over the map to `docs/levels.png`.
//!
//! `cargo run --release -p vitro-check --example levels_plot [OUT.png [X0,Y0,X1,Y1]]`
//! (the optional window, in world metres, draws a close-up).

use vitro_check::scenario::{Drive, Fly, flight_route, trip};
use vitro_check::{Run, Scenario};
use vitro_site::map::Mode;
use vitro_site::render::{Overlay, RenderOptions, render_site_with};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::air::AirKind;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::{CtolKind, GroundKind, VtolKind};

fn points(run: &Run) -> Vec<[f64; 2]> {
    run.samples.iter().map(|s| [s.pos[0], s.pos[1]]).collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| format!("{root}/docs/levels.png"));
    let setup = Setup::default_town()?;
    let (a, b) = trip(&setup, Mode::Drive)?;
    let car = Drive {
        kind: GroundKind::Car,
        from: a,
        to: b,
    };
    let route = flight_route(&setup, a, b)?;
    let uav = Fly {
        aircraft: AirKind::Ctol(CtolKind::Procerus),
        route: route.clone(),
    };
    let heli = Fly {
        aircraft: AirKind::Vtol(VtolKind::Skeldar),
        route,
    };
    let runs = [
        (
            car.run(&setup, Level::Discrete)?,
            "car, discrete: node to node",
        ),
        (car.run(&setup, Level::Interpolated)?, "car, interpolated"),
        (
            car.run(&setup, Level::Physical)?,
            "car, physical (rigid body)",
        ),
        (
            uav.run(&setup, Level::Kinematic)?,
            "Procerus fixed-wing, kinematic",
        ),
        (
            heli.run(&setup, Level::Dynamic)?,
            "Skeldar helicopter, rotor dynamics",
        ),
    ];
    for (r, label) in &runs {
        println!(
            "{label:<36} arrives {:>7.1} s, {} samples",
            r.arrival.unwrap_or(f64::NAN),
            r.samples.len()
        );
    }
    // Discrete: dashed, a dot at each node; interpolated: a wide band the physical car's
    // thin line runs in; the aircraft in their own colours.
    let mut overlays: Vec<Overlay> = Vec::new();
    for (i, (r, label)) in runs.iter().enumerate() {
        let mut o = Overlay::line(*label, points(r), [0, 0, 0, 255]);
        match i {
            0 => {
                o.rgba = [20, 20, 20, 255];
                o.width = 2.0;
                o.dash = Some(vec![10.0, 6.0]);
                o.dots = 5.0;
            }
            1 => {
                o.rgba = [60, 140, 230, 255];
                o.width = 9.0;
            }
            2 => {
                o.rgba = [200, 20, 40, 255];
                o.width = 2.5;
            }
            3 => o.rgba = [0, 150, 60, 255],
            _ => {
                o.rgba = [150, 60, 200, 255];
                o.dash = Some(vec![14.0, 5.0]);
            }
        }
        overlays.push(o);
    }
    let mut bb = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for o in &overlays {
        for p in &o.points {
            bb = [
                bb[0].min(p[0]),
                bb[1].min(p[1]),
                bb[2].max(p[0]),
                bb[3].max(p[1]),
            ];
        }
    }
    let m = 200.0;
    let window = match std::env::args().nth(2) {
        Some(w) => {
            let v: Vec<f64> = w.split(',').map(str::parse).collect::<Result<_, _>>()?;
            let [a, b, c, d] = v[..] else {
                return Err("window must be X0,Y0,X1,Y1".into());
            };
            [a, b, c, d]
        }
        None => [bb[0] - m, bb[1] - m, bb[2] + m, bb[3] + m],
    };
    println!("window {window:?}");
    let opts = RenderOptions {
        width: 1800,
        window: Some(window),
        title: "One route at every level of fidelity".into(),
        attribution: vec!["Terrain: USGS-derived sample shipped with matplotlib".into()],
        ..RenderOptions::default()
    };
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let size = render_site_with(&setup.site, &opts, &overlays, &out)?;
    println!("wrote {out}: {} x {} px", size.width, size.height);
    Ok(())
}
