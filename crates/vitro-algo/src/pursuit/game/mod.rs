//! Pursuit as a game: the classical cops-and-robber turn order with the pursuers' partial
//! view, and searches in which the evader's decisions are part of the game tree.
//!
//! # Rules
//! `k` pursuers stand on given vertices; the evader, seeing them, places itself. Then every
//! round the pursuers move (all at once, each along an edge or staying) and the evader, seeing
//! their new positions, moves. The evader is caught when a pursuer stands on its vertex (after
//! either move). With [`FullVisibility`](super::FullVisibility) this is exactly the game whose
//! value [`crate::cops`] computes, so `k >= ` cop number pursuers can force capture and fewer
//! cannot: the searches are checked against that theory.
//!
//! # Information
//! The evader is **omniscient** (it sees the pursuers and knows what they know): the worst
//! case for the pursuers, as in the cops-and-robber literature. The pursuers see the evader
//! only when a pursuer's vertex sees its vertex ([`Arena::sees`], e.g. within `h` hops,
//! [`HopRange`](super::HopRange)). Their information set is the [`Belief`] of the vertices the
//! evader may occupy, kept by [`play_game`]: spread one step after each evader move, minus the
//! pursuers' own vertices (no capture happened), then collapsed on a sighting or cleared of
//! every vertex the pursuers see. The truth is always in it.
//!
//! # Objectives
//! Capture (the sooner the better) and keeping the evader in sight: [`GameOutcome`] reports
//! both, and the searches' rewards combine them (see [`MoIsmcts`] and [`WorstCaseMinimax`]).
//!
//! # Players
//! Pursuers: [`MoIsmcts`] (multiple-observer information-set MCTS, one tree per player, the
//! evader's moves chosen by its own statistics inside the search) and [`WorstCaseMinimax`]
//! (alpha-beta over the pursuers' information states against an adversarial evader, no
//! determinization). Evaders: [`ExactEvader`] (the solved cops-and-robber table plus hiding),
//! [`MoIsmcts`] (the same search on the evader's side), and the omniscient
//! [`FleeingHider`].
//!
//! ```
//! use rand::SeedableRng;
//! use rand_chacha::ChaCha8Rng;
//! use vitro_algo::graph;
//! use vitro_algo::pursuit::{Arena, FullVisibility};
//! use vitro_algo::pursuit::game::{play_game, ExactEvader, MoIsmcts, MoIsmctsConfig};
//!
//! // A tree has cop number 1: one pursuer catches even an exact evader.
//! let arena = Arena::new(graph::tree(2, 3)?, &FullVisibility)?;
//! let mut evader = ExactEvader::new(&arena, 1)?;
//! let mut pursuers = MoIsmcts::new(MoIsmctsConfig::default());
//! let mut rng = ChaCha8Rng::seed_from_u64(1);
//! let out = play_game(&arena, &[0], &mut pursuers, &mut evader, 40, &mut rng)?;
//! assert!(out.captured_at.is_some());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod eval;
mod exact;
mod ismcts;
#[cfg(test)]
mod tests;
mod worst;

pub use eval::{EvalSummary, evaluate, wilson_interval};
pub use exact::{ExactEvader, FleeingHider};
pub use ismcts::{MoIsmcts, MoIsmctsConfig};
pub use worst::{WorstCaseMinimax, WorstCaseMinimaxConfig};

use super::{Arena, Belief, PursuitError};
use crate::graph::NodeId;
use rand_chacha::ChaCha8Rng;

/// What the pursuer team knows when it moves.
#[derive(Clone, Copy, Debug)]
pub struct TeamView<'a> {
    /// The board.
    pub arena: &'a Arena,
    /// The pursuers' positions.
    pub positions: &'a [NodeId],
    /// Where the evader may be (a single vertex while it is in sight).
    pub belief: &'a Belief,
    /// Rounds left in the episode, this one included.
    pub rounds_left: u32,
}

/// What the (omniscient) evader knows when it moves: everything.
#[derive(Clone, Copy, Debug)]
pub struct EvaderInfo<'a> {
    /// The board.
    pub arena: &'a Arena,
    /// The pursuers' positions after their move of this round.
    pub pursuers: &'a [NodeId],
    /// The evader's position.
    pub position: NodeId,
    /// The pursuers' information set about the evader (before this move).
    pub pursuer_belief: &'a Belief,
    /// Rounds left in the episode, this one included.
    pub rounds_left: u32,
}

