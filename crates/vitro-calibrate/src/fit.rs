//! Making a calibration: run the sample trips at the concrete level and, uncalibrated, at
//! the abstract ones; fit each (entity type, abstract level) by least squares; run every
//! trip again at the calibrated abstract levels and record the residuals, on the fitted
//! trips and on the held-out ones.

use crate::trips::{self, Trip, levels, par_map};
use std::collections::BTreeMap;
use std::sync::Arc;
use vitro_check::CheckError;
use vitro_tactical::calibration::median;
use vitro_tactical::calibration::{
    Calibration, FORMAT, Features, Fit, Residuals, TripRecord, entity_key,
};
use vitro_tactical::entity::Level;
use vitro_tactical::setup::Setup;

/// What the fit's runs are labelled with: where the calibration is for.
#[derive(Clone, Debug, Default)]
pub struct Stamp {
    /// The scenario, as named.
    pub scenario: String,
    /// The map's file name.
    pub map: String,
    /// [`site_fingerprint`](vitro_tactical::calibration::site_fingerprint) of the scenario's site.
    pub site_fingerprint: String,
    /// [`types_fingerprint`](vitro_tactical::calibration::types_fingerprint) of the type set.
    pub types_fingerprint: String,
    /// Seed of the trip sample.
    pub seed: u64,
}

/// Runs a calibration needs for `trips` with abstract levels `to`: each trip at its
/// concrete level, then at each abstract level of `to` it has, uncalibrated and calibrated.
pub fn runs_needed(trips: &[Trip], to: &[Level]) -> usize {
    let squads = if to.contains(&Level::Discrete) {
        crate::squad::runs_needed(trips)
    } else {
        0
    };
    squads
        + trips
            .iter()
            .map(|t| 1 + 2 * levels(t.kind).1.iter().filter(|l| to.contains(l)).count())
            .sum::<usize>()
}

/// Least squares of `y` on the rows `x` with a light pull (1e-3 of each column's scale)
/// towards `prior`, so that a regressor that hardly varies (no climb on a flat sample)
/// keeps its prior instead of an arbitrary value; a regressor that is zero in every row
/// keeps its prior exactly. The pull is one extra row per column (ridge regression towards
/// `prior`), and the stacked system is solved by Householder QR ([`qr_least_squares`]).
pub fn least_squares<const N: usize>(x: &[[f64; N]], y: &[f64], prior: [f64; N]) -> [f64; N] {
    let n = x.len().min(y.len());
    let (x, y) = (&x[..n], &y[..n]);
    let scale: [f64; N] = std::array::from_fn(|c| x.iter().map(|r| r[c] * r[c]).sum());
    let cols: Vec<usize> = (0..N).filter(|&c| scale[c] > 0.0).collect();
    let k = cols.len();
    let mut a = nalgebra::DMatrix::zeros(n + k, k);
    let mut b = nalgebra::DVector::zeros(n + k);
    for (i, (r, yi)) in x.iter().zip(y).enumerate() {
        for (j, &c) in cols.iter().enumerate() {
            a[(i, j)] = r[c];
        }
        b[i] = *yi;
    }
    for (j, &c) in cols.iter().enumerate() {
        let w = (1e-3 * scale[c].max(1e-6)).sqrt();
        a[(n + j, j)] = w;
        b[n + j] = w * prior[c];
    }
    let mut p = prior;
    match qr_solve(a, b) {
        Some(fit) => {
            for (&c, v) in cols.iter().zip(fit.iter()) {
                p[c] = *v;
            }
            p
        }
        None => prior,
    }
}

