//! `vitro validate`: checks a scenario file without running it.
//!
//! A mission scenario (one with `[site]` or `[[entity]]`) is checked by
//! [`ScenarioFile::validate`]: every problem is printed on stderr with its place and what was
//! expected, and the exit code is 2. Any other file is taken for the patrolling-cars demo.

use crate::Failure;
use std::path::Path;
use vitro_tactical::scenario::{ScenarioFile, Validated};

/// Validates the scenario at `path` and prints a one-line summary on stdout.
pub(crate) fn validate(path: &Path) -> Result<(), Failure> {
    if !is_mission(path) {
        return crate::run::validate(path);
    }
    match ScenarioFile::validate(path) {
        Ok(v) => {
            println!("{}", summary(path, &v));
            Ok(())
        }
        Err(d) => {
            let n = d.len();
            let problems = if n == 1 { "problem" } else { "problems" };
            Err(Failure::Input(anyhow::anyhow!(
                "invalid scenario {}: {n} {problems}\n{}",
                path.display(),
                d.render()
            )))
        }
    }
}

/// True if the file at `path` looks like a mission scenario: its top level has `site` or
/// `entity` (or, when it is not valid TOML, a line starts a `[site]` or `[[entity]]` table).
/// An unreadable file is left to the demo's loader, which reports it.
pub(crate) fn is_mission(path: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(path) else {
        return false;
    };
    match text.parse::<toml::Table>() {
        Ok(t) => t.contains_key("site") || t.contains_key("entity"),
        Err(_) => text.lines().map(str::trim_start).any(|l| {
            l.starts_with("[site]") || l.starts_with("[[entity]]") || l.starts_with("site =")
        }),
    }
}

/// `FILE: ok (name: N entities in G groups, map on terrain, T s, fidelity L)`.
fn summary(path: &Path, v: &Validated) -> String {
    let f = &v.loaded.file;
    let entities: u64 = f.entities.iter().map(|e| u64::from(e.count)).sum();
    let name = |p: &Path| {
        p.file_name()
            .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
    };
    format!(
        "{}: ok ({:?}: {entities} entities in {} groups, {} on {}, {} simulated seconds, fidelity {})",
        path.display(),
        f.name,
        f.entities.len(),
        name(&v.loaded.map),
        name(&v.loaded.terrain),
        f.end.time_s,
        format!("{:?}", f.fidelity.level).to_lowercase(),
    )
}
