//! Cops and robber with full visibility, solved exactly.
//!
//! The cop number of a graph is the least `k` such that `k` cops, placed first and moving
//! first, surely catch a robber who sees everything (see [`CopsGame`] for the rules).
//! [`cop_number`] computes it per connected component (the robber picks his component after
//! seeing the cops, so the cop number of a graph is the sum over its components): for
//! `k = 1, 2, ...` it first looks for a dominating set of size `k` (cops standing on one catch
//! the robber on their first move, so `k` cops win), and otherwise decides the `k`-cop game by
//! retrograde analysis ([`CopsGame::solve`]). The first `k` that wins is the answer; the
//! search stops at the domination number at the latest.
//!
//! ```
//! use vitro_algo::cops::{cop_number, CopOptions};
//! use vitro_algo::graph;
//!
//! assert_eq!(cop_number(&graph::petersen(), &CopOptions::default())?.cop_number, 3);
//! assert_eq!(cop_number(&graph::grid(3, 4)?, &CopOptions::default())?.cop_number, 2);
//! # Ok::<(), vitro_algo::cops::CopsError>(())
//! ```

mod domination;
mod game;
mod multiset;
mod options;

pub use game::{CopsGame, Outcome, Turn};
pub use options::{CopOptions, CopsError};

use crate::graph::{Graph, NodeId};

/// How the winning `k` of a component was established.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Decision {
    /// A dominating set of `k` vertices exists (so `k` cops win at once).
    DominatingSet,
    /// Retrograde analysis of the `k`-cop game.
    Retrograde,
}

/// The cop number of one connected component.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ComponentCopNumber {
    /// The component's vertices (ids in the whole graph), ascending.
    pub nodes: Vec<NodeId>,
    /// Its cop number.
    pub cop_number: usize,
    /// How the winning `k` was established (every smaller `k` was refuted by retrograde
    /// analysis).
    pub decided_by: Decision,
    /// Cop moves until capture with `cop_number` cops under optimal play on both sides.
    pub capture_time: u32,
    /// Positions in the game tables solved for this component.
    pub states_explored: u64,
}

/// The result of [`cop_number`].
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct CopResult {
    /// The cop number of the whole graph (the sum over components; 0 for the empty graph).
    pub cop_number: usize,
    /// Positions in all game tables solved (a measure of the work done).
    pub states_explored: u64,
    /// Per connected component, ordered by smallest vertex.
    pub components: Vec<ComponentCopNumber>,
}

/// Computes the cop number of `graph` exactly (see the [module docs](self)).
///
/// # Errors
/// [`CopsError::TooManyStates`] if some game needed is larger than `options.max_states`.
pub fn cop_number(graph: &Graph, options: &CopOptions) -> Result<CopResult, CopsError> {
    let mut result = CopResult {
        cop_number: 0,
        states_explored: 0,
        components: Vec::new(),
    };
    for nodes in graph.components() {
        let sub = graph.induced_subgraph(&nodes)?;
        let component = component_cop_number(&sub, nodes, options)?;
        result.cop_number += component.cop_number;
        result.states_explored += component.states_explored;
        result.components.push(component);
    }
    Ok(result)
}

/// The cop number of a connected, non-empty graph.
fn component_cop_number(
    graph: &Graph,
    nodes: Vec<NodeId>,
    options: &CopOptions,
) -> Result<ComponentCopNumber, CopsError> {
    let n = graph.node_count();
    let mut states_explored = 0u64;
    // A dominating set of all n vertices always exists, so the loop ends by k = n.
    for k in 1..=n {
        if options.use_domination
            && domination::dominating_set(graph, k, options.max_states).is_some()
        {
            return Ok(ComponentCopNumber {
                nodes,
                cop_number: k,
                decided_by: Decision::DominatingSet,
                // Cops on every vertex catch at once; otherwise the robber finds a free vertex
                // and is caught on the cops' first move.
                capture_time: u32::from(k < n),
                states_explored,
            });
        }
        let game = CopsGame::solve(graph, k, options)?;
        states_explored += game.state_count() as u64;
        if let Some(capture_time) = game.capture_time() {
            return Ok(ComponentCopNumber {
                nodes,
                cop_number: k,
                decided_by: Decision::Retrograde,
                capture_time,
                states_explored,
            });
        }
    }
    // Only reachable for the empty graph, which has no component.
    Err(CopsError::EmptyGraph)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;

    #[test]
    fn small_cases() {
        let opts = CopOptions::default();
        assert_eq!(cop_number(&Graph::default(), &opts).unwrap().cop_number, 0);
        let isolated = Graph::from_edges(3, &[]).unwrap();
        assert_eq!(cop_number(&isolated, &opts).unwrap().cop_number, 3);
        assert_eq!(
            cop_number(&graph::cycle(3).unwrap(), &opts)
                .unwrap()
                .cop_number,
            1
        );
        assert_eq!(
            cop_number(&graph::cycle(4).unwrap(), &opts)
                .unwrap()
                .cop_number,
            2
        );
    }

    #[test]
    fn limit_is_reported() {
        let opts = CopOptions {
            max_states: 50,
            use_domination: false,
        };
        assert!(matches!(
            cop_number(&graph::cycle(6).unwrap(), &opts),
            Err(CopsError::TooManyStates { .. })
        ));
    }
}
