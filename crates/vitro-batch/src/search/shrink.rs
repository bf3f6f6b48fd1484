//! Shrinking a failing run to a minimal one that still fails, as property-based testing
//! does: greedy, first improvement, each step a smaller run.
//!
//! A run is the base scenario with some elements of its arrays of tables removed (the
//! mission's `[[entity]]` groups), the searched parameters' values, a seed and an end time.
//! The steps tried, in this order, from the current run:
//!
//! 1. end at the failure: the end time cut to just past the run's `sim_time_s` (a mission
//!    stops when it is decided);
//! 2. remove one element of an array of tables (the last first): fewer entity groups;
//! 3. lower an element's integer `count` to 1, to half, or by one: fewer entities;
//! 4. move a searched parameter to the scenario's own value, or half-way there (a `count`
//!    only downward); the seed to the scenario's.
//!
//! The candidates are run in chunks of [`CHUNK`] in parallel; the first (in this order) that
//! still fails becomes the current run, and the steps start over, skipping those that did not
//! fail before (they seldom do later); once none is left, one full pass tries every step
//! again. Shrinking ends when a full pass finds no step that fails, or the budget is spent. The chunk size is fixed, so the result does not depend on
//! the job count. A step the scenario rejects (a run error, e.g. the mission without its
//! truck) just does not fail.

use super::spec::{Dim, Objective, Range};
use crate::keys::{scenario_kind, set_path};
use crate::make::run_guarded;
use crate::runner::{Keep, RunSettings, Runner};
use crate::value::Value;
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet};

/// Candidates run at once.
pub const CHUNK: usize = 4;

/// One run to try: the scenario (with removals), the searched values, seed and end time.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// The base scenario with elements removed.
    pub base: toml::Table,
    /// Searched parameters' values, by dotted key (paths follow the removals).
    pub params: Vec<(String, Value)>,
    /// The seed.
    pub seed: u64,
    /// End time override.
    pub end_s: Option<f64>,
}

impl Case {
    /// The scenario to run.
    pub fn scenario(&self) -> toml::Table {
        let mut t = self.base.clone();
        for (p, v) in &self.params {
            set_path(&mut t, p, v.to_toml());
        }
        t
    }

    /// Entity groups and entities: the elements of the arrays of tables and the sum of
    /// their `count`s (1 where absent).
    pub fn size(&self) -> (usize, i64) {
        let t = self.scenario();
        let mut groups = 0;
        let mut total = 0;
        for v in t.values() {
            if let toml::Value::Array(items) = v {
                for item in items.iter().filter_map(toml::Value::as_table) {
                    groups += 1;
                    total += item
                        .get("count")
                        .and_then(toml::Value::as_integer)
                        .unwrap_or(1);
                }
            }
        }
        (groups, total)
    }
}

/// What a shrink ended with.
#[derive(Clone, Debug)]
pub struct Shrunk {
    /// The smallest failing run found.
    pub case: Case,
    /// Its metrics.
    pub metrics: BTreeMap<String, Value>,
    /// Runs made.
    pub runs: u32,
    /// The steps taken, in words.
    pub changes: Vec<String>,
}