/// A policy of the pursuer team in the turn-based game.
pub trait TeamStrategy {
    /// A short name for reports.
    fn name(&self) -> String;
    /// The next vertex of every pursuer (each in the closed neighbourhood of its position).
    fn choose(&mut self, view: &TeamView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId>;
}

/// A policy of the evader in the turn-based game.
pub trait GameEvader {
    /// A short name for reports.
    fn name(&self) -> String;
    /// The start vertex, chosen after seeing the pursuers.
    fn place(&mut self, arena: &Arena, pursuers: &[NodeId], rng: &mut ChaCha8Rng) -> NodeId;
    /// The next vertex (in the closed neighbourhood of its position).
    fn choose(&mut self, info: &EvaderInfo<'_>, rng: &mut ChaCha8Rng) -> NodeId;
}

/// The outcome of [`play_game`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GameOutcome {
    /// The round of capture (0: the evader placed itself on a pursuer); `None` if it
    /// survived every round.
    pub captured_at: Option<u32>,
    /// Rounds played.
    pub rounds: u32,
    /// Rounds after which the pursuers saw the evader (their objective besides capture).
    pub rounds_in_sight: u32,
    /// The evader's start.
    pub evader_start: NodeId,
    /// True if the pursuers' information set held the evader's position after every round.
    pub truth_in_belief: bool,
}

fn illegal(who: &'static str, from: NodeId, to: NodeId) -> PursuitError {
    PursuitError::IllegalMove {
        who,
        detail: format!("{from} -> {to}"),
    }
}

/// Applies the pursuers' observation of the evader at `evader` to `belief`; true if seen.
pub(crate) fn observe(
    arena: &Arena,
    pursuers: &[NodeId],
    evader: NodeId,
    belief: &mut Belief,
) -> bool {
    if pursuers.iter().any(|&p| arena.sees(p, evader)) {
        belief.collapse(evader);
        true
    } else {
        belief.exclude_seen_by(arena, pursuers);
        false
    }
}

/// Plays one episode of at most `rounds` rounds (see the [module docs](self)).
///
/// # Errors
/// [`PursuitError::NoPursuers`], [`PursuitError::BadVertex`] for a start off the graph,
/// [`PursuitError::IllegalMove`] if a strategy breaks the rules.
pub fn play_game(
    arena: &Arena,
    pursuers: &[NodeId],
    team: &mut dyn TeamStrategy,
    evader: &mut dyn GameEvader,
    rounds: u32,
    rng: &mut ChaCha8Rng,
) -> Result<GameOutcome, PursuitError> {
    if pursuers.is_empty() {
        return Err(PursuitError::NoPursuers);
    }
    for &v in pursuers {
        arena.check(v)?;
    }
    let n = arena.node_count();
    let mut pos = pursuers.to_vec();
    let mut ev = evader.place(arena, &pos, rng);
    arena.check(ev)?;
    let mut out = GameOutcome {
        captured_at: None,
        rounds: 0,
        rounds_in_sight: 0,
        evader_start: ev,
        truth_in_belief: true,
    };
    if pos.contains(&ev) {
        out.captured_at = Some(0);
        return Ok(out);
    }
    let mut belief = Belief::uniform(n);
    belief.remove(&pos);
    observe(arena, &pos, ev, &mut belief);
    for round in 1..=rounds {
        let rounds_left = rounds - round + 1;
        let next = team.choose(
            &TeamView {
                arena,
                positions: &pos,
                belief: &belief,
                rounds_left,
            },
            rng,
        );
        if next.len() != pos.len() {
            return Err(PursuitError::IllegalMove {
                who: "pursuers",
                detail: format!("{} moves for {} pursuers", next.len(), pos.len()),
            });
        }
        for (&from, &to) in pos.iter().zip(&next) {
            if to >= n || arena.moves(from).binary_search(&to).is_err() {
                return Err(illegal("pursuers", from, to));
            }
        }
        pos = next;
        out.rounds = round;
        if pos.contains(&ev) {
            out.captured_at = Some(round);
            return Ok(out);
        }
        belief.remove(&pos);
        let to = evader.choose(
            &EvaderInfo {
                arena,
                pursuers: &pos,
                position: ev,
                pursuer_belief: &belief,
                rounds_left,
            },
            rng,
        );
        if to >= n || arena.moves(ev).binary_search(&to).is_err() {
            return Err(illegal("evader", ev, to));
        }
        ev = to;
        if pos.contains(&ev) {
            out.captured_at = Some(round);
            return Ok(out);
        }
        belief.predict(arena);
        belief.remove(&pos);
        if observe(arena, &pos, ev, &mut belief) {
            out.rounds_in_sight += 1;
        }
        out.truth_in_belief &= belief.contains(ev);
    }
    Ok(out)
}
