use crate::fit::{knee_predicts, least_squares, screened_fit};
use vitro_tactical::calibration::Features;

#[test]
fn least_squares_recovers_a_linear_model() {
    let truth = [1.2, 5.0, 0.8, 0.05];
    let x: Vec<[f64; 4]> = (0..20)
        .map(|i| {
            let i = i as f64;
            [30.0 + 7.0 * i, 1.0, (i * 1.7) % 5.0, (i * 3.1) % 11.0]
        })
        .collect();
    let y: Vec<f64> = x
        .iter()
        .map(|r| (0..4).map(|j| r[j] * truth[j]).sum())
        .collect();
    let p = least_squares(&x, &y, [1.0, 0.0, 0.0, 0.0]);
    // Five regressors as the model has them (the start turn), the same solver.
    for j in 0..4 {
        assert!(
            (p[j] - truth[j]).abs() < 0.05 * truth[j].abs() + 0.05,
            "{p:?}"
        );
    }
}

#[test]
fn least_squares_recovers_the_start_turn_knee_beside_the_linear_terms() {
    // Trips of a truck-like body: the start-turn cost bends up above 45° (see the
    // `start_turns` example); a fit with the knee term finds both start-turn terms.
    let truth = [0.97, 4.5, 0.4, 0.08, 0.3, 6.0];
    let (rows, y) = trip_sample(40, truth, 0.0);
    let p = least_squares(&rows, &y, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    for j in 0..6 {
        assert!(
            (p[j] - truth[j]).abs() < 0.05 * truth[j].abs() + 0.05,
            "{p:?}"
        );
    }
}

#[test]
fn the_screen_leaves_out_a_trip_that_ran_into_a_wall() {
    // Twenty trips on a known model, one of which took four minutes longer (a body stuck
    // against a wall while it turned at its start): the plain fit is pulled away, the
    // screened one is not.
    let truth = [1.0, 6.0, 0.3, 0.08, 0.4, 2.0];
    let (rows, mut y) = trip_sample(20, truth, 0.05);
    y[9] += 240.0;
    let plain = least_squares(&rows, &y, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let (p, excluded) = screened_fit(&rows, &y);
    let err = |q: &[f64; 6]| (0..6).map(|j| (q[j] - truth[j]).abs()).fold(0.0, f64::max);
    assert_eq!(excluded, 1);
    assert!(err(&p) < 0.3, "{p:?}");
    assert!(err(&plain) > 2.0, "{plain:?}");
}

/// `n` sample trips with start turns spread over 0 to 2 rad on every other trip, and times
/// from `truth` with a deterministic jitter of up to `noise` seconds.
fn trip_sample(n: u32, truth: [f64; 6], noise: f64) -> (Vec<[f64; 6]>, Vec<f64>) {
    let rows: Vec<[f64; 6]> = (0..n)
        .map(|i| {
            let i = f64::from(i);
            Features {
                profile_s: 20.0 + 4.0 * i,
                length_m: 0.0,
                turn_rad: (i * 1.3) % 7.0,
                climb_m: (i * 2.9) % 9.0,
                start_turn_rad: if i as u32 % 2 == 1 {
                    (i * 0.37) % 2.0
                } else {
                    0.0
                },
            }
            .row()
        })
        .collect();
    let y = rows
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let jitter = noise * ((((k * 7919) % 13) as f64) / 6.0 - 1.0);
            (0..6).map(|j| r[j] * truth[j]).sum::<f64>() + jitter
        })
        .collect();
    (rows, y)
}

#[test]
fn the_knee_stays_where_it_predicts_left_out_trips() {
    // A real knee (4 s/rad² past 45°) under 1 s of jitter: kept, and recovered.
    let (rows, y) = trip_sample(40, [1.0, 5.0, 0.3, 0.08, 1.0, 4.0], 1.0);
    assert!(knee_predicts(&rows, &y));
    let (p, excluded) = screened_fit(&rows, &y);
    assert_eq!(excluded, 0);
    assert!((p[5] - 4.0).abs() < 1.0, "{p:?}");
}

#[test]
fn a_knee_the_data_do_not_show_is_left_at_zero() {
    // No knee in the truth, 1.5 s of jitter: a fitted knee would only follow the jitter.
    let (rows, y) = trip_sample(40, [1.0, 5.0, 0.3, 0.08, 1.5, 0.0], 1.5);
    assert!(!knee_predicts(&rows, &y));
    let (p, _) = screened_fit(&rows, &y);
    assert_eq!(p[5], 0.0, "{p:?}");
    let plain = least_squares(&rows, &y, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_ne!(
        plain[5], 0.0,
        "the plain fit does put a knee on the jitter: {plain:?}"
    );
}
