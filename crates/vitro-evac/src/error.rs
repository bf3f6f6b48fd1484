//! Why a mission could not be built.

use vitro_tactical::scenario::Diagnostics;

/// Why a mission could not be built.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// The scenario file has problems.
    #[error("{0}")]
    Scenario(#[from] Diagnostics),
    /// The scenario is valid but the mission cannot be set up on its site.
    #[error("cannot set up the mission: {0}")]
    Setup(String),
}
