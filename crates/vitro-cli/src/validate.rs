//! `vitro validate`: checks a scenario file (or an experiment file) without running it.
//!
//! A scenario's `kind` names its mission, which checks it: every problem is printed on stderr
//! with its place and what was expected, and the exit code is 2. An experiment (a file with
//! a top-level `scenario` string) is checked as `vitro batch` and `vitro search` load it.

use crate::Failure;
use crate::missions::{failure, registry};
use std::path::Path;

/// Validates the scenario (or experiment) at `path` and prints a one-line summary on stdout.
pub(crate) fn validate(path: &Path) -> Result<(), Failure> {
    if is_experiment(path) {
        let runner = crate::batch::runner_for(path);
        let exp = crate::batch::load(path, runner.as_ref())?;
        let what = match &exp.search {
            Some(s) => format!(
                "a search over {} parameters, {} runs",
                s.dims.len(),
                s.budget
            ),
            None => format!("{} runs", exp.design.runs().unwrap_or(0)),
        };
        println!("{}: ok (experiment {:?}: {what})", path.display(), exp.name);
        return Ok(());
    }
    let (_, summary) = registry().validate(path).map_err(|e| failure(path, e))?;
    println!("{}: ok ({summary})", path.display());
    Ok(())
}

/// True if the file at `path` is an experiment: TOML with a top-level `scenario` string.
fn is_experiment(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.get("scenario").is_some_and(toml::Value::is_str))
}
