//! The aircraft calibration on a small flight set: the same fit whatever the thread count,
//! and the calibrated lattice closer to each continuous level than the plain one on flights
//! the fit did not see.

mod common;

use std::sync::Arc;
use vitro_tactical::calibrate::Calibration;
use vitro_tactical::calibrate::flights::{
    FlightSampling, calibrate_air, evaluate_air, sample_flights,
};
use vitro_tactical::check::Setup;
use vitro_tactical::entity::air::AirKind;
use vitro_tactical::types::{CtolKind, VtolKind};

fn setup() -> Setup {
    let (site, _) = common::town();
    Setup::new(site)
}

fn empty() -> Calibration {
    Calibration::parse(
        "format = 1\nmodel = \"m\"\nscenario = \"s\"\nmap = \"m\"\nsite_fingerprint = \"0\"\n\
         types_fingerprint = \"0\"\nfrom = \"physical\"\nseed = 1\nwall_s = 0.0\nfit = []\n",
    )
    .unwrap()
}

fn small(kinds: Vec<AirKind>, seed: u64, fit: usize, held: usize) -> FlightSampling {
    FlightSampling {
        fit_per_type: fit,
        held_out_per_type: held,
        leg_m: (150.0, 400.0),
        max_waypoints: 3,
        kinds,
        seed,
    }
}

/// Held-out tolerance on the calibrated lattice's mean relative error (bias), %.
const BIAS_TOLERANCE_PCT: f64 = 5.0;

#[test]
fn the_calibrated_lattice_predicts_each_continuous_level_better() {
    let s = setup();
    let kinds = vec![
        AirKind::Ctol(CtolKind::Procerus),
        AirKind::Vtol(VtolKind::Vidar),
        AirKind::Vtol(VtolKind::Skeldar),
    ];
    let flights = sample_flights(&s, &small(kinds.clone(), 3, 8, 0));
    assert_eq!(flights.len(), 24);
    let mut cal = empty();
    calibrate_air(&s, &flights, &mut cal, 2, &|| {}).unwrap();
    assert_eq!(cal.aircraft.len(), 3);
    // The round trip through the file keeps every figure.
    assert_eq!(Calibration::parse(&cal.to_toml().unwrap()).unwrap(), cal);
    // Fresh flights the fit did not see.
    let cal = Arc::new(cal);
    let fresh = sample_flights(&s, &small(kinds, 77, 0, 4));
    let rows = evaluate_air(&s, &cal, &fresh, 5.0, 2, &|| {}).unwrap();
    assert_eq!(rows.len(), 3, "{rows:?}");
    for p in &rows {
        let r = &p.residuals;
        assert!(r.n >= 3, "{p:?}");
        // The lattice is optimistic (no acceleration, no braking, free turns) ...
        assert!(r.bias_pct_before < -BIAS_TOLERANCE_PCT, "{p:?}");
        // ... and the calibration takes the bias into the tolerance.
        assert!(r.bias_pct_after.abs() < BIAS_TOLERANCE_PCT, "{p:?}");
        assert!(r.mape_pct_after < r.mape_pct_before / 2.0, "{p:?}");
    }
}

#[test]
fn the_aircraft_fit_is_the_same_on_one_thread_and_two() {
    let s = setup();
    let flights = sample_flights(&s, &small(vec![AirKind::Vtol(VtolKind::Skeldar)], 5, 3, 1));
    assert_eq!(flights.len(), 4);
    let (mut one, mut two) = (empty(), empty());
    calibrate_air(&s, &flights, &mut one, 1, &|| {}).unwrap();
    calibrate_air(&s, &flights, &mut two, 2, &|| {}).unwrap();
    assert_eq!(one, two);
    assert_eq!(one.flights.len(), 4);
}
