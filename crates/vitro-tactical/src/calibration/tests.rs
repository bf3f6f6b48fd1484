use super::*;

fn sample() -> Calibration {
    Calibration {
        format: FORMAT,
        model: "m".into(),
        scenario: "s.toml".into(),
        map: "town.osm.pbf".into(),
        site_fingerprint: "00000000000000aa".into(),
        types_fingerprint: types_fingerprint(TypeBook::builtin()),
        from: "physical".into(),
        seed: 3,
        wall_s: 1.5,
        unfinished: 0,
        fits: vec![Fit {
            entity: "cargo_truck".into(),
            level: "discrete".into(),
            concrete: "physical".into(),
            alpha: 1.1,
            beta: 4.0,
            kappa: 0.5,
            gamma: 0.01,
            delta: 0.7,
            epsilon: 5.5,
            trips: 3,
            excluded: 0,
            fit_residuals: Residuals::of(&[10.0, 20.0], &[9.0, 18.0], &[10.5, 19.0]),
            held_out: Residuals::default(),
        }],
        squads: vec![SquadFit {
            level: "discrete".into(),
            concrete: "directed".into(),
            normal: 1.1,
            slow: 1.9,
            walks: 4,
            calm: Residuals::default(),
            contact: Residuals::default(),
            escorted: Residuals::default(),
        }],
        trips: vec![],
        aircraft: vec![],
        flights: vec![],
    }
}

#[test]
fn a_calibration_survives_the_round_trip() {
    let c = sample();
    let text = c.to_toml().unwrap();
    assert!(text.starts_with("# Vitro calibration"));
    assert_eq!(Calibration::parse(&text).unwrap(), c);
}

#[test]
fn another_site_or_type_set_is_refused() {
    let c = sample();
    let types = types_fingerprint(TypeBook::builtin());
    assert!(c.check("00000000000000aa", &types).is_ok());
    let e = c.check("00000000000000bb", &types).unwrap_err();
    assert!(e.to_string().contains("another map"), "{e}");
    let e = c.check("00000000000000aa", "0").unwrap_err();
    assert!(e.to_string().contains("another type set"), "{e}");
}

#[test]
fn residuals_are_signed_relative_errors() {
    let r = Residuals::of(&[100.0, 200.0], &[80.0, 160.0], &[100.0, 210.0]);
    assert!((r.bias_pct_before + 20.0).abs() < 1e-9);
    assert!((r.mape_pct_after - 2.5).abs() < 1e-9);
    assert!((r.max_pct_after - 5.0).abs() < 1e-9);
}

#[test]
fn the_pace_stretch_is_the_squad_fit_of_the_level() {
    let mut c = sample();
    assert_eq!(c.pace_stretch(Level::Discrete, true), Some(1.9));
    assert_eq!(c.pace_stretch(Level::Discrete, false), Some(1.1));
    assert_eq!(c.pace_stretch(Level::Interpolated, true), None);
    c.squads.clear();
    assert_eq!(c.pace_stretch(Level::Discrete, true), None);
}

#[test]
fn a_file_without_squad_fits_still_reads() {
    let mut c = sample();
    c.squads.clear();
    let text = c.to_toml().unwrap();
    assert!(!text.lines().any(|l| l == "[[squad]]"));
    assert_eq!(Calibration::parse(&text).unwrap(), c);
}

#[test]
fn the_start_turn_costs_nothing_extra_below_the_knee_and_its_square_above() {
    let f = |turn: f64| Features {
        profile_s: 60.0,
        start_turn_rad: turn,
        ..Features::default()
    };
    assert_eq!(f(0.0).start_excess_sq(), 0.0);
    assert_eq!(f(START_KNEE - 0.1).start_excess_sq(), 0.0);
    let right = f(std::f64::consts::FRAC_PI_2);
    assert!((right.start_excess_sq() - START_KNEE * START_KNEE).abs() < 1e-12);
    assert_eq!(right.row()[5], right.start_excess_sq());
    // A truck-like fit: a right angle costs epsilon × (π/4)² on top of the linear term.
    let mut c = sample();
    c.fits[0].epsilon = 6.0;
    let fit = &c.fits[0];
    let extra = fit.predict(&right) - fit.predict(&f(0.0));
    let want = fit.delta * std::f64::consts::FRAC_PI_2 + 6.0 * START_KNEE * START_KNEE;
    assert!((extra - want).abs() < 1e-9, "{extra} {want}");
}