/// Shrinks the failing run `start` (with its `metrics`) within `budget` runs on `pool`,
/// calling `on_run` after each run.
#[allow(clippy::too_many_arguments)]
pub fn shrink(
    pool: &rayon::ThreadPool,
    runner: &dyn Runner,
    keep: &Keep,
    objective: &Objective,
    dims: &[Dim],
    start: Case,
    metrics: BTreeMap<String, Value>,
    budget: u32,
    on_run: &(dyn Fn() + Sync),
) -> Shrunk {
    let default_seed = dims
        .iter()
        .find(|d| d.path == "seed")
        .and_then(|d| d.default.as_ref())
        .and_then(Value::as_f64)
        .map(|s| s as u64);
    let mut best = Shrunk {
        case: start,
        metrics,
        runs: 0,
        changes: Vec::new(),
    };
    // Steps that did not fail are skipped until a full pass over every step (of the run as
    // it is then) finds none that fails: the end.
    let mut rejected: BTreeSet<String> = BTreeSet::new();
    let mut full = false;
    'steps: loop {
        let candidates: Vec<(String, Case)> = steps(&best.case, &best.metrics, dims, default_seed)
            .into_iter()
            .filter(|(what, _)| full || !rejected.contains(what))
            .collect();
        for chunk in candidates.chunks(CHUNK) {
            let left = budget.saturating_sub(best.runs) as usize;
            if left == 0 {
                break 'steps;
            }
            let chunk = &chunk[..chunk.len().min(left)];
            let results: Vec<Option<BTreeMap<String, Value>>> = pool.install(|| {
                chunk
                    .par_iter()
                    .with_max_len(1)
                    .map(|(_, case)| {
                        let settings = RunSettings {
                            end_s: case.end_s,
                            keep,
                        };
                        let out = run_guarded(runner, &case.scenario(), case.seed, &settings);
                        on_run();
                        out.ok().map(|o| o.metrics).filter(|m| objective.fails(m))
                    })
                    .collect()
            });
            best.runs += chunk.len() as u32;
            let first = results
                .into_iter()
                .enumerate()
                .find_map(|(i, r)| r.map(|m| (i, m)));
            let tried = first.as_ref().map_or(chunk.len(), |(i, _)| *i);
            rejected.extend(chunk[..tried].iter().map(|(what, _)| what.clone()));
            if let Some((i, m)) = first {
                best.case = chunk[i].1.clone();
                best.metrics = m;
                best.changes.push(chunk[i].0.clone());
                full = false;
                continue 'steps;
            }
        }
        if full {
            break;
        }
        full = true;
    }
    best
}

/// The smaller runs to try from `case`, best first, each with its description.
fn steps(
    case: &Case,
    metrics: &BTreeMap<String, Value>,
    dims: &[Dim],
    default_seed: Option<u64>,
) -> Vec<(String, Case)> {
    let mut out = Vec::new();
    // 1. End just past the failure.
    if let Some(t) = metrics.get("sim_time_s").and_then(Value::as_f64)
        && t.is_finite()
        && t > 0.0
    {
        let end = t.ceil() + 1.0;
        if case.end_s.is_none_or(|e| end < e) {
            let what = match case.end_s {
                Some(e) => format!("end time {e} s -> {end} s"),
                None => format!("end time -> {end} s"),
            };
            out.push((
                what,
                Case {
                    end_s: Some(end),
                    ..case.clone()
                },
            ));
        }
    }
    let scenario = case.scenario();
    let arrays: Vec<(&String, Vec<&toml::Table>)> = scenario
        .iter()
        .filter_map(|(k, v)| {
            let items: Vec<&toml::Table> =
                v.as_array()?.iter().filter_map(|x| x.as_table()).collect();
            (!items.is_empty()).then_some((k, items))
        })
        .collect();
    // 2. Fewer groups.
    for (key, items) in &arrays {
        for i in (0..items.len()).rev() {
            let name = items[i]
                .get("name")
                .and_then(toml::Value::as_str)
                .map(|n| format!(" ({n})"))
                .unwrap_or_default();
            out.push((format!("remove {key}.{i}{name}"), remove(case, key, i)));
        }
    }
    // 3. Smaller groups.
    for (key, items) in &arrays {
        for (i, item) in items.iter().enumerate() {
            let Some(c) = item.get("count").and_then(toml::Value::as_integer) else {
                continue;
            };
            let mut targets = vec![1, c / 2, c - 1];
            targets.retain(|&t| t >= 1 && t < c);
            targets.dedup();
            for t in targets {
                let path = format!("{key}.{i}.count");
                out.push((
                    format!("{path} {c} -> {t}"),
                    with_value(case, &path, Value::Int(t)),
                ));
            }
        }
    }
    // 4. Parameters toward the scenario's values.
    for (path, v) in &case.params {
        let Ok(d) = scenario_kind(&case.base, path) else {
            continue;
        };
        // An entity count never goes back up: fewer entities is the point.
        let count = path.ends_with(".count");
        if *v == d || (count && d.as_f64() > v.as_f64()) {
            continue;
        }
        let mut to_default = case.clone();
        to_default.params.retain(|(p, _)| p != path);
        out.push((format!("{path} {v} -> {d} (the scenario's)"), to_default));
        let width = dims
            .iter()
            .find(|x| &x.path == path)
            .map(|x| match x.range {
                Range::Float { low, high } => high - low,
                _ => 0.0,
            });
        let half = match (v, &d) {
            (Value::Int(x), Value::Int(y)) => Some(Value::Int(y + (x - y) / 2)),
            (Value::Float(x), Value::Float(y)) if (x - y).abs() > 0.02 * width.unwrap_or(0.0) => {
                Some(Value::Float((x + y) / 2.0))
            }
            _ => None,
        };
        if let Some(h) = half.filter(|h| h != v && *h != d) {
            out.push((format!("{path} {v} -> {h}"), with_value(case, path, h)));
        }
    }
    if let Some(s) = default_seed.filter(|&s| s != case.seed) {
        out.push((
            format!("seed {} -> {s} (the scenario's)", case.seed),
            Case {
                seed: s,
                ..case.clone()
            },
        ));
    }
    out
}