/// The `p` that minimises `Σ (rows[i] · p - y[i])²`, by nalgebra's Householder QR of the
/// rows (no normal equations, so no squared condition number). `None` if there are fewer
/// rows than unknowns, the rows do not have full column rank, or the answer is not finite.
/// Householder reflections take only square roots, which IEEE 754 rounds the same on every
/// platform: the same rows give the same bits everywhere.
///
/// ```
/// use vitro_calibrate::fit::qr_least_squares;
/// // y = 2 + 3 x, four points.
/// let rows = [[1.0, 0.0], [1.0, 1.0], [1.0, 2.0], [1.0, 3.0]];
/// let y = [2.0, 5.0, 8.0, 11.0];
/// let [a, b] = qr_least_squares(&rows, &y).unwrap();
/// assert!((a - 2.0).abs() < 1e-12 && (b - 3.0).abs() < 1e-12);
/// assert!(qr_least_squares(&[[1.0, 2.0]], &[3.0]).is_none()); // one row, two unknowns
/// ```
pub fn qr_least_squares<const N: usize>(rows: &[[f64; N]], y: &[f64]) -> Option<[f64; N]> {
    let m = rows.len().min(y.len());
    let a = nalgebra::DMatrix::from_fn(m, N, |i, j| rows[i][j]);
    let b = nalgebra::DVector::from_fn(m, |i, _| y[i]);
    let p = qr_solve(a, b)?;
    let mut out = [0.0; N];
    for (o, v) in out.iter_mut().zip(p.iter()) {
        *o = *v;
    }
    Some(out)
}

/// Least squares of `a p ≈ b` by Householder QR: `None` without full column rank (or more
/// columns than rows) or with a non-finite answer.
fn qr_solve(a: nalgebra::DMatrix<f64>, mut b: nalgebra::DVector<f64>) -> Option<Vec<f64>> {
    let (m, n) = a.shape();
    if n == 0 {
        return Some(Vec::new());
    }
    if m < n {
        return None;
    }
    let qr = a.qr();
    qr.q_tr_mul(&mut b);
    let r = qr.r();
    if r.diagonal().iter().any(|d| d.abs() < 1e-12) {
        return None;
    }
    let p = r.solve_upper_triangular(&b.rows(0, n).into_owned())?;
    p.iter()
        .all(|v| v.is_finite())
        .then(|| p.iter().copied().collect())
}

/// How many robust standard deviations (1.4826 × the median absolute deviation) a trip's
/// residual may be off before the fit leaves it out.
pub const SCREEN_SIGMAS: f64 = 5.0;

/// The trip model's least squares with an outlier screen: fit, leave out the trips whose
/// residual is more than [`SCREEN_SIGMAS`] robust standard deviations (and at least 2 s)
/// from the median residual, fit the rest again; up to three rounds, until the kept set
/// stands. A body that runs into a wall while it turns at its start takes minutes where
/// the others take seconds: one such trip would otherwise set the start-turn terms for all.
/// On the kept trips the start-turn knee (`epsilon`) then stays only where it predicts trips
/// it was not fitted on better than the model without it ([`knee_predicts`]); else it is 0.
/// Returns the parameters and how many trips were left out.
pub fn screened_fit(x: &[[f64; 6]], y: &[f64]) -> ([f64; 6], usize) {
    let mut keep = vec![true; x.len()];
    let mut p = least_squares(x, y, PRIOR);
    for _ in 0..3 {
        let res: Vec<f64> = x
            .iter()
            .zip(y)
            .map(|(r, yi)| yi - r.iter().zip(&p).map(|(a, b)| a * b).sum::<f64>())
            .collect();
        let med = median(res.clone());
        let mad = median(res.iter().map(|r| (r - med).abs()).collect());
        let bound = (SCREEN_SIGMAS * 1.4826 * mad).max(2.0);
        let next: Vec<bool> = res.iter().map(|r| (r - med).abs() <= bound).collect();
        if next == keep || next.iter().filter(|k| **k).count() < 8 {
            break;
        }
        keep = next;
        let (xs, ys) = kept(x, y, &keep);
        p = least_squares(&xs, &ys, PRIOR);
    }
    let (xs, ys) = kept(x, y, &keep);
    if !knee_predicts(&xs, &ys) {
        p = least_squares(&without_knee(&xs), &ys, PRIOR);
    }
    (p, keep.iter().filter(|k| !**k).count())
}

/// The rows of `x` and `y` whose `keep` is true.
fn kept(x: &[[f64; 6]], y: &[f64], keep: &[bool]) -> (Vec<[f64; 6]>, Vec<f64>) {
    x.iter()
        .zip(y)
        .zip(keep)
        .filter(|(_, k)| **k)
        .map(|((r, yi), _)| (*r, *yi))
        .unzip()
}

/// The trip model's neutral parameters, towards which [`least_squares`] pulls lightly.
const PRIOR: [f64; 6] = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0];

