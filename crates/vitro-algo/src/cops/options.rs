//! What a cop-number computation is asked for, and why it can fail.

use crate::graph::GraphError;

/// Errors from the cops-and-robber solver.
#[derive(Debug, thiserror::Error)]
pub enum CopsError {
    /// Solving would need a larger table than allowed.
    #[error("{cops} cops need {states} positions, more than the limit of {limit}")]
    TooManyStates {
        /// The number of cops being tried.
        cops: usize,
        /// Positions needed (saturated).
        states: u64,
        /// The configured limit ([`CopOptions::max_states`]).
        limit: u64,
    },
    /// A position given to a strategy query is not a position of the game.
    #[error("invalid position: {0}")]
    InvalidPosition(String),
    /// A move was asked for in a position where the robber is already caught.
    #[error("the robber is already caught")]
    AlreadyCaptured,
    /// The graph has no vertex to stand on.
    #[error("the graph is empty")]
    EmptyGraph,
    /// Extracting a component failed.
    #[error(transparent)]
    Graph(#[from] GraphError),
}

/// Limits and switches for [`cop_number`](crate::cops::cop_number) and [`CopsGame::solve`](crate::cops::CopsGame::solve).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CopOptions {
    /// The most positions (cop multiset × robber vertex × turn) one game table may hold; about
    /// 12 bytes each. Default: 2^25 (about 400 MB).
    pub max_states: u64,
    /// Stop at `k` as soon as a dominating set of size `k` exists, without solving that game.
    /// Default: true. Turn off to decide every `k` by retrograde analysis.
    pub use_domination: bool,
}

impl Default for CopOptions {
    fn default() -> Self {
        CopOptions {
            max_states: 1 << 25,
            use_domination: true,
        }
    }
}
