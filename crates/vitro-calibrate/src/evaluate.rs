//! The property "the abstract level predicts the concrete one": trips the calibration did
//! not see, run at the concrete level and at each abstract level without and with the
//! calibration; per entity type and level, the relative errors before and after against a
//! stated tolerance.

use crate::fit::{Job, run_jobs};
use crate::trips::{Trip, levels};
use std::collections::BTreeMap;
use std::sync::Arc;
use vitro_check::CheckError;
use vitro_tactical::calibration::{Calibration, Residuals, entity_key};
use vitro_tactical::entity::Level;
use vitro_tactical::setup::Setup;

/// The concrete level and the paired times: concrete, before, after.
type Paired = (Level, Vec<f64>, Vec<f64>, Vec<f64>);

/// How well one abstract level predicts the concrete level for one entity type.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    /// The entity type.
    pub entity: String,
    /// The abstract level.
    pub level: Level,
    /// The concrete level.
    pub concrete: Level,
    /// Relative errors before and after calibration.
    pub residuals: Residuals,
    /// The tolerance on the mean absolute relative error after calibration, %.
    pub tolerance_pct: f64,
    /// True if the calibrated level's mean absolute error is within the tolerance.
    pub pass: bool,
}

/// Runs `trips` at their concrete levels and at the abstract levels `to`, without and with
/// `cal`, on `threads` threads; one [`Prediction`] per (entity type, level). `tick` is called
/// after each run (`trips × (1 + 2 × levels)` in all).
pub fn evaluate(
    setup: &Setup,
    cal: &Arc<Calibration>,
    trips: &[Trip],
    to: &[Level],
    tolerance_pct: f64,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Prediction>, CheckError> {
    let mut plain = Vec::new();
    let mut calibrated = Vec::new();
    for (i, t) in trips.iter().enumerate() {
        let (concrete, abs) = levels(t.kind);
        plain.push(Job {
            trip: i,
            level: concrete,
        });
        for l in abs.into_iter().filter(|l| to.contains(l)) {
            plain.push(Job { trip: i, level: l });
            calibrated.push(Job { trip: i, level: l });
        }
    }
    let before = run_jobs(setup, trips, &plain, None, threads, tick)?;
    let after = run_jobs(setup, trips, &calibrated, Some(cal.clone()), threads, tick)?;
    let mut conc: BTreeMap<usize, f64> = BTreeMap::new();
    let mut b: BTreeMap<(usize, Level), f64> = BTreeMap::new();
    for (j, r) in plain.iter().zip(before) {
        let Some(r) = r else { continue };
        if j.level == levels(trips[j.trip].kind).0 {
            conc.insert(j.trip, r);
        } else {
            b.insert((j.trip, j.level), r);
        }
    }
    let a: BTreeMap<(usize, Level), f64> = calibrated
        .iter()
        .zip(after)
        .filter_map(|(j, r)| r.map(|r| ((j.trip, j.level), r)))
        .collect();
    let mut groups: BTreeMap<(String, Level), Paired> = BTreeMap::new();
    for (&(i, level), &bi) in &b {
        if let (Some(&c), Some(&ai)) = (conc.get(&i), a.get(&(i, level))) {
            let (concrete, _) = levels(trips[i].kind);
            let g = groups.entry((entity_key(trips[i].kind), level)).or_insert((
                concrete,
                Vec::new(),
                Vec::new(),
                Vec::new(),
            ));
            g.1.push(c);
            g.2.push(bi);
            g.3.push(ai);
        }
    }
    Ok(groups
        .into_iter()
        .map(|((entity, level), (concrete, c, bf, af))| {
            let residuals = Residuals::of(&c, &bf, &af);
            Prediction {
                entity,
                level,
                concrete,
                pass: residuals.mape_pct_after <= tolerance_pct,
                residuals,
                tolerance_pct,
            }
        })
        .collect())
}
