//! Information-set Monte-Carlo tree search by determinization (the mission's hunt search).
//!
//! **Not game-theoretic**: the tree holds only the searcher's own moves and the opponent is
//! the scripted epsilon-greedy default policy below, so the opponent modelled is no smarter
//! than that script. The game-theoretic search, with the opponent's decisions in their own
//! tree and the observations simulated, is [`super::game::MoIsmcts`]; this one is kept
//! because the evacuation mission's hunt (and its trace hashes) use it.
//!
//! Each iteration samples the opponent's positions from the belief (a determinization), then
//! descends a UCT tree over the searching side's own moves. A pursuer team's joint move is
//! decomposed into one tree level per pursuer (branching `deg + 1` instead of its power), and
//! the tree is keyed by own moves only, so one tree is shared by all determinizations (own
//! positions are known, so a node's moves are the same in every sample). The opponent moves
//! by a simple default policy inside the sample (the evader flees from the pursuers it is
//! assumed to see; pursuers chase the evader), simultaneously with the own move. After one new
//! node a rollout plays both sides' default policies (with `epsilon` random moves) up to
//! `horizon` turns from the root.
//!
//! Reward (pursuers' view, the evader gets one minus it): capture at turn `s` of the
//! simulation gives `1 - s / (2 * horizon)` in `[0.5, 1]`; no capture gives half the
//! closeness of the final position (nearest pursuer's distance), in `[0, 0.5)`, so the
//! searches are guided on graphs where capture is rarely reached within the horizon. The
//! evader's reward is thus survival time plus distance kept.

use super::episode::caught;
use super::sim::{chase_step, closeness, flee_step, random_step};
use super::{
    Arena, Belief, Budget, EvaderStrategy, EvaderView, PursuerStrategy, PursuerView, Sampler,
};
use crate::graph::NodeId;
use rand::{Rng, RngCore};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

/// Settings of [`Mcts`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MctsConfig {
    /// Iterations (simulations) per move, and an optional time limit.
    pub budget: Budget,
    /// UCT exploration constant (rewards lie in `[0, 1]`). Default 0.7.
    pub exploration: f64,
    /// Simulated turns from the root. Default 30.
    pub horizon: u32,
    /// Probability of a random move in the default policies. Default 0.2.
    pub epsilon: f64,
}

impl Default for MctsConfig {
    fn default() -> Self {
        MctsConfig {
            budget: Budget::iterations(100),
            exploration: 0.7,
            horizon: 30,
            epsilon: 0.2,
        }
    }
}

/// Information-set MCTS, usable for either side (see the [module docs](crate::pursuit)).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Mcts {
    /// Settings.
    pub config: MctsConfig,
    /// Iterations run so far over all moves (for throughput figures).
    pub iterations_run: u64,
}

impl Mcts {
    /// A searcher with these settings.
    pub fn new(config: MctsConfig) -> Mcts {
        Mcts {
            config,
            iterations_run: 0,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Pursuers,
    Evader,
}

const NONE: u32 = u32::MAX;

struct Node {
    visits: f64,
    value: f64,
    /// One slot per move of the mover at this node (`NONE` = not expanded); empty until the
    /// node is first left.
    children: Vec<u32>,
}

impl Node {
    fn new() -> Node {
        Node {
            visits: 0.0,
            value: 0.0,
            children: Vec::new(),
        }
    }
}

/// A determinized position.
struct State {
    pursuers: Vec<NodeId>,
    evader: NodeId,
}

struct Search<'a> {
    arena: &'a Arena,
    side: Side,
    cfg: MctsConfig,
    nodes: Vec<Node>,
    /// Own pieces: the pursuer count, or 1.
    movers: usize,
    scale: f64,
    /// `epsilon` scaled to 2^32.
    noise: u64,
    /// Scratch buffers reused by every iteration: the tree path, the own moves chosen so
    /// far this turn, and the other side's moves.
    path: Vec<u32>,
    pending: Vec<NodeId>,
    next: Vec<NodeId>,
}

impl Search<'_> {
    fn own_pos(&self, s: &State, mover: usize) -> NodeId {
        match self.side {
            Side::Pursuers => s.pursuers[mover],
            Side::Evader => s.evader,
        }
    }

    /// True with probability `epsilon` (one 32-bit draw: this runs for every piece at
    /// every simulated turn).
    fn noisy(&self, rng: &mut ChaCha8Rng) -> bool {
        u64::from(rng.next_u32()) < self.noise
    }

