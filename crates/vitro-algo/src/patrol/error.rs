//! Why a patrolling game could not be read or solved.

use crate::graph::NodeId;
use std::path::PathBuf;

/// Errors from loading, solving or evaluating a patrolling game.
#[derive(Debug, thiserror::Error)]
pub enum PatrolError {
    /// The instance text is malformed at this 1-based line and column.
    #[error("line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The instance is inconsistent (built in code rather than parsed).
    #[error("invalid instance: {0}")]
    InvalidInstance(String),
    /// A policy does not fit the instance.
    #[error("invalid policy: {0}")]
    InvalidPolicy(String),
    /// The instance uses a feature the solver does not handle yet.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The LP solver failed.
    #[error("LP solver: {0}")]
    Lp(String),
    /// A plan was asked about a unit it does not have.
    #[error("unit {unit} is not in the plan ({units} units)")]
    NoSuchUnit {
        /// The unit asked about.
        unit: usize,
        /// The plan's units.
        units: usize,
    },
    /// A vertex outside the graph.
    #[error("vertex {0} is not in the graph")]
    NoSuchVertex(NodeId),
}
