//! Making runs: one run guarded against panics, a set of runs in parallel recorded in the
//! journal as each ends, and the rounds of a conditioned experiment.

use crate::design::RunSpec;
use crate::experiment::Experiment;
use crate::journal::{Journal, JournalError, RunRecord, Status};
use crate::runner::{RunOutput, RunSettings, Runner, SeriesRow};
use crate::stop::{PointStop, StopReport, StopRule};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

/// Makes the runs `specs` on `pool`, appending each record to `journal` as it ends and then
/// calling `done` with it; returns the records in the order they ended.
pub(crate) fn execute_all(
    pool: &rayon::ThreadPool,
    exp: &Experiment,
    runner: &dyn Runner,
    specs: &[RunSpec],
    journal: &Mutex<Journal>,
    done: &(dyn Fn(&RunRecord) + Sync),
) -> Result<Vec<RunRecord>, JournalError> {
    let records = Mutex::new(Vec::with_capacity(specs.len()));
    pool.install(|| {
        specs
            .par_iter()
            .with_max_len(1)
            .try_for_each(|spec| -> Result<(), JournalError> {
                let rec = execute(exp, runner, spec);
                journal
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .append(&rec)?;
                done(&rec);
                records
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .push(rec);
                Ok(())
            })
    })?;
    Ok(records.into_inner().unwrap_or_else(PoisonError::into_inner))
}

/// Makes one run; an error or a panic is a failed record.
pub(crate) fn execute(exp: &Experiment, runner: &dyn Runner, spec: &RunSpec) -> RunRecord {
    let scenario = exp.scenario_for(&spec.params);
    let settings = RunSettings {
        end_s: exp.end_s,
        keep: &exp.keep,
    };
    let t0 = Instant::now();
    let outcome = run_guarded(runner, &scenario, spec.seed, &settings);
    let wall_s = t0.elapsed().as_secs_f64();
    let mut rec = RunRecord {
        run: spec.run,
        point: spec.point,
        replicate: spec.replicate,
        seed: spec.seed,
        params: spec.params.iter().cloned().collect(),
        status: Status::Ok,
        error: None,
        wall_s,
        metrics: Default::default(),
        series: Vec::new(),
    };
    match outcome {
        Ok(out) => {
            let keep = &exp.keep;
            rec.metrics = out
                .metrics
                .into_iter()
                .filter(|(k, _)| keep.metrics.contains(k))
                .collect();
            if !keep.series.is_empty() {
                rec.series = out
                    .series
                    .into_iter()
                    .map(|s| SeriesRow {
                        t_s: s.t_s,
                        values: s
                            .values
                            .into_iter()
                            .filter(|(k, _)| keep.series.contains(k))
                            .collect(),
                    })
                    .collect();
            }
        }
        Err(message) => {
            rec.status = Status::Failed;
            rec.error = Some(message);
        }
    }
    rec
}

/// Makes the runs of a conditioned experiment missing from `records` (which holds those
/// of earlier sessions and gets the new ones), round by round; returns each point's outcome.
pub(crate) fn run_rounds(
    pool: &rayon::ThreadPool,
    exp: &Experiment,
    runner: &dyn Runner,
    rule: &StopRule,
    journal: &Mutex<Journal>,
    records: &mut Vec<RunRecord>,
    done: &(dyn Fn(&RunRecord) + Sync),
) -> Result<StopReport, JournalError> {
    let design = &exp.design;
    let points = design.points().unwrap_or(0);
    let most = design.replicates;
    let run_of = |p: u64, r: u32| p * u64::from(most) + u64::from(r);
    let mut have: BTreeMap<u64, RunRecord> = records.drain(..).map(|r| (r.run, r)).collect();
    // Replicates each open point needs now; closed points move to `outcome`.
    let mut open: BTreeMap<u64, u32> = (0..points).map(|p| (p, rule.min_replicates)).collect();
    let mut outcome: BTreeMap<u64, PointStop> = BTreeMap::new();
    while !open.is_empty() {
        let specs: Vec<RunSpec> = open
            .iter()
            .flat_map(|(&p, &n)| (0..n).map(move |r| run_of(p, r)))
            .filter(|k| !have.contains_key(k))
            .filter_map(|k| design.run(k))
            .collect();
        for rec in execute_all(pool, exp, runner, &specs, journal, done)? {
            have.insert(rec.run, rec);
        }
        let mut next = BTreeMap::new();
        for (p, n) in open {
            let mine: Vec<&RunRecord> = (0..n).filter_map(|r| have.get(&run_of(p, r))).collect();
            let (mean, half_width) = rule.estimate(&mine);
            let met = half_width <= rule.half_width;
            if met || n >= most {
                outcome.insert(
                    p,
                    PointStop {
                        point: p,
                        replicates: n,
                        mean,
                        half_width,
                        met,
                    },
                );
            } else {
                next.insert(p, n + 1);
            }
        }
        open = next;
    }
    // Records of earlier sessions past a point's stop (a resume after the rule changed
    // cannot happen: the experiment's bytes are checked) stay in the journal and tables.
    records.extend(have.into_values());
    Ok(StopReport {
        rule: rule.clone(),
        points: outcome.into_values().collect(),
    })
}

/// Runs `scenario` with `seed`; a panic becomes an error (`panicked: ...`).
pub(crate) fn run_guarded(
    runner: &dyn Runner,
    scenario: &toml::Table,
    seed: u64,
    settings: &RunSettings<'_>,
) -> Result<RunOutput, String> {
    match catch_unwind(AssertUnwindSafe(|| runner.run(scenario, seed, settings))) {
        Ok(result) => result,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a non-text payload".to_owned());
            Err(format!("panicked: {what}"))
        }
    }
}
