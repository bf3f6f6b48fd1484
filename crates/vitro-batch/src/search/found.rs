//! What a search writes about its failures: `found.csv` (one row per failing run), the
//! choice of the failures to shrink, and the minimal scenarios `minimal/run-K.toml`.

use super::cem::Coord;
use super::error::SearchError;
use super::shrink::{Case, Shrunk};
use super::spec::Search;
use crate::journal::RunRecord;
use crate::manifest::{Manifest, MinimalInfo};
use crate::runner::Runner;
use crate::table::{Column, Table};
use crate::write_file::write_atomic;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Name of the table of failing runs.
pub const FOUND_FILE: &str = "found.csv";
/// Folder of the minimal failing scenarios.
pub const MINIMAL_DIR: &str = "minimal";

/// Writes `found.csv`: `run, generation, seed`, one column per searched parameter,
/// `objective` (the guide metric, else the failure's metric) and `trace_hash`.
pub(crate) fn write(
    dir: &Path,
    manifest: &Manifest,
    search: &Search,
    failing: &[&RunRecord],
) -> Result<PathBuf, SearchError> {
    let pop = u64::from(search.population);
    let mut columns = vec![
        Column::uint("run", failing.iter().map(|r| r.run).collect()),
        Column::uint("generation", failing.iter().map(|r| r.run / pop).collect()),
        Column::uint("seed", failing.iter().map(|r| r.seed).collect()),
    ];
    for p in &manifest.parameters {
        let cells = failing.iter().map(|r| r.params.get(&p.path).cloned());
        columns.push(Column::values(&p.path, cells.collect()));
    }
    let objective = failing.iter().map(|r| search.objective.value(&r.metrics));
    columns.push(Column::values("objective", objective.collect()));
    let hash = failing.iter().map(|r| r.metrics.get("trace_hash").cloned());
    columns.push(Column::values("trace_hash", hash.collect()));
    let table = Table {
        columns,
        rows: failing.len(),
    };
    let path = dir.join(FOUND_FILE);
    let fail = |message: String| SearchError::Write {
        path: path.clone(),
        message,
    };
    let bytes = table.to_csv().map_err(|e| fail(e.to_string()))?;
    write_atomic(&path, &bytes).map_err(|e| fail(e.to_string()))?;
    Ok(path)
}

/// Up to `n` failures far apart: the first one found, then again and again the one farthest
/// from those chosen (distance: the sum over the coordinates of the difference of an ordered
/// one, in units of its range, and 1 for a choice or seed that differs); ties go to the
/// earlier run.
pub(crate) fn distinct<'a>(
    failing: &[&'a RunRecord],
    points: &BTreeMap<u64, Vec<Coord>>,
    n: u32,
) -> Vec<&'a RunRecord> {
    let dist = |a: &[Coord], b: &[Coord]| -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| match (x, y) {
                (Coord::Unit(x), Coord::Unit(y)) => (x - y).abs(),
                (x, y) => f64::from(u8::from(x != y)),
            })
            .sum()
    };
    let mut chosen: Vec<&RunRecord> = Vec::new();
    let empty = Vec::new();
    let point = |r: &RunRecord| points.get(&r.run).unwrap_or(&empty);
    while chosen.len() < n as usize && chosen.len() < failing.len() {
        let next = failing
            .iter()
            .filter(|r| !chosen.iter().any(|c| c.run == r.run))
            .map(|r| {
                let d = chosen
                    .iter()
                    .map(|c| dist(point(r), point(c)))
                    .fold(f64::INFINITY, f64::min);
                (*r, d)
            })
            .fold(None::<(&RunRecord, f64)>, |best, (r, d)| match best {
                Some((_, bd)) if bd >= d => best,
                _ => Some((r, d)),
            });
        match next {
            Some((r, _)) => chosen.push(r),
            None => break,
        }
    }
    chosen
}

/// Writes the shrunk failure `done` of run `rec` as `minimal/run-K.toml`; returns its entry
/// and path.
pub(crate) fn write_minimal(
    dir: &Path,
    runner: &dyn Runner,
    search: &Search,
    rec: &RunRecord,
    start: &Case,
    done: &Shrunk,
    hash: &str,
) -> Result<(MinimalInfo, PathBuf), SearchError> {
    let folder = dir.join(MINIMAL_DIR);
    let name = format!("run-{}.toml", rec.run);
    let path = folder.join(&name);
    let fail = |message: String| SearchError::Write {
        path: path.clone(),
        message,
    };
    std::fs::create_dir_all(&folder).map_err(|e| fail(e.to_string()))?;
    let body = runner
        .scenario_file(
            &done.case.scenario(),
            done.case.seed,
            done.case.end_s,
            &folder,
        )
        .map_err(fail)?;
    let (g0, e0) = start.size();
    let (g1, e1) = done.case.size();
    let mut header = format!(
        "# Minimal failing scenario: `vitro search` run {} shrunk in {} runs.\n\
         # Objective: {}\n\
         # Entities: {g0} groups, {e0} entities -> {g1} groups, {e1} entities.\n",
        rec.run,
        done.runs,
        search.objective.describe()
    );
    for c in &done.changes {
        header.push_str(&format!("#   {c}\n"));
    }
    header.push_str(&format!(
        "# `vitro run {name}` fails again with this trace hash:\n# expected trace hash: {hash}\n\n"
    ));
    let text = header + &body;
    write_atomic(&path, text.as_bytes()).map_err(|e| fail(e.to_string()))?;
    let info = MinimalInfo {
        run: rec.run,
        file: format!("{MINIMAL_DIR}/{name}"),
        trace_hash: hash.to_owned(),
        runs: done.runs,
        changes: done.changes.clone(),
        also: Vec::new(),
    };
    Ok((info, path))
}
