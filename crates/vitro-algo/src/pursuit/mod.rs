//! Visibility-based pursuit–evasion with imperfect information, and two anytime algorithms
//! over information sets: information-set Monte-Carlo tree search ([`Mcts`]) and
//! iterative-deepening alpha-beta minimax ([`Minimax`]).
//!
//! # Rules
//! `k` pursuers and one evader stand on vertices of a graph. Every turn **all players move
//! simultaneously**, each along an edge or staying. The evader is caught when, after the move,
//! a pursuer stands on its vertex or a pursuer and the evader swapped ends of one edge
//! (crossed). A generic [`Visibility`] says whether a vertex sees another; the pursuer team
//! sees the evader when some pursuer sees its vertex (shared information), the evader sees a
//! pursuer when it sees that pursuer's vertex. Nobody knows anything at the start: both sides
//! start from a uniform belief over all vertices and then observe.
//!
//! # Information sets
//! Each side keeps a [`Belief`] per opponent piece: the set of vertices it may occupy plus a
//! probability distribution over that set for sampling. Every turn the belief is spread one
//! step along the edges (random-walk model: each vertex's mass is shared equally by its closed
//! neighbourhood), then the observation is applied: a sighting collapses it to one vertex;
//! otherwise every vertex the observers see is removed. The true position is therefore always
//! in the set. The evader keeps one belief per pursuer (a product of marginals).
//!
//! # Players
//! [`PursuerStrategy`] and [`EvaderStrategy`] are implemented by the baselines
//! ([`RandomPursuers`], [`GreedyPursuers`], [`RandomEvader`], [`FleeingEvader`]) and by both
//! searches, for either side. [`play`] runs one episode.
//!
//! ```
//! use rand::SeedableRng;
//! use rand_chacha::ChaCha8Rng;
//! use vitro_algo::graph;
//! use vitro_algo::pursuit::{play, Arena, FullVisibility, GreedyPursuers, FleeingEvader};
//!
//! let arena = Arena::new(graph::path(8)?, &FullVisibility)?;
//! let mut rng = ChaCha8Rng::seed_from_u64(1);
//! let result = play(&arena, &[0], 7, &mut GreedyPursuers, &mut FleeingEvader, 50, &mut rng)?;
//! assert!(result.captured_at.is_some());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod baseline;
mod belief;
mod episode;
pub mod game;
mod mcts;
mod minimax;
mod sim;
#[cfg(test)]
mod tests;

pub use baseline::{FleeingEvader, GreedyPursuers, RandomEvader, RandomPursuers};
pub use belief::{Belief, Sampler};
pub use episode::{EpisodeResult, EvaderStrategy, EvaderView, PursuerStrategy, PursuerView, play};
pub use mcts::{Mcts, MctsConfig};
pub use minimax::{Minimax, MinimaxConfig};

use crate::graph::{Graph, NodeId};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// The most vertices an [`Arena`] may have (it stores all-pairs distances and visibility).
pub const MAX_ARENA_NODES: usize = 4096;

/// Errors from building an arena or playing an episode.
#[derive(Debug, thiserror::Error)]
pub enum PursuitError {
    /// The graph has no vertex.
    #[error("the graph is empty")]
    EmptyGraph,
    /// The graph is larger than [`MAX_ARENA_NODES`].
    #[error("graph too large for an arena: {0} vertices, at most {MAX_ARENA_NODES}")]
    TooLarge(usize),
    /// A start position names a vertex outside the graph.
    #[error("vertex {vertex} is outside 0..{node_count}")]
    BadVertex {
        /// The vertex.
        vertex: NodeId,
        /// The graph's vertex count.
        node_count: usize,
    },
    /// No pursuers were given.
    #[error("at least one pursuer is needed")]
    NoPursuers,
    /// A strategy returned an illegal move (not to the closed neighbourhood, or the wrong
    /// number of pursuer moves).
    #[error("illegal move by {who}: {detail}")]
    IllegalMove {
        /// `"pursuers"` or `"evader"`.
        who: &'static str,
        /// What was wrong.
        detail: String,
    },
}

/// Whether a vertex sees another (need not be symmetric). Every vertex is treated as seeing
/// itself, whatever the implementation says.
pub trait Visibility {
    /// True if an observer at `from` sees a piece at `to`.
    fn sees(&self, from: NodeId, to: NodeId) -> bool;
}

/// Everybody sees everything (the classical cops-and-robber information).
#[derive(Clone, Copy, Debug, Default)]
pub struct FullVisibility;

impl Visibility for FullVisibility {
    fn sees(&self, _from: NodeId, _to: NodeId) -> bool {
        true
    }
}

/// Visibility given as an undirected graph on the same vertices: `u` sees `v` iff `u == v` or
/// `{u, v}` is an edge of it (e.g. line-of-sight pairs precomputed over terrain).
#[derive(Clone, Debug)]
pub struct VisibilityGraph(pub Graph);

impl Visibility for VisibilityGraph {
    fn sees(&self, from: NodeId, to: NodeId) -> bool {
        from == to || (from < self.0.node_count() && self.0.has_edge(from, to))
    }
}

/// A vertex sees everything within `range` edges of it (hop distance in `graph`).
#[derive(Clone, Debug)]
pub struct HopRange {
    within: Vec<Vec<NodeId>>,
}

impl HopRange {
    /// Vertices within `range` hops of each vertex of `graph`.
    pub fn new(graph: &Graph, range: usize) -> HopRange {
        let within = (0..graph.node_count())
            .map(|v| {
                let mut list: Vec<NodeId> = graph
                    .distances_from(v)
                    .iter()
                    .enumerate()
                    .filter(|(_, d)| d.is_some_and(|d| d <= range))
                    .map(|(u, _)| u)
                    .collect();
                list.sort_unstable();
                list
            })
            .collect();
        HopRange { within }
    }
}