/// Whether the start-turn knee (the last column) predicts trips left out of the fit better
/// than the model without it: the leave-one-out mean squared error of both. A term the data
/// do not support (a knee fitted to a few noisy starts) predicts worse than none.
pub fn knee_predicts(x: &[[f64; 6]], y: &[f64]) -> bool {
    loo_mse(x, y) < loo_mse(&without_knee(x), y)
}

/// The rows with the knee's column set to 0 (its parameter then stays at its prior, 0).
fn without_knee(x: &[[f64; 6]]) -> Vec<[f64; 6]> {
    x.iter()
        .map(|r| [r[0], r[1], r[2], r[3], r[4], 0.0])
        .collect()
}

/// The mean squared error of predicting each row from a fit of all the others.
fn loo_mse(x: &[[f64; 6]], y: &[f64]) -> f64 {
    let n = x.len();
    if n < 2 {
        return 0.0;
    }
    let total: f64 = (0..n)
        .map(|i| {
            let keep: Vec<bool> = (0..n).map(|j| j != i).collect();
            let (xs, ys) = kept(x, y, &keep);
            let p = least_squares(&xs, &ys, PRIOR);
            let e = y[i] - x[i].iter().zip(&p).map(|(a, b)| a * b).sum::<f64>();
            e * e
        })
        .sum();
    total / n as f64
}

/// One run of the calibration: a trip at a level.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Job {
    pub(crate) trip: usize,
    pub(crate) level: Level,
}