    /// The pursuers' default moves from `s`, written to `out`.
    fn pursuer_policy(&self, s: &State, rng: &mut ChaCha8Rng, out: &mut Vec<NodeId>) {
        out.clear();
        for &p in &s.pursuers {
            out.push(if self.noisy(rng) {
                random_step(self.arena, p, rng)
            } else {
                chase_step(self.arena, p, s.evader, rng)
            });
        }
    }

    fn evader_policy(&self, s: &State, rng: &mut ChaCha8Rng) -> NodeId {
        if self.noisy(rng) {
            random_step(self.arena, s.evader, rng)
        } else {
            flee_step(self.arena, s.evader, &s.pursuers, rng)
        }
    }

    /// Applies a full turn (the pursuers' moves are taken from `pursuers`, which is left
    /// holding the old positions); true on capture.
    fn apply(&self, s: &mut State, pursuers: &mut Vec<NodeId>, evader: NodeId) -> bool {
        let hit = caught(&s.pursuers, pursuers, s.evader, evader);
        std::mem::swap(&mut s.pursuers, pursuers);
        s.evader = evader;
        hit
    }

    /// The own side's reward from the pursuers' `r`.
    fn own(&self, r: f64) -> f64 {
        match self.side {
            Side::Pursuers => r,
            Side::Evader => 1.0 - r,
        }
    }

    fn capture_reward(&self, turn: u32) -> f64 {
        1.0 - f64::from(turn) / (2.0 * f64::from(self.cfg.horizon.max(1)))
    }

    fn iterate(&mut self, mut s: State, rng: &mut ChaCha8Rng) {
        let mut path = std::mem::take(&mut self.path);
        let mut pending = std::mem::take(&mut self.pending);
        let mut next = std::mem::take(&mut self.next);
        path.clear();
        path.push(0);
        pending.clear();
        let mut node = 0usize;
        let mut turn = 0u32;
        let mut expanded = false;
        let mut result: Option<f64> = None;
        while turn < self.cfg.horizon && !expanded {
            let mover = pending.len();
            let moves = self.arena.moves(self.own_pos(&s, mover));
            if self.nodes[node].children.is_empty() {
                self.nodes[node].children = vec![NONE; moves.len()];
            }
            let children = &self.nodes[node].children;
            let fresh = children.iter().filter(|&&c| c == NONE).count();
            let slot = if fresh > 0 {
                let pick = rng.random_range(0..fresh);
                let slot = children
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| **c == NONE)
                    .nth(pick)
                    .map_or(0, |(i, _)| i);
                let id = self.nodes.len() as u32;
                self.nodes.push(Node::new());
                self.nodes[node].children[slot] = id;
                expanded = true;
                slot
            } else {
                self.select(node)
            };
            node = self.nodes[node].children[slot] as usize;
            path.push(node as u32);
            pending.push(moves[slot]);
            if pending.len() == self.movers {
                let hit = match self.side {
                    Side::Pursuers => {
                        let e = self.evader_policy(&s, rng);
                        self.apply(&mut s, &mut pending, e)
                    }
                    Side::Evader => {
                        self.pursuer_policy(&s, rng, &mut next);
                        self.apply(&mut s, &mut next, pending[0])
                    }
                };
                pending.clear();
                turn += 1;
                if hit {
                    result = Some(self.capture_reward(turn));
                    break;
                }
            }
        }
        // Finish a partial joint move with the default policy, then roll out.
        if result.is_none() && !pending.is_empty() && turn < self.cfg.horizon {
            self.pursuer_policy(&s, rng, &mut next);
            next[..pending.len()].copy_from_slice(&pending);
            let e = self.evader_policy(&s, rng);
            turn += 1;
            if self.apply(&mut s, &mut next, e) {
                result = Some(self.capture_reward(turn));
            }
        }
        while result.is_none() && turn < self.cfg.horizon {
            self.pursuer_policy(&s, rng, &mut next);
            let e = self.evader_policy(&s, rng);
            turn += 1;
            if self.apply(&mut s, &mut next, e) {
                result = Some(self.capture_reward(turn));
            }
        }
        let r = result
            .unwrap_or_else(|| 0.5 * closeness(self.arena, &s.pursuers, s.evader, self.scale));
        let reward = self.own(r);
        for &n in &path {
            let n = &mut self.nodes[n as usize];
            n.visits += 1.0;
            n.value += reward;
        }
        self.path = path;
        self.pending = pending;
        self.next = next;
    }

    /// UCT child choice among fully expanded children (ties: the first).
    fn select(&self, node: usize) -> usize {
        let parent = &self.nodes[node];
        let log_n = libm::log(parent.visits.max(1.0));
        let mut best = 0;
        let mut best_score = f64::NEG_INFINITY;
        for (i, &c) in parent.children.iter().enumerate() {
            let child = &self.nodes[c as usize];
            let score = child.value / child.visits.max(1.0)
                + self.cfg.exploration * (log_n / child.visits.max(1.0)).sqrt();
            if score > best_score {
                best = i;
                best_score = score;
            }
        }
        best
    }

    /// The most visited move of each own piece along the root's principal line; `None` where
    /// the tree has no visited child.
    fn best_moves(&self, s: &State) -> Vec<Option<NodeId>> {
        let mut node = 0usize;
        let mut out = Vec::with_capacity(self.movers);
        for mover in 0..self.movers {
            let moves = self.arena.moves(self.own_pos(s, mover));
            let best = self.nodes[node]
                .children
                .iter()
                .enumerate()
                .filter(|(_, c)| **c != NONE)
                .max_by(|a, b| {
                    let va = self.nodes[*a.1 as usize].visits;
                    let vb = self.nodes[*b.1 as usize].visits;
                    va.total_cmp(&vb).then(b.0.cmp(&a.0))
                });
            match best {
                Some((slot, &child)) => {
                    out.push(Some(moves[slot]));
                    node = child as usize;
                }
                None => {
                    out.extend(std::iter::repeat_n(None, self.movers - mover));
                    break;
                }
            }
        }
        out
    }
}

