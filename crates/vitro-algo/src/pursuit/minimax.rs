//! Iterative-deepening alpha-beta minimax over sampled information sets (the mission's hunt
//! search).
//!
//! **Strategy fusion**: each sampled determinization is searched as a perfect-information
//! game and the root values are averaged, so below the root the searcher plays as if it knew
//! the sampled position; the values are neither guaranteed nor expected values of the
//! imperfect-information game. The search without that flaw is
//! [`super::game::WorstCaseMinimax`] (alpha-beta over information states); this one is kept
//! because the evacuation mission's hunt (and its trace hashes) use it.
//!
//! At each move the searcher draws `samples` determinizations of the opponent from its belief
//! (duplicates merged, weighted by multiplicity). One search turn is an own move followed by
//! the opponent's reply to it: the opponent is assumed to see the own move (a pessimistic
//! reading of the simultaneous turn), and the pair is then applied at once with the usual
//! capture rules. For every own root move the value is the weighted mean over the samples of
//! the depth-limited alpha-beta value; the search deepens one turn at a time until the budget
//! of expanded nodes runs out, and the best move of the last completed depth is played (the
//! greedy move if not even depth 1 completed).
//!
//! Forward pruning keeps pursuer teams tractable: a pursuer never considers a move that takes
//! it farther from the (determinized) evader; at the root a pursuer move is kept if it does
//! not take it farther from at least one sample. The evader considers all its moves.
//!
//! Evaluation (pursuers' view, the evader negates it): capture scores `10 - 0.01 * turn`,
//! other leaves the closeness of the nearest and the mean pursuer in `[0, 1]`.

use super::sim::{chase_step, closeness, flee_step};
use super::{Arena, Budget, EvaderStrategy, EvaderView, PursuerStrategy, PursuerView};
use crate::graph::NodeId;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

/// Settings of [`Minimax`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MinimaxConfig {
    /// Node expansions per move (and an optional time limit).
    pub budget: Budget,
    /// Determinizations drawn per move. Default 4.
    pub samples: usize,
    /// Deepest search, in turns. Default 12.
    pub max_depth: u32,
    /// Distance at which the evaluation's closeness reaches 0. Default 30.
    pub scale: f64,
}

impl Default for MinimaxConfig {
    fn default() -> Self {
        MinimaxConfig {
            budget: Budget::iterations(3000),
            samples: 4,
            max_depth: 12,
            scale: 30.0,
        }
    }
}

/// Iterative-deepening minimax, usable for either side (see the [module docs](crate::pursuit)).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Minimax {
    /// Settings.
    pub config: MinimaxConfig,
    /// Deepest completed depth at the last move (0: fell back to the greedy move).
    pub last_depth: u32,
    /// Nodes expanded so far over all moves.
    pub nodes_expanded: u64,
}

impl Minimax {
    /// A searcher with these settings.
    pub fn new(config: MinimaxConfig) -> Minimax {
        Minimax {
            config,
            last_depth: 0,
            nodes_expanded: 0,
        }
    }
}

const CAPTURE: f64 = 10.0;

#[derive(Clone)]
struct State {
    pursuers: Vec<NodeId>,
    evader: NodeId,
}

/// A move of the side to play: the pursuers' joint move or the evader's.
#[derive(Clone, PartialEq, Eq)]
enum Move {
    Pursuers(Vec<NodeId>),
    Evader(NodeId),
}

struct Search<'a> {
    arena: &'a Arena,
    /// +1 when the pursuers search, -1 for the evader (values are pursuers' view times this).
    sign: f64,
    scale: f64,
    nodes: u64,
    limit: u64,
    deadline: Option<Instant>,
}

/// Pursuer joint moves that take no pursuer farther from `evader`, closer ones first.
fn pursuer_moves(arena: &Arena, pursuers: &[NodeId], evader: NodeId) -> Vec<Vec<NodeId>> {
    let options: Vec<Vec<NodeId>> = pursuers
        .iter()
        .map(|&p| {
            let here = arena.dist(p, evader);
            let mut o: Vec<NodeId> = arena
                .moves(p)
                .iter()
                .copied()
                .filter(|&v| arena.dist(v, evader) <= here)
                .collect();
            o.sort_by_key(|&v| (arena.dist(v, evader), v));
            o
        })
        .collect();
    product(&options)
}