/// `case` with the value at `path` set: a searched parameter's value if it is one, else the
/// base scenario's.
fn with_value(case: &Case, path: &str, v: Value) -> Case {
    let mut c = case.clone();
    match c.params.iter_mut().find(|(p, _)| p == path) {
        Some((_, x)) => *x = v,
        None => set_path(&mut c.base, path, v.to_toml()),
    }
    c
}

/// `case` without element `i` of the array of tables `key`; searched paths into later
/// elements move down by one, those into the removed element go.
fn remove(case: &Case, key: &str, i: usize) -> Case {
    let mut c = case.clone();
    if let Some(toml::Value::Array(items)) = c.base.get_mut(key)
        && i < items.len()
    {
        items.remove(i);
    }
    let prefix = format!("{key}.");
    c.params = c
        .params
        .into_iter()
        .filter_map(|(p, v)| {
            let Some(rest) = p.strip_prefix(&prefix) else {
                return Some((p, v));
            };
            let (index, tail) = rest.split_once('.').unwrap_or((rest, ""));
            match index.parse::<usize>() {
                Ok(j) if j == i => None,
                Ok(j) if j > i => Some((format!("{key}.{}.{tail}", j - 1), v)),
                _ => Some((p, v)),
            }
        })
        .collect();
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case() -> Case {
        let base: toml::Table = toml::from_str(
            "seed = 1\n[[entity]]\nname = 'a'\ncount = 4\n[[entity]]\nname = 'b'\n\
             [[entity]]\nname = 'c'\ncount = 2\nspeed = 1.0\n",
        )
        .unwrap();
        Case {
            base,
            params: vec![
                ("entity.2.speed".into(), Value::Float(3.0)),
                ("entity.0.count".into(), Value::Int(6)),
            ],
            seed: 9,
            end_s: Some(100.0),
        }
    }

    #[test]
    fn removal_renumbers_searched_paths() {
        let c = remove(&case(), "entity", 1);
        assert_eq!(c.params[0].0, "entity.1.speed");
        assert_eq!(c.scenario()["entity"].as_array().unwrap().len(), 2);
        let c = remove(&case(), "entity", 0);
        assert_eq!(c.params.len(), 1, "the removed group's parameter goes");
        assert_eq!(case().size(), (3, 9));
    }

    #[test]
    fn steps_go_toward_smaller_runs() {
        let m = BTreeMap::from([("sim_time_s".to_string(), Value::Float(41.5))]);
        let s = steps(&case(), &m, &[], Some(1));
        let names: Vec<&str> = s.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names[0], "end time 100 s -> 43 s");
        assert!(names.contains(&"remove entity.2 (c)"));
        assert!(names.contains(&"entity.0.count 6 -> 3"), "{names:?}");
        assert!(names.contains(&"entity.2.count 2 -> 1"));
        assert!(names.contains(&"entity.0.count 6 -> 4 (the scenario's)"));
        let up = Case {
            params: vec![("entity.0.count".into(), Value::Int(2))],
            ..case()
        };
        let s = steps(&up, &m, &[], None);
        assert!(
            !s.iter()
                .any(|(n, _)| n.starts_with("entity.0.count 2 -> 4")),
            "a count never goes back up"
        );
        assert!(names.contains(&"entity.2.speed 3.0 -> 1.0 (the scenario's)"));
        assert_eq!(*names.last().unwrap(), "seed 9 -> 1 (the scenario's)");
        // Every step makes the run smaller or moves it toward the scenario.
        for (_, c) in &s {
            assert_ne!(c, &case());
        }
    }
}
