//! Omniscient evaders: the exact cops-and-robber strategy (with hiding) and a greedy one.

use super::{Arena, EvaderInfo, GameEvader};
use crate::cops::{CopOptions, CopsError, CopsGame, Outcome, Turn};
use crate::graph::NodeId;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Picks the candidate with the largest key, ties uniformly at random (reservoir sampling
/// over the candidates in ascending order, so the draw depends only on the RNG).
fn best_by<K: Ord>(
    candidates: impl Iterator<Item = NodeId>,
    rng: &mut ChaCha8Rng,
    mut key: impl FnMut(NodeId) -> K,
) -> Option<NodeId> {
    let mut best: Option<(K, NodeId)> = None;
    let mut ties = 0u32;
    for v in candidates {
        let k = key(v);
        match &best {
            Some((b, _)) if k < *b => {}
            Some((b, _)) if k == *b => {
                ties += 1;
                if rng.random_range(0..ties) == 0 {
                    best = Some((k, v));
                }
            }
            _ => {
                best = Some((k, v));
                ties = 1;
            }
        }
    }
    best.map(|(_, v)| v)
}

/// Hop distance from `v` to the nearest of `pursuers`.
fn nearest(arena: &Arena, pursuers: &[NodeId], v: NodeId) -> u16 {
    pursuers
        .iter()
        .map(|&p| arena.dist(p, v))
        .min()
        .unwrap_or(u16::MAX)
}

fn unseen(arena: &Arena, pursuers: &[NodeId], v: NodeId) -> bool {
    !pursuers.iter().any(|&p| arena.sees(p, v))
}

/// The exact robber of [`crate::cops`], hiding when it can: it knows everything, and it
/// moves (or places itself) to the vertex that is best by, in order,
/// 1. escaping forever in the full-visibility game (the solved table of [`CopsGame`]),
/// 2. being out of the pursuers' sight after the move,
/// 3. the longest capture time under optimal full-visibility play,
/// 4. the distance to the nearest pursuer,
///
/// ties at random. With full visibility (2 never separates) this is an optimal robber: it
/// escapes forever against fewer pursuers than the cop number and delays capture as long as
/// possible otherwise.
#[derive(Clone, Debug)]
pub struct ExactEvader {
    game: CopsGame,
}

impl ExactEvader {
    /// Solves the `pursuers`-cop game on `arena`'s graph.
    ///
    /// # Errors
    /// [`CopsError::TooManyStates`] if the table would exceed the default limit
    /// ([`CopOptions::max_states`]).
    pub fn new(arena: &Arena, pursuers: usize) -> Result<ExactEvader, CopsError> {
        Ok(ExactEvader {
            game: CopsGame::solve(arena.graph(), pursuers, &CopOptions::default())?,
        })
    }

    /// True if the pursuers (as many as the table was solved for) win the full-visibility game
    /// from their best placement.
    pub fn cops_win(&self) -> bool {
        self.game.cops_win()
    }

    /// Larger is better for the evader standing at `v`, the cops to move.
    fn key(&self, arena: &Arena, pursuers: &[NodeId], v: NodeId) -> (bool, bool, u32, u16) {
        let (escapes, plies) = match self.game.outcome(pursuers, v, Turn::Cops) {
            Ok(Outcome::RobberEscapes) => (true, u32::MAX),
            Ok(Outcome::CopsWin { plies }) => (false, plies),
            Err(_) => (false, 0),
        };
        (
            escapes,
            unseen(arena, pursuers, v),
            plies,
            nearest(arena, pursuers, v),
        )
    }
}

impl GameEvader for ExactEvader {
    fn name(&self) -> String {
        "exact (omniscient; solved cops-and-robber table, then hiding)".into()
    }

    fn place(&mut self, arena: &Arena, pursuers: &[NodeId], rng: &mut ChaCha8Rng) -> NodeId {
        best_by(0..arena.node_count(), rng, |v| self.key(arena, pursuers, v)).unwrap_or(0)
    }

    fn choose(&mut self, info: &EvaderInfo<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        let arena = info.arena;
        best_by(arena.moves(info.position).iter().copied(), rng, |v| {
            self.key(arena, info.pursuers, v)
        })
        .unwrap_or(info.position)
    }
}

/// An omniscient greedy evader for boards too large for [`ExactEvader`]'s table: it prefers
/// vertices out of sight, then far from the nearest pursuer, then far from all of them.
#[derive(Clone, Copy, Debug, Default)]
pub struct FleeingHider;

impl FleeingHider {
    fn key(arena: &Arena, pursuers: &[NodeId], v: NodeId) -> (bool, bool, u16, u32) {
        let total = pursuers.iter().map(|&p| u32::from(arena.dist(p, v))).sum();
        (
            !pursuers.contains(&v),
            unseen(arena, pursuers, v),
            nearest(arena, pursuers, v),
            total,
        )
    }
}

impl GameEvader for FleeingHider {
    fn name(&self) -> String {
        "fleeing hider (omniscient greedy: out of sight, then far)".into()
    }

    fn place(&mut self, arena: &Arena, pursuers: &[NodeId], rng: &mut ChaCha8Rng) -> NodeId {
        best_by(0..arena.node_count(), rng, |v| {
            Self::key(arena, pursuers, v)
        })
        .unwrap_or(0)
    }

    fn choose(&mut self, info: &EvaderInfo<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        best_by(info.arena.moves(info.position).iter().copied(), rng, |v| {
            Self::key(info.arena, info.pursuers, v)
        })
        .unwrap_or(info.position)
    }
}
