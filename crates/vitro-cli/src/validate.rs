//! `vitro validate`: checks a scenario file without running it.
//!
//! The file's `kind` names its mission, which checks it: every problem is printed on stderr
//! with its place and what was expected, and the exit code is 2.

use crate::Failure;
use crate::missions::{failure, registry};
use std::path::Path;

/// Validates the scenario at `path` and prints a one-line summary on stdout.
pub(crate) fn validate(path: &Path) -> Result<(), Failure> {
    let (_, summary) = registry().validate(path).map_err(|e| failure(path, e))?;
    println!("{}: ok ({summary})", path.display());
    Ok(())
}
