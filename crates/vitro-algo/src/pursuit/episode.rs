//! Players' interfaces and the episode loop (simultaneous moves, beliefs kept by the referee).

use super::{Arena, Belief, PursuitError};
use crate::graph::NodeId;
use rand_chacha::ChaCha8Rng;

/// What the pursuer team knows when choosing a move.
#[derive(Clone, Copy, Debug)]
pub struct PursuerView<'a> {
    /// The board.
    pub arena: &'a Arena,
    /// The pursuers' own positions.
    pub positions: &'a [NodeId],
    /// Where the evader may be.
    pub belief: &'a Belief,
    /// Turns played so far.
    pub turn: u32,
}

/// What the evader knows when choosing a move.
#[derive(Clone, Copy, Debug)]
pub struct EvaderView<'a> {
    /// The board.
    pub arena: &'a Arena,
    /// The evader's own position.
    pub position: NodeId,
    /// Where each pursuer may be (one belief per pursuer, in pursuer order).
    pub beliefs: &'a [Belief],
    /// Turns played so far.
    pub turn: u32,
}

/// A policy for the pursuer team.
pub trait PursuerStrategy {
    /// The next vertex of every pursuer (each in the closed neighbourhood of its position).
    fn choose(&mut self, view: &PursuerView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId>;
}

/// A policy for the evader.
pub trait EvaderStrategy {
    /// The evader's next vertex (in the closed neighbourhood of its position).
    fn choose(&mut self, view: &EvaderView<'_>, rng: &mut ChaCha8Rng) -> NodeId;
}

/// One turn of an episode, after the moves and observations.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Pursuer positions.
    pub pursuers: Vec<NodeId>,
    /// Evader position.
    pub evader: NodeId,
    /// Size of the pursuers' information set about the evader.
    pub pursuer_belief_size: usize,
    /// True if every belief (the pursuers' and each of the evader's) holds the true position.
    pub truth_in_beliefs: bool,
}

/// The outcome of [`play`].
#[derive(Clone, Debug, PartialEq)]
pub struct EpisodeResult {
    /// The turn of capture (0: the evader started on a pursuer); `None` if it survived.
    pub captured_at: Option<u32>,
    /// Every turn played, the start included (index 0).
    pub steps: Vec<Step>,
}

/// True if the move from `before` to `after` catches the evader: a pursuer on its vertex, or
/// a pursuer and the evader swapping the ends of an edge.
pub(crate) fn caught(
    before: &[NodeId],
    after: &[NodeId],
    evader_before: NodeId,
    evader_after: NodeId,
) -> bool {
    after.contains(&evader_after)
        || before
            .iter()
            .zip(after)
            .any(|(&b, &a)| b == evader_after && a == evader_before)
}

/// Plays one episode of at most `horizon` turns from the given start (see the
/// [module docs](super) for the rules).
///
/// # Errors
/// [`PursuitError::NoPursuers`], [`PursuitError::BadVertex`] for a start off the graph,
/// [`PursuitError::IllegalMove`] if a strategy breaks the rules.
pub fn play(
    arena: &Arena,
    pursuers: &[NodeId],
    evader: NodeId,
    pursuer_strategy: &mut dyn PursuerStrategy,
    evader_strategy: &mut dyn EvaderStrategy,
    horizon: u32,
    rng: &mut ChaCha8Rng,
) -> Result<EpisodeResult, PursuitError> {
    if pursuers.is_empty() {
        return Err(PursuitError::NoPursuers);
    }
    for &v in pursuers.iter().chain([&evader]) {
        arena.check(v)?;
    }
    let n = arena.node_count();
    let mut pos = pursuers.to_vec();
    let mut ev = evader;
    let mut p_belief = Belief::uniform(n);
    let mut e_beliefs = vec![Belief::uniform(n); pos.len()];
    observe(arena, &pos, ev, &mut p_belief, &mut e_beliefs);
    let mut steps = vec![snapshot(&pos, ev, &p_belief, &e_beliefs)];
    if pos.contains(&ev) {
        return Ok(EpisodeResult {
            captured_at: Some(0),
            steps,
        });
    }
    for turn in 0..horizon {
        let p_view = PursuerView {
            arena,
            positions: &pos,
            belief: &p_belief,
            turn,
        };
        let next = pursuer_strategy.choose(&p_view, rng);
        let e_view = EvaderView {
            arena,
            position: ev,
            beliefs: &e_beliefs,
            turn,
        };
        let e_next = evader_strategy.choose(&e_view, rng);
        if next.len() != pos.len() {
            return Err(PursuitError::IllegalMove {
                who: "pursuers",
                detail: format!("{} moves for {} pursuers", next.len(), pos.len()),
            });
        }
        for (&from, &to) in pos.iter().zip(&next) {
            if to >= n || arena.moves(from).binary_search(&to).is_err() {
                return Err(PursuitError::IllegalMove {
                    who: "pursuers",
                    detail: format!("{from} -> {to}"),
                });
            }
        }
        if e_next >= n || arena.moves(ev).binary_search(&e_next).is_err() {
            return Err(PursuitError::IllegalMove {
                who: "evader",
                detail: format!("{ev} -> {e_next}"),
            });
        }
        let hit = caught(&pos, &next, ev, e_next);
        pos = next;
        ev = e_next;
        p_belief.predict(arena);
        for b in &mut e_beliefs {
            b.predict(arena);
        }
        observe(arena, &pos, ev, &mut p_belief, &mut e_beliefs);
        steps.push(snapshot(&pos, ev, &p_belief, &e_beliefs));
        if hit {
            return Ok(EpisodeResult {
                captured_at: Some(turn + 1),
                steps,
            });
        }
    }
    Ok(EpisodeResult {
        captured_at: None,
        steps,
    })
}

/// Applies both sides' observations of the current positions to their beliefs.
fn observe(
    arena: &Arena,
    pursuers: &[NodeId],
    evader: NodeId,
    p_belief: &mut Belief,
    e_beliefs: &mut [Belief],
) {
    if pursuers.iter().any(|&p| arena.sees(p, evader)) {
        p_belief.collapse(evader);
    } else {
        p_belief.exclude_seen_by(arena, pursuers);
    }
    for (b, &p) in e_beliefs.iter_mut().zip(pursuers) {
        if arena.sees(evader, p) {
            b.collapse(p);
        } else {
            b.exclude_seen_by(arena, &[evader]);
        }
    }
}

fn snapshot(pursuers: &[NodeId], evader: NodeId, p_belief: &Belief, e_beliefs: &[Belief]) -> Step {
    Step {
        pursuers: pursuers.to_vec(),
        evader,
        pursuer_belief_size: p_belief.size(),
        truth_in_beliefs: p_belief.contains(evader)
            && e_beliefs.iter().zip(pursuers).all(|(b, &p)| b.contains(p)),
    }
}