/// Makes the calibration of `to` (abstract levels) from the trips: see the module doc.
/// `threads` threads run the trips (the result does not depend on their number); `tick` is
/// called after each run ([`runs_needed`] in all).
pub fn calibrate(
    setup: &Setup,
    trips: &[Trip],
    to: &[Level],
    stamp: &Stamp,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<Calibration, CheckError> {
    let feats: Vec<Features> = trips
        .iter()
        .map(|t| trips::features(setup, t))
        .collect::<Result<_, _>>()?;
    // Stage 1: the concrete level and the uncalibrated abstract levels.
    let mut jobs = Vec::new();
    for (i, t) in trips.iter().enumerate() {
        let (concrete, abs) = levels(t.kind);
        jobs.push(Job {
            trip: i,
            level: concrete,
        });
        for l in abs.into_iter().filter(|l| to.contains(l)) {
            jobs.push(Job { trip: i, level: l });
        }
    }
    let before = run_jobs(setup, trips, &jobs, None, threads, tick)?;
    let unfinished = before.iter().filter(|r| r.is_none()).count();
    let mut concrete: Vec<Option<f64>> = vec![None; trips.len()];
    let mut uncal: BTreeMap<(usize, Level), f64> = BTreeMap::new();
    for (j, r) in jobs.iter().zip(&before) {
        if j.level == levels(trips[j.trip].kind).0 {
            concrete[j.trip] = *r;
        } else if let Some(r) = r {
            uncal.insert((j.trip, j.level), *r);
        }
    }
    // Stage 2: the fits.
    let mut groups: BTreeMap<(String, Level), Vec<usize>> = BTreeMap::new();
    for (i, t) in trips.iter().enumerate() {
        for l in levels(t.kind).1.into_iter().filter(|l| to.contains(l)) {
            groups.entry((entity_key(t.kind), l)).or_default().push(i);
        }
    }
    let mut fits = Vec::new();
    for ((entity, level), idx) in &groups {
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for &i in idx.iter().filter(|&&i| trips[i].fit) {
            let (Some(c), Some(&u)) = (concrete[i], uncal.get(&(i, *level))) else {
                continue;
            };
            let f = &feats[i];
            // The discrete level hops on the profile's times; the interpolated level has its
            // own lag, which the stretch scales with it.
            let target = if *level == Level::Discrete {
                c
            } else {
                c * f.profile_s / u.max(1e-9)
            };
            x.push(f.row());
            y.push(target);
        }
        let (p, excluded) = screened_fit(&x, &y);
        fits.push(Fit {
            entity: entity.clone(),
            level: level.name().to_owned(),
            concrete: levels(trips[idx[0]].kind).0.name().to_owned(),
            alpha: p[0],
            beta: p[1],
            kappa: p[2],
            gamma: p[3],
            delta: p[4],
            epsilon: p[5],
            trips: x.len() - excluded,
            excluded,
            fit_residuals: Residuals::default(),
            held_out: Residuals::default(),
        });
    }
    let mut cal = Calibration {
        format: FORMAT,
        model: "T = alpha * T_profile + beta + kappa * turn_rad + gamma * climb_m + delta * \
                start_turn_rad + epsilon * max(0, start_turn_rad - pi/4)^2; the abstract \
                level's profile is stretched by T / T_profile"
            .into(),
        scenario: stamp.scenario.clone(),
        map: stamp.map.clone(),
        site_fingerprint: stamp.site_fingerprint.clone(),
        types_fingerprint: stamp.types_fingerprint.clone(),
        from: Level::Physical.name().into(),
        seed: stamp.seed,
        wall_s: 0.0,
        unfinished,
        fits,
        squads: Vec::new(),
        trips: Vec::new(),
        aircraft: Vec::new(),
        flights: Vec::new(),
    };
    // Stage 3: every trip again at the calibrated abstract levels.
    let jobs: Vec<Job> = jobs
        .into_iter()
        .filter(|j| j.level != levels(trips[j.trip].kind).0)
        .collect();
    let shared = Arc::new(cal.clone());
    let after = run_jobs(setup, trips, &jobs, Some(shared), threads, tick)?;
    cal.unfinished += after.iter().filter(|r| r.is_none()).count();
    let mut cal_t: BTreeMap<(usize, Level), f64> = BTreeMap::new();
    for (j, r) in jobs.iter().zip(&after) {
        if let Some(r) = r {
            cal_t.insert((j.trip, j.level), *r);
        }
    }
    for fit in &mut cal.fits {
        let level = if fit.level == "interpolated" {
            Level::Interpolated
        } else {
            Level::Discrete
        };
        let idx = &groups[&(fit.entity.clone(), level)];
        for (set, slot) in [(true, &mut fit.fit_residuals), (false, &mut fit.held_out)] {
            let (mut c, mut b, mut a) = (Vec::new(), Vec::new(), Vec::new());
            for &i in idx.iter().filter(|&&i| trips[i].fit == set) {
                if let (Some(ci), Some(&bi), Some(&ai)) =
                    (concrete[i], uncal.get(&(i, level)), cal_t.get(&(i, level)))
                {
                    c.push(ci);
                    b.push(bi);
                    a.push(ai);
                }
            }
            *slot = Residuals::of(&c, &b, &a);
        }
    }
    // Stage 4: the squads' pace at the discrete level, over the trip fits.
    if to.contains(&Level::Discrete) {
        cal.squads = crate::squad::fit_squad(setup, trips, &cal, threads, tick)?
            .into_iter()
            .collect();
    }
    for (i, t) in trips.iter().enumerate() {
        let Some(c) = concrete[i] else { continue };
        let (classes, bridge) = trips::coverage(setup, t);
        let pick = |m: &BTreeMap<(usize, Level), f64>| {
            m.iter()
                .filter(|((k, _), _)| *k == i)
                .map(|((_, l), v)| (l.name().to_owned(), *v))
                .collect::<BTreeMap<String, f64>>()
        };
        cal.trips.push(TripRecord {
            entity: entity_key(t.kind),
            set: if t.fit { "fit" } else { "held_out" }.into(),
            from: t.from.0,
            to: t.to.0,
            classes,
            bridge,
            features: feats[i],
            concrete_s: c,
            before_s: pick(&uncal),
            after_s: pick(&cal_t),
        });
    }
    Ok(cal)
}

/// Runs the jobs on `threads` threads; the arrival time of each, in order.
pub(crate) fn run_jobs(
    setup: &Setup,
    trips: &[Trip],
    jobs: &[Job],
    calibration: Option<Arc<Calibration>>,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Option<f64>>, CheckError> {
    let out = par_map(
        jobs,
        threads,
        |j| trips::run(setup, &trips[j.trip], j.level, calibration.clone()),
        tick,
    );
    if out.len() != jobs.len() {
        return Err(CheckError::Scenario {
            scenario: "calibration".into(),
            message: "a trip's run failed".into(),
        });
    }
    // A trip whose body gave up (stalled) at some level has no time there: it is left out
    // of the fit and the residuals (the file lists the trips that have every time).
    Ok(out.into_iter().map(|r| r.ok().flatten()).collect())
}
