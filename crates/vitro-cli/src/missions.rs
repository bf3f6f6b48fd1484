//! The missions this binary knows ([`vitro_tools::registry`]): every command looks a
//! scenario file's `kind` up there, and knows no mission by name.

use crate::Failure;
use std::path::Path;
use vitro_mission::RegistryError;
pub(crate) use vitro_tools::registry;

/// A registry error about the scenario at `path` as a failure: bad input (exit 2) or a run
/// that could not be set up (exit 1).
pub(crate) fn failure(path: &Path, e: RegistryError) -> Failure {
    vitro_tools::scenario_error(path, e).into()
}