impl Visibility for HopRange {
    fn sees(&self, from: NodeId, to: NodeId) -> bool {
        self.within
            .get(from)
            .is_some_and(|l| l.binary_search(&to).is_ok())
    }
}

/// [`Arena::toward`]'s table: for every (from, target), the bit set of the moves at `from`
/// (closed neighbourhood, ascending) with the least hop distance to `target`.
fn shortest_moves(closed: &[Vec<NodeId>], dist: &[u16]) -> Vec<u16> {
    let n = closed.len();
    let mut out = vec![0u16; n * n];
    for (from, moves) in closed.iter().enumerate() {
        if moves.len() > 16 {
            continue;
        }
        for target in 0..n {
            // Distances are symmetric (undirected graph): read the target's row.
            let row = &dist[target * n..(target + 1) * n];
            let best = moves.iter().map(|&v| row[v]).min().unwrap_or(FAR);
            let mut bits = 0u16;
            for (i, &v) in moves.iter().enumerate() {
                if row[v] == best {
                    bits |= 1 << i;
                }
            }
            out[from * n + target] = bits;
        }
    }
    out
}

/// Distance used for vertices in different components.
pub const FAR: u16 = u16::MAX;

/// A graph prepared for play: closed neighbourhoods, all-pairs hop distances and the
/// visibility relation, precomputed.
#[derive(Clone, Debug)]
pub struct Arena {
    graph: Graph,
    closed: Vec<Vec<NodeId>>,
    visible_from: Vec<Vec<NodeId>>,
    dist: Vec<u16>,
    /// Per (from, target), a bit per move at `from` (index into [`Arena::moves`]) that is
    /// on a shortest path to `target`; 0 where `from` has more than 16 moves.
    toward: Vec<u16>,
    diameter: u16,
}

impl Arena {
    /// Prepares `graph` with the visibility `vis`.
    ///
    /// # Errors
    /// [`PursuitError::EmptyGraph`] or [`PursuitError::TooLarge`].
    pub fn new(graph: Graph, vis: &dyn Visibility) -> Result<Arena, PursuitError> {
        let n = graph.node_count();
        if n == 0 {
            return Err(PursuitError::EmptyGraph);
        }
        if n > MAX_ARENA_NODES {
            return Err(PursuitError::TooLarge(n));
        }
        let closed: Vec<Vec<NodeId>> = (0..n)
            .map(|v| {
                let mut c = graph.neighbors(v).to_vec();
                c.push(v);
                c.sort_unstable();
                c
            })
            .collect();
        let visible_from = (0..n)
            .map(|u| (0..n).filter(|&v| u == v || vis.sees(u, v)).collect())
            .collect();
        let mut dist = vec![FAR; n * n];
        let mut queue = VecDeque::new();
        for s in 0..n {
            let row = &mut dist[s * n..(s + 1) * n];
            row[s] = 0;
            queue.push_back(s);
            while let Some(u) = queue.pop_front() {
                for &v in graph.neighbors(u) {
                    if row[v] == FAR {
                        row[v] = row[u] + 1;
                        queue.push_back(v);
                    }
                }
            }
        }
        let diameter = dist
            .iter()
            .copied()
            .filter(|&d| d != FAR)
            .max()
            .unwrap_or(0);
        let toward = shortest_moves(&closed, &dist);
        Ok(Arena {
            graph,
            closed,
            visible_from,
            dist,
            toward,
            diameter,
        })
    }

    /// The graph.
    pub fn graph(&self) -> &Graph {
        &self.graph
    }

    /// Number of vertices.
    pub fn node_count(&self) -> usize {
        self.closed.len()
    }

    /// `v` and its neighbours, ascending: the moves available at `v`.
    pub fn moves(&self, v: NodeId) -> &[NodeId] {
        &self.closed[v]
    }

    /// The vertices seen from `v` (including `v`), ascending.
    pub fn visible_from(&self, v: NodeId) -> &[NodeId] {
        &self.visible_from[v]
    }

    /// True if an observer at `from` sees `to`.
    pub fn sees(&self, from: NodeId, to: NodeId) -> bool {
        self.visible_from[from].binary_search(&to).is_ok()
    }

    /// Hop distance between `u` and `v`; [`FAR`] if disconnected.
    pub fn dist(&self, u: NodeId, v: NodeId) -> u16 {
        self.dist[u * self.closed.len() + v]
    }

    /// The moves at `from` on a shortest path to `target`, as bits over
    /// [`Arena::moves`]`(from)`; 0 if `from` has more than 16 moves (not tabulated).
    pub fn toward(&self, from: NodeId, target: NodeId) -> u16 {
        self.toward[from * self.closed.len() + target]
    }

    /// The largest finite hop distance.
    pub fn diameter(&self) -> u16 {
        self.diameter
    }

    fn check(&self, v: NodeId) -> Result<(), PursuitError> {
        if v < self.node_count() {
            Ok(())
        } else {
            Err(PursuitError::BadVertex {
                vertex: v,
                node_count: self.node_count(),
            })
        }
    }
}

/// How much a search may do before answering: iterations (MCTS simulations, or minimax node
/// expansions) and optionally wall time. Only the iteration budget is reproducible.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Budget {
    /// Most iterations (at least one is always done).
    pub iterations: u64,
    /// Optional wall-clock limit, checked between iterations.
    pub time: Option<Duration>,
}

impl Budget {
    /// A pure iteration budget.
    pub fn iterations(iterations: u64) -> Budget {
        Budget {
            iterations,
            time: None,
        }
    }

    fn deadline(&self) -> Option<Instant> {
        self.time.map(|t| Instant::now() + t)
    }
}