fn product(options: &[Vec<NodeId>]) -> Vec<Vec<NodeId>> {
    let mut out = vec![Vec::new()];
    for o in options {
        out = out
            .iter()
            .flat_map(|prefix| {
                o.iter().map(move |&v| {
                    let mut m = prefix.clone();
                    m.push(v);
                    m
                })
            })
            .collect();
    }
    out
}

/// Evader moves, those farthest from the nearest pursuer first.
fn evader_moves(arena: &Arena, pursuers: &[NodeId], evader: NodeId) -> Vec<NodeId> {
    let mut o = arena.moves(evader).to_vec();
    o.sort_by_key(|&v| {
        let near = pursuers
            .iter()
            .map(|&p| arena.dist(v, p))
            .min()
            .unwrap_or(0);
        (std::cmp::Reverse(near), v)
    });
    o
}

impl Search<'_> {
    fn own_moves(&self, s: &State) -> Vec<Move> {
        if self.sign > 0.0 {
            pursuer_moves(self.arena, &s.pursuers, s.evader)
                .into_iter()
                .map(Move::Pursuers)
                .collect()
        } else {
            evader_moves(self.arena, &s.pursuers, s.evader)
                .into_iter()
                .map(Move::Evader)
                .collect()
        }
    }

    fn opponent_moves(&self, s: &State) -> Vec<Move> {
        if self.sign > 0.0 {
            evader_moves(self.arena, &s.pursuers, s.evader)
                .into_iter()
                .map(Move::Evader)
                .collect()
        } else {
            pursuer_moves(self.arena, &s.pursuers, s.evader)
                .into_iter()
                .map(Move::Pursuers)
                .collect()
        }
    }

    /// The position after both moves, and whether the evader was caught.
    fn apply(&self, s: &State, a: &Move, b: &Move) -> (State, bool) {
        let (pursuers, evader) = match (a, b) {
            (Move::Pursuers(p), Move::Evader(e)) | (Move::Evader(e), Move::Pursuers(p)) => {
                (p.clone(), *e)
            }
            // Never built: each turn pairs one move of each side.
            _ => (s.pursuers.clone(), s.evader),
        };
        let hit = super::episode::caught(&s.pursuers, &pursuers, s.evader, evader);
        (State { pursuers, evader }, hit)
    }

    fn over_budget(&mut self) -> bool {
        self.nodes += 1;
        self.nodes > self.limit
            || (self.nodes.is_multiple_of(256)
                && self.deadline.is_some_and(|d| Instant::now() >= d))
    }

    /// Own-view value of the own move `m` in `s` (the opponent's best reply), searching
    /// `depth - 1` more turns below; `None` when the budget ran out.
    fn reply_value(
        &mut self,
        s: &State,
        m: &Move,
        depth: u32,
        turn: u32,
        alpha: f64,
        beta: f64,
    ) -> Option<f64> {
        let mut worst = f64::INFINITY;
        for r in self.opponent_moves(s) {
            let (child, hit) = self.apply(s, m, &r);
            let v = if hit {
                self.sign * (CAPTURE - 0.01 * f64::from(turn + 1))
            } else {
                self.turn_value(&child, depth - 1, turn + 1, alpha, beta.min(worst))?
            };
            worst = worst.min(v);
            if worst <= alpha {
                break;
            }
        }
        Some(worst)
    }

    /// Own-view alpha-beta value of `s` searched `depth` turns deep.
    fn turn_value(
        &mut self,
        s: &State,
        depth: u32,
        turn: u32,
        mut alpha: f64,
        beta: f64,
    ) -> Option<f64> {
        if self.over_budget() {
            return None;
        }
        if depth == 0 {
            return Some(self.sign * closeness(self.arena, &s.pursuers, s.evader, self.scale));
        }
        let mut best = f64::NEG_INFINITY;
        for m in self.own_moves(s) {
            let v = self.reply_value(s, &m, depth, turn, alpha, beta)?;
            best = best.max(v);
            alpha = alpha.max(best);
            if alpha >= beta {
                break;
            }
        }
        Some(best)
    }
}

