//! [`run_search`]: the generations of a search, recorded in the batch journal, then the
//! tables, `found.csv` and the shrunk failures.

use super::cem::{Coord, Rank, Sampler, Strategy};
use super::error::SearchError;
use super::found;
use super::shrink::{self, Case};
use super::spec::{Range, Search};
use crate::design::{Origin, RunSpec, seed_of};
use crate::exec::{BatchError, Progress, failures, open_dir, pool};
use crate::experiment::Experiment;
use crate::journal::{RunRecord, Status};
use crate::make::execute_all;
use crate::manifest::{self, Manifest, MinimalInfo, ParamInfo, RunEntry, SearchInfo};
use crate::runner::Runner;
use crate::table_out;
use crate::value::Value;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// How to run a search.
#[derive(Clone, Debug)]
pub struct SearchOptions {
    /// The result directory (created if needed).
    pub out: PathBuf,
    /// Worker threads (at least 1).
    pub jobs: usize,
    /// Complete the search in `out` instead of refusing a directory with results.
    pub resume: bool,
    /// Evaluations (default: the experiment's `[search] budget`).
    pub budget: Option<u64>,
    /// Adaptive (CEM) or random.
    pub strategy: Strategy,
    /// The search seed (default: the experiment's `seed`).
    pub seed: Option<u64>,
    /// Failures to shrink (default: the experiment's `[search] shrink`).
    pub shrink: Option<u32>,
}

/// What a search reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum SearchEvent<'a> {
    /// A search run ended.
    Run(Progress<'a>),
    /// Shrinking of failing run `run` starts: the `index`-th of `count`, at most `budget` runs.
    Shrink {
        /// The failing run.
        run: u64,
        /// Which shrink (0-based).
        index: usize,
        /// How many.
        count: usize,
        /// Its budget of runs.
        budget: u32,
    },
    /// A shrink run ended.
    ShrinkRun,
}

/// What a search did and found.
#[derive(Clone, Debug)]
pub struct SearchReport {
    /// Evaluations of the search.
    pub planned: u64,
    /// Evaluations found done (resume).
    pub skipped: u64,
    /// Evaluations made now.
    pub ran: u64,
    /// Whether a torn last journal line was dropped.
    pub torn_dropped: bool,
    /// Runs that could not run (errors, panics): (run, error).
    pub errors: Vec<(u64, String)>,
    /// The failing runs found, in run order.
    pub failures: Vec<u64>,
    /// The shrunk failures written.
    pub minimal: Vec<MinimalInfo>,
    /// Wall-clock seconds of this session.
    pub wall_s: f64,
    /// Files written (tables, found.csv, minimal scenarios).
    pub files: Vec<PathBuf>,
}

