//! The missions this binary knows: every command looks a scenario file's `kind` up here, and
//! knows no mission by name beyond this list.

use crate::Failure;
use std::path::Path;
use std::sync::OnceLock;
use vitro_mission::{MissionError, Registry, RegistryError};

/// The registry of the missions `vitro` runs.
pub(crate) fn registry() -> &'static Registry {
    static REGISTRY: OnceLock<Registry> = OnceLock::new();
    REGISTRY.get_or_init(|| {
        Registry::new(vec![
            &vitro_evac::Evacuation,
            &vitro_demo::PatrollingCars,
            &vitro_surveillance::Surveillance,
        ])
    })
}

/// A registry error about the scenario at `path` as a failure: bad input (exit 2) or a run
/// that could not be set up (exit 1).
pub(crate) fn failure(path: &Path, e: RegistryError) -> Failure {
    match e {
        RegistryError::Mission(MissionError::Scenario(m)) => {
            Failure::Input(anyhow::anyhow!("invalid scenario {}: {m}", path.display()))
        }
        RegistryError::Mission(MissionError::Setup(m)) => {
            Failure::Runtime(anyhow::anyhow!("cannot set up {}: {m}", path.display()))
        }
        RegistryError::Read { source, .. } => Failure::Input(anyhow::anyhow!(
            "cannot read scenario {}: {source}",
            path.display()
        )),
        e @ RegistryError::Kind(_) => Failure::Input(e.into()),
    }
}
