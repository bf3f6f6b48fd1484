//! The aircraft calibration on a small flight set: the same fit whatever the thread count,
//! and the calibrated lattice closer to each continuous level than the plain one on flights
//! the fit did not see.

mod common;

use std::sync::Arc;
use vitro_calibrate::flights::{FlightSampling, calibrate_air, evaluate_air, sample_flights};
use vitro_tactical::calibration::Calibration;
use vitro_tactical::entity::air::AirKind;
use vitro_tactical::setup::Setup;
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
    let flights = sample_flights(&s, &small(kinds.clone(), 3, 12, 0));
    assert_eq!(flights.len(), 36);
    let mut cal = empty();
    calibrate_air(&s, &flights, &mut cal, 2, &|| {}).unwrap();
    assert_eq!(cal.aircraft.len(), 3);
    // The round trip through the file keeps every figure.
    assert_eq!(Calibration::parse(&cal.to_toml().unwrap()).unwrap(), cal);
    // Fresh flights the fit did not see.
    let cal = Arc::new(cal);
    let fresh = sample_flights(&s, &small(kinds, 77, 0, 5));
    let rows = evaluate_air(&s, &cal, &fresh, 5.0, 2, &|| {}).unwrap();
    assert_eq!(rows.len(), 3, "{rows:?}");
    for p in &rows {
        println!("{p:?}");
    }
    for p in &rows {
        let r = &p.residuals;
        assert!(r.n >= 4, "{p:?}");
        // The calibrated lattice's bias is within the tolerance, and at most half the plain
        // lattice's where that is outside it (the helicopters' lattice is optimistic: no
        // acceleration, no braking; the fixed-wing lattice pessimistic: it zig-zags and
        // loops over its cells) ...
        assert!(r.bias_pct_after.abs() < BIAS_TOLERANCE_PCT, "{p:?}");
        if r.bias_pct_before.abs() > BIAS_TOLERANCE_PCT {
            assert!(
                r.bias_pct_after.abs() < r.bias_pct_before.abs() / 2.0,
                "{p:?}"
            );
        }
        // ... and its flight times are closer, flight by flight.
        assert!(r.rmse_s_after < r.rmse_s_before / 2.0, "{p:?}");
    }
    // At least one type's plain lattice is far off (the Skeldar's: a fast helicopter that
    // the lattice has at cruise speed from the first instant).
    assert!(
        rows.iter()
            .any(|p| p.residuals.bias_pct_before < -3.0 * BIAS_TOLERANCE_PCT),
        "{rows:?}"
    );
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