/// Runs the search of `exp` (its `[search]` table) with `opts`, calling `progress` as it
/// goes; then writes the manifest, the tables, `found.csv` and the shrunk failures.
pub fn run_search(
    exp: &Experiment,
    runner: &dyn Runner,
    opts: &SearchOptions,
    progress: &(dyn Fn(SearchEvent<'_>) + Sync),
) -> Result<SearchReport, SearchError> {
    let started = Instant::now();
    let search = exp
        .search
        .as_ref()
        .ok_or_else(|| SearchError::NoSearch(exp.path.clone()))?;
    let budget = opts.budget.unwrap_or(search.budget).max(1);
    let seed = opts.seed.unwrap_or(exp.design.base_seed);
    let pop = u64::from(search.population);
    let dir = opts.out.as_path();

    let mut manifest = Manifest::new(exp, None);
    // The seed has its own column: a searched seed's range goes with the search's settings.
    manifest.parameters = (search.dims.iter())
        .filter(|d| d.path != "seed")
        .map(param_info)
        .collect();
    manifest.replicates = 1;
    manifest.runs_total = budget;
    manifest.runs = Vec::new();
    manifest.search = Some(SearchInfo {
        strategy: opts.strategy.as_str().into(),
        seed,
        budget,
        population: search.population,
        elite: search.elite,
        objective: search.objective.describe(),
        seed_range: search.dims.iter().find_map(|d| match d.range {
            Range::Seed { low, high } => Some([low, high]),
            _ => None,
        }),
        failures: 0,
        minimal: Vec::new(),
    });
    let (journal, reading) = open_dir(dir, &mut manifest, opts.resume)?;
    let mut have: BTreeMap<u64, RunRecord> = BTreeMap::new();
    for rec in reading.records {
        if rec.run >= budget {
            return Err(mismatch(
                dir,
                format!("it holds run {}, beyond the budget of {budget}", rec.run),
            ));
        }
        have.insert(rec.run, rec);
    }
    let skipped = have.len() as u64;
    let jobs = opts.jobs.max(1);
    manifest.sessions.push(manifest::session(jobs));
    manifest.save(dir)?;

    let pool = pool(jobs)?;
    let journal = Mutex::new(journal);
    let counter = AtomicU64::new(skipped);
    let ranges: Vec<Range> = search.dims.iter().map(|d| d.range.clone()).collect();
    let mut sampler = Sampler::new(opts.strategy, seed, ranges, search.elite);
    let mut points: BTreeMap<u64, Vec<Coord>> = BTreeMap::new();
    let mut ran = 0;
    for g in 0..budget.div_ceil(pop) {
        // Always draw a whole generation, so a larger budget on resume extends this one.
        let drawn = sampler.propose(g, search.population as usize);
        let count = pop.min(budget - g * pop) as usize;
        let mut specs = Vec::with_capacity(count);
        for (i, point) in drawn.into_iter().take(count).enumerate() {
            let k = g * pop + i as u64;
            let spec = spec_of(search, &sampler.values(&point), k, seed);
            if let Some(rec) = have.get(&k)
                && (rec.seed != spec.seed || rec.params != spec.params.iter().cloned().collect())
            {
                return Err(mismatch(
                    dir,
                    format!("its run {k} is not the run this search makes there"),
                ));
            }
            manifest.runs.push(RunEntry {
                run: k,
                seed: spec.seed,
                status: "pending".into(),
            });
            points.insert(k, point);
            specs.push(spec);
        }
        let missing: Vec<RunSpec> = specs
            .iter()
            .filter(|s| !have.contains_key(&s.run))
            .cloned()
            .collect();
        let made = execute_all(&pool, exp, runner, &missing, &journal, &|rec| {
            let done = counter.fetch_add(1, Ordering::Relaxed) + 1;
            progress(SearchEvent::Run(Progress {
                done,
                total: budget,
                before: skipped,
                record: rec,
            }));
        })?;
        ran += made.len() as u64;
        for rec in made {
            have.insert(rec.run, rec);
        }
        let evaluated = specs
            .iter()
            .map(|s| {
                let rank = have
                    .get(&s.run)
                    .filter(|r| r.status == Status::Ok)
                    .map(|r| Rank {
                        fails: search.objective.fails(&r.metrics),
                        score: search.objective.score(&r.metrics),
                        run: r.run,
                    });
                (points[&s.run].clone(), rank)
            })
            .collect();
        sampler.observe(evaluated);
    }
    drop(journal);

    let records: Vec<RunRecord> = have.into_values().collect();
    let failing: Vec<&RunRecord> = records
        .iter()
        .filter(|r| r.status == Status::Ok && search.objective.fails(&r.metrics))
        .collect();
    manifest.set_statuses(&records);
    let mut files = table_out::write_tables(dir, &manifest, &records)?;
    files.push(found::write(dir, &manifest, search, &failing)?);

    // Shrink the most different failures.
    let chosen = found::distinct(&failing, &points, opts.shrink.unwrap_or(search.shrink));
    let mut minimal: Vec<MinimalInfo> = Vec::new();
    for (index, rec) in chosen.iter().enumerate() {
        progress(SearchEvent::Shrink {
            run: rec.run,
            index,
            count: chosen.len(),
            budget: search.shrink_budget,
        });
        let start = Case {
            base: exp.scenario.clone(),
            params: rec
                .params
                .iter()
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect(),
            seed: rec.seed,
            end_s: exp.end_s,
        };
        let done = shrink::shrink(
            &pool,
            runner,
            &exp.keep,
            &search.objective,
            &search.dims,
            start.clone(),
            rec.metrics.clone(),
            search.shrink_budget,
            &|| progress(SearchEvent::ShrinkRun),
        );
        // Failures that shrink to the same run (same trace hash) are one failure.
        let hash = match done.metrics.get("trace_hash") {
            Some(Value::Text(h)) => h.clone(),
            _ => String::new(),
        };
        if let Some(m) = minimal
            .iter_mut()
            .find(|m| !hash.is_empty() && m.trace_hash == hash)
        {
            m.also.push(rec.run);
            continue;
        }
        let (info, path) = found::write_minimal(dir, runner, search, rec, &start, &done, &hash)?;
        files.push(path);
        minimal.push(info);
    }
    if let Some(s) = manifest.search.as_mut() {
        s.failures = failing.len() as u64;
        s.minimal = minimal.clone();
    }
    if let Some(s) = manifest.sessions.last_mut() {
        s.finished = Some(manifest::now());
        s.runs_done = ran;
    }
    manifest.save(dir)?;
    Ok(SearchReport {
        planned: budget,
        skipped,
        ran,
        torn_dropped: reading.torn,
        errors: failures(&records),
        failures: failing.iter().map(|r| r.run).collect(),
        minimal,
        wall_s: started.elapsed().as_secs_f64(),
        files,
    })
}

fn mismatch(dir: &std::path::Path, why: String) -> SearchError {
    SearchError::Batch(BatchError::Mismatch {
        dir: dir.to_owned(),
        why,
    })
}

/// The manifest's entry for a searched parameter: its range's ends or its choices.
fn param_info(d: &super::spec::Dim) -> ParamInfo {
    let levels = match &d.range {
        Range::Float { low, high } => vec![Value::Float(*low), Value::Float(*high)],
        Range::Int { low, high } => vec![Value::Int(*low), Value::Int(*high)],
        Range::Seed { low, high } => vec![
            Value::Int(i64::try_from(*low).unwrap_or(i64::MAX)),
            Value::Int(i64::try_from(*high).unwrap_or(i64::MAX)),
        ],
        Range::Choice(v) => v.clone(),
    };
    ParamInfo {
        path: d.path.clone(),
        origin: Origin::Search,
        levels,
    }
}

/// Run `k` with the point's `values`: the seed from a searched `seed`, else
/// `seed_of(search seed, k) >> 1` (63 bits, so that a scenario file's TOML integer holds it);
/// the other values as scenario parameters.
fn spec_of(search: &Search, values: &[Value], k: u64, seed: u64) -> RunSpec {
    let mut run_seed = seed_of(seed, k) >> 1;
    let mut params = Vec::with_capacity(values.len());
    for (d, v) in search.dims.iter().zip(values) {
        if d.path == "seed" {
            if let Value::Int(s) = v {
                run_seed = *s as u64;
            }
        } else {
            params.push((d.path.clone(), v.clone()));
        }
    }
    RunSpec {
        run: k,
        point: k,
        replicate: 0,
        seed: run_seed,
        params,
    }
}
