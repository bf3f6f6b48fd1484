//! Reading a graph file (`u v` edge lists) for the `vitro solve` commands.

use crate::Failure;
use anyhow::anyhow;
use std::path::Path;
use vitro_algo::graph::{Graph, GraphError};

/// Loads an edge list; errors name the file, line and column.
pub(crate) fn load_graph(path: &Path) -> Result<Graph, Failure> {
    vitro_tools::input_file(path)?;
    Graph::load(path).map_err(|e| match e {
        GraphError::Parse {
            line,
            column,
            message,
        } => Failure::Input(anyhow!("{}:{line}:{column}: {message}", path.display())),
        e @ GraphError::Io { .. } => Failure::Input(e.into()),
        other => Failure::Input(anyhow!("{}: {other}", path.display())),
    })
}