impl Mcts {
    fn run(
        &mut self,
        arena: &Arena,
        side: Side,
        root: &State,
        mut sample: impl FnMut(&mut ChaCha8Rng) -> Option<State>,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Option<NodeId>> {
        let mut search = Search {
            arena,
            side,
            cfg: self.config,
            nodes: vec![Node::new()],
            movers: match side {
                Side::Pursuers => root.pursuers.len(),
                Side::Evader => 1,
            },
            scale: f64::from(u32::from(arena.diameter()).min(self.config.horizon).max(1)),
            noise: (self.config.epsilon.clamp(0.0, 1.0) * 4_294_967_296.0) as u64,
            path: Vec::new(),
            pending: Vec::new(),
            next: Vec::new(),
        };
        let deadline = self.config.budget.deadline();
        for i in 0..self.config.budget.iterations.max(1) {
            if i > 0 && deadline.is_some_and(|d| Instant::now() >= d) {
                break;
            }
            let Some(s) = sample(rng) else { break };
            search.iterate(s, rng);
            self.iterations_run += 1;
        }
        search.best_moves(root)
    }
}

impl PursuerStrategy for Mcts {
    fn choose(&mut self, view: &PursuerView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
        let pursuers = view.positions.to_vec();
        let root = State {
            pursuers: pursuers.clone(),
            evader: view.belief.most_likely().unwrap_or(pursuers[0]),
        };
        let sampler = view.belief.sampler();
        let best = self.run(
            view.arena,
            Side::Pursuers,
            &root,
            |rng| {
                sampler.sample(rng).map(|evader| State {
                    pursuers: pursuers.clone(),
                    evader,
                })
            },
            rng,
        );
        // Pieces the tree says nothing about chase the most likely position.
        best.iter()
            .zip(view.positions)
            .map(|(b, &p)| b.unwrap_or_else(|| chase_step(view.arena, p, root.evader, rng)))
            .collect()
    }
}

impl EvaderStrategy for Mcts {
    fn choose(&mut self, view: &EvaderView<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        let likely: Vec<NodeId> = view
            .beliefs
            .iter()
            .map(|b| b.most_likely().unwrap_or(view.position))
            .collect();
        let root = State {
            pursuers: likely.clone(),
            evader: view.position,
        };
        let samplers: Vec<Sampler> = view.beliefs.iter().map(Belief::sampler).collect();
        let evader = view.position;
        let best = self.run(
            view.arena,
            Side::Evader,
            &root,
            |rng| {
                let pursuers: Option<Vec<NodeId>> =
                    samplers.iter().map(|b| b.sample(rng)).collect();
                pursuers.map(|pursuers| State { pursuers, evader })
            },
            rng,
        );
        best.first()
            .copied()
            .flatten()
            .unwrap_or_else(|| flee_step(view.arena, view.position, &likely, rng))
    }
}