impl Minimax {
    /// Deepens over the root moves `roots` for the weighted determinizations; returns the
    /// index of the best root move of the last completed depth.
    fn run(
        &mut self,
        arena: &Arena,
        sign: f64,
        roots: &[Move],
        samples: &[(State, f64)],
    ) -> Option<usize> {
        let mut search = Search {
            arena,
            sign,
            scale: self.config.scale.max(1.0),
            nodes: 0,
            limit: self.config.budget.iterations.max(1),
            deadline: self.config.budget.deadline(),
        };
        let mut best = None;
        self.last_depth = 0;
        'deepen: for depth in 1..=self.config.max_depth.max(1) {
            let mut values = vec![0.0; roots.len()];
            for (s, w) in samples {
                for (i, m) in roots.iter().enumerate() {
                    match search.reply_value(s, m, depth, 0, f64::NEG_INFINITY, f64::INFINITY) {
                        Some(v) => values[i] += w * v,
                        None => break 'deepen,
                    }
                }
            }
            best = values
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1).then(b.0.cmp(&a.0)))
                .map(|(i, _)| i);
            self.last_depth = depth;
        }
        self.nodes_expanded += search.nodes.min(search.limit);
        best
    }

    fn samples(&self, draw: impl FnMut() -> Option<State>) -> Vec<(State, f64)> {
        let mut draws: Vec<(Vec<NodeId>, NodeId)> = std::iter::repeat_with(draw)
            .take(self.config.samples.max(1))
            .flatten()
            .map(|s| (s.pursuers, s.evader))
            .collect();
        let total = draws.len() as f64;
        draws.sort();
        let mut merged: Vec<(State, f64)> = Vec::new();
        for (pursuers, evader) in draws {
            match merged.last_mut() {
                Some((s, w)) if s.pursuers == pursuers && s.evader == evader => *w += 1.0 / total,
                _ => merged.push((State { pursuers, evader }, 1.0 / total)),
            }
        }
        merged
    }
}

impl PursuerStrategy for Minimax {
    fn choose(&mut self, view: &PursuerView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
        let arena = view.arena;
        let pursuers = view.positions;
        let samples = self.samples(|| {
            view.belief.sample(rng).map(|evader| State {
                pursuers: pursuers.to_vec(),
                evader,
            })
        });
        let greedy_target = view.belief.most_likely().unwrap_or(pursuers[0]);
        // Root: a pursuer move is kept if it brings it no farther from some sample.
        let options: Vec<Vec<NodeId>> = pursuers
            .iter()
            .map(|&p| {
                let mut o: Vec<NodeId> = arena
                    .moves(p)
                    .iter()
                    .copied()
                    .filter(|&v| {
                        samples
                            .iter()
                            .any(|(s, _)| arena.dist(v, s.evader) <= arena.dist(p, s.evader))
                    })
                    .collect();
                o.sort_by_key(|&v| (arena.dist(v, greedy_target), v));
                o
            })
            .collect();
        let roots: Vec<Move> = product(&options).into_iter().map(Move::Pursuers).collect();
        match self
            .run(arena, 1.0, &roots, &samples)
            .and_then(|i| roots.get(i))
        {
            Some(Move::Pursuers(m)) => m.clone(),
            _ => pursuers
                .iter()
                .map(|&p| chase_step(arena, p, greedy_target, rng))
                .collect(),
        }
    }
}

impl EvaderStrategy for Minimax {
    fn choose(&mut self, view: &EvaderView<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        let arena = view.arena;
        let evader = view.position;
        let samples = self.samples(|| {
            let pursuers: Option<Vec<NodeId>> =
                view.beliefs.iter().map(|b| b.sample(&mut *rng)).collect();
            pursuers.map(|pursuers| State { pursuers, evader })
        });
        let likely: Vec<NodeId> = view
            .beliefs
            .iter()
            .map(|b| b.most_likely().unwrap_or(evader))
            .collect();
        let roots: Vec<Move> = evader_moves(arena, &likely, evader)
            .into_iter()
            .map(Move::Evader)
            .collect();
        match self
            .run(arena, -1.0, &roots, &samples)
            .and_then(|i| roots.get(i))
        {
            Some(Move::Evader(e)) => *e,
            _ => flee_step(arena, evader, &likely, rng),
        }
    }
}
