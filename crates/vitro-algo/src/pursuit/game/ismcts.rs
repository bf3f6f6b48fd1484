//! Multiple-observer information-set MCTS (MO-ISMCTS, Cowling, Powley and Whitehouse 2012)
//! for the turn-based game.
//!
//! There is one tree per player, each over that player's own information:
//! - the **pursuers' tree**: its nodes are the team's observation histories. A joint move is
//!   one tree level per pursuer (branching `deg + 1`, not its power); after the evader's move
//!   comes an observation edge, keyed by what the team saw (the evader's vertex, or nothing).
//! - the **evader's tree**: the evader is omniscient, so its nodes are full histories: its
//!   start (the determinization), the pursuers' joint move it observed, its own move, ...
//!
//! Each iteration draws a determinization (the evader's vertex, from the pursuers'
//! information set) and descends both trees at once: every decision is taken by the player
//! who owns it, by UCB1 on its own node's statistics, so the evader inside the search is as
//! smart as the search (not a scripted policy). The pursuers' tree cannot tell
//! determinizations apart except through the observations the simulation produces (the
//! visibility relation is applied inside every simulated round), so its choices are
//! functions of what the team would actually know. When one tree gains a node, the
//! simulation continues with default policies that respect the same information: the
//! evader flees (omniscient), the pursuers chase the evader while they see it and otherwise
//! its last sighting (or a guess drawn from their information set).
//!
//! Reward (pursuers; the evader gets one minus it): capture in simulated round `s` of `H`
//! gives `1 - (s - 1) / (2H)`, in `(0.5, 1]`; otherwise `0.5 * (w * f + (1 - w) * c)`, where
//! `f` is the fraction of simulated rounds with the evader in sight, `c` the closeness of
//! the nearest pursuer at the end, and `w` [`MoIsmctsConfig::sight_weight`]: capture first,
//! then keeping the evader in sight.
//!
//! On the evader's side the search starts from the true position (the evader knows it), so
//! the pursuers modelled in its simulations learn against that one position: pessimistic for
//! the evader.

use super::super::sim::{chase_step, closeness, flee_step, random_step};
use super::super::{Budget, Sampler};
use super::{Arena, EvaderInfo, GameEvader, TeamStrategy, TeamView};
use crate::graph::NodeId;
use rand::{Rng, RngCore};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

/// Settings of [`MoIsmcts`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MoIsmctsConfig {
    /// Iterations per move, and an optional time limit.
    pub budget: Budget,
    /// UCB1 exploration constant (rewards lie in `[0, 1]`). Default 0.7.
    pub exploration: f64,
    /// Simulated rounds at most (fewer when the episode ends sooner). Default 20.
    pub horizon: u32,
    /// Probability of a random move in the default policies. Default 0.1.
    pub epsilon: f64,
    /// Weight of time-in-sight against closeness in the reward without capture. Default 0.5.
    pub sight_weight: f64,
}

impl Default for MoIsmctsConfig {
    fn default() -> Self {
        MoIsmctsConfig {
            budget: Budget::iterations(300),
            exploration: 0.7,
            horizon: 20,
            epsilon: 0.1,
            sight_weight: 0.5,
        }
    }
}

/// MO-ISMCTS for either side of the turn-based game (see the [game](super) module docs).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct MoIsmcts {
    /// Settings.
    pub config: MoIsmctsConfig,
    /// Iterations run so far over all moves.
    pub iterations_run: u64,
}

impl MoIsmcts {
    /// A searcher with these settings.
    pub fn new(config: MoIsmctsConfig) -> MoIsmcts {
        MoIsmcts {
            config,
            iterations_run: 0,
        }
    }
}

/// Observation key: the evader was not seen.
const UNSEEN: u64 = u64::MAX;

struct Node {
    visits: f64,
    value: f64,
    /// `(key, child)`: a move slot at decision nodes, an observation at the others.
    children: Vec<(u64, u32)>,
}

struct Tree {
    nodes: Vec<Node>,
}

impl Tree {
    fn new() -> Tree {
        Tree {
            nodes: vec![Node {
                visits: 0.0,
                value: 0.0,
                children: Vec::new(),
            }],
        }
    }

    fn add(&mut self, node: u32, key: u64) -> u32 {
        let id = self.nodes.len() as u32;
        self.nodes.push(Node {
            visits: 0.0,
            value: 0.0,
            children: Vec::new(),
        });
        self.nodes[node as usize].children.push((key, id));
        id
    }

    /// The child for an observation `key`, and whether it was created now.
    fn enter(&mut self, node: u32, key: u64) -> (u32, bool) {
        match self.nodes[node as usize]
            .children
            .iter()
            .find(|(k, _)| *k == key)
        {
            Some(&(_, c)) => (c, false),
            None => (self.add(node, key), true),
        }
    }

    /// A decision among `moves` slots: an untried slot at random while there is one (a new
    /// node), otherwise UCB1. Returns the slot, the child and whether it was created.
    fn decide(
        &mut self,
        node: u32,
        moves: usize,
        exploration: f64,
        rng: &mut ChaCha8Rng,
    ) -> (usize, u32, bool) {
        let children = &self.nodes[node as usize].children;
        if children.len() < moves {
            let untried = moves - children.len();
            let mut pick = rng.random_range(0..untried);
            for slot in 0..moves {
                if children.iter().any(|(k, _)| *k == slot as u64) {
                    continue;
                }
                if pick == 0 {
                    return (slot, self.add(node, slot as u64), true);
                }
                pick -= 1;
            }
        }
        let log_n = libm::log(self.nodes[node as usize].visits.max(1.0));
        let mut best = (0usize, 0u32);
        let mut best_score = f64::NEG_INFINITY;
        for &(key, c) in children {
            let child = &self.nodes[c as usize];
            let n = child.visits.max(1.0);
            let score = child.value / n + exploration * libm::sqrt(log_n / n);
            if score > best_score {
                best_score = score;
                best = (key as usize, c);
            }
        }
        (best.0, best.1, false)
    }

    /// The most visited child `(key, child)` (ties: the smallest key).
    fn most_visited(&self, node: u32) -> Option<(u64, u32)> {
        self.nodes[node as usize]
            .children
            .iter()
            .copied()
            .max_by(|a, b| {
                let va = self.nodes[a.1 as usize].visits;
                let vb = self.nodes[b.1 as usize].visits;
                va.total_cmp(&vb).then(b.0.cmp(&a.0))
            })
    }
}

/// Where an iteration starts.
struct Root<'a> {
    pursuers: &'a [NodeId],
    /// The pursuers' information set, for the determinization and their rollout guess.
    belief: &'a Sampler,
    /// True if the team sees the evader at the root.
    seen: bool,
    /// `Some(e)`: the evader searches, stands at `e` and moves first.
    evader: Option<NodeId>,
    horizon: u32,
}

struct Search<'a> {
    arena: &'a Arena,
    cfg: MoIsmctsConfig,
    team: Tree,
    evader: Tree,
    scale: f64,
    noise: u64,
}

impl Search<'_> {
    fn noisy(&self, rng: &mut ChaCha8Rng) -> bool {
        u64::from(rng.next_u32()) < self.noise
    }

    fn joint_key(&self, pursuers: &[NodeId]) -> u64 {
        let n = self.arena.node_count() as u64 + 1;
        pursuers
            .iter()
            .fold(0u64, |h, &p| h.wrapping_mul(n).wrapping_add(p as u64 + 1))
    }

    /// One simulation; returns false if the root information set is empty.
    fn iterate(&mut self, root: &Root<'_>, rng: &mut ChaCha8Rng) -> bool {
        let arena = self.arena;
        let c = self.cfg.exploration;
        let (mut e, mut en) = match root.evader {
            Some(e) => (e, 0u32),
            None => match root.belief.sample(rng) {
                Some(e) => (e, self.evader.enter(0, e as u64).0),
                None => return false,
            },
        };
        // The team's belief about the evader in the rollout: the last sighting, else a guess.
        let mut target = if root.seen {
            e
        } else {
            root.belief.sample(rng).unwrap_or(e)
        };
        let mut seen_now = root.seen;
        let mut pursuers = root.pursuers.to_vec();
        let mut team_path = vec![0u32];
        let mut evader_path = vec![0u32];
        if en != 0 {
            evader_path.push(en);
        }
        let mut pn = 0u32;
        let mut in_tree = true;
        let mut evader_first = root.evader.is_some();
        let (mut rounds, mut in_sight) = (0u32, 0u32);
        let mut captured: Option<u32> = None;
        let horizon = root.horizon.max(1);
        while rounds < horizon {
            if !evader_first {
                for piece in pursuers.iter_mut() {
                    let p = *piece;
                    let moves = arena.moves(p);
                    *piece = if in_tree {
                        let (slot, child, new) = self.team.decide(pn, moves.len(), c, rng);
                        pn = child;
                        team_path.push(child);
                        in_tree &= !new;
                        moves[slot]
                    } else if self.noisy(rng) {
                        random_step(arena, p, rng)
                    } else if seen_now {
                        chase_step(arena, p, e, rng)
                    } else if p == target {
                        random_step(arena, p, rng)
                    } else {
                        chase_step(arena, p, target, rng)
                    };
                }
                if pursuers.contains(&e) {
                    captured = Some(rounds + 1);
                    break;
                }
                if in_tree {
                    let (child, new) = self.evader.enter(en, self.joint_key(&pursuers));
                    en = child;
                    evader_path.push(child);
                    in_tree &= !new;
                }
            }
            evader_first = false;
            let moves = arena.moves(e);
            e = if in_tree {
                let (slot, child, new) = self.evader.decide(en, moves.len(), c, rng);
                en = child;
                evader_path.push(child);
                in_tree &= !new;
                moves[slot]
            } else {
                let step = if self.noisy(rng) {
                    random_step(arena, e, rng)
                } else {
                    e
                };
                if step == e || pursuers.contains(&step) {
                    flee_step(arena, e, &pursuers, rng)
                } else {
                    step
                }
            };
            rounds += 1;
            if pursuers.contains(&e) {
                captured = Some(rounds);
                break;
            }
            seen_now = pursuers.iter().any(|&p| arena.sees(p, e));
            if seen_now {
                in_sight += 1;
                target = e;
            }
            if in_tree {
                let key = if seen_now { e as u64 } else { UNSEEN };
                let (child, new) = self.team.enter(pn, key);
                pn = child;
                team_path.push(child);
                in_tree &= !new;
            }
        }
        let r = match captured {
            Some(s) => 1.0 - f64::from(s - 1) / (2.0 * f64::from(horizon)),
            None => {
                let w = self.cfg.sight_weight.clamp(0.0, 1.0);
                let sight = f64::from(in_sight) / f64::from(rounds.max(1));
                0.5 * (w * sight + (1.0 - w) * closeness(arena, &pursuers, e, self.scale))
            }
        };
        for &n in &team_path {
            let n = &mut self.team.nodes[n as usize];
            n.visits += 1.0;
            n.value += r;
        }
        for &n in &evader_path {
            let n = &mut self.evader.nodes[n as usize];
            n.visits += 1.0;
            n.value += 1.0 - r;
        }
        true
    }
}

impl MoIsmcts {
    fn search<'a>(
        &mut self,
        arena: &'a Arena,
        root: &Root<'_>,
        rng: &mut ChaCha8Rng,
    ) -> Search<'a> {
        let mut s = Search {
            arena,
            cfg: self.config,
            team: Tree::new(),
            evader: Tree::new(),
            scale: f64::from(u32::from(arena.diameter()).clamp(1, root.horizon.max(1))),
            noise: (self.config.epsilon.clamp(0.0, 1.0) * 4_294_967_296.0) as u64,
        };
        let deadline = self.config.budget.deadline();
        for i in 0..self.config.budget.iterations.max(1) {
            if i > 0 && deadline.is_some_and(|d| Instant::now() >= d) {
                break;
            }
            if !s.iterate(root, rng) {
                break;
            }
            self.iterations_run += 1;
        }
        s
    }
}

impl TeamStrategy for MoIsmcts {
    fn name(&self) -> String {
        format!("MO-ISMCTS ({} iterations)", self.config.budget.iterations)
    }

    fn choose(&mut self, view: &TeamView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
        let sampler = view.belief.sampler();
        let root = Root {
            pursuers: view.positions,
            belief: &sampler,
            seen: view.belief.size() == 1,
            evader: None,
            horizon: self.config.horizon.min(view.rounds_left).max(1),
        };
        let s = self.search(view.arena, &root, rng);
        let guess = view.belief.most_likely();
        let mut node = Some(0u32);
        view.positions
            .iter()
            .map(|&p| {
                let moves = view.arena.moves(p);
                match node.and_then(|n| s.team.most_visited(n)) {
                    Some((slot, child)) => {
                        node = Some(child);
                        moves[slot as usize]
                    }
                    None => {
                        node = None;
                        guess.map_or(p, |t| chase_step(view.arena, p, t, rng))
                    }
                }
            })
            .collect()
    }
}

impl GameEvader for MoIsmcts {
    fn name(&self) -> String {
        format!("MO-ISMCTS ({} iterations)", self.config.budget.iterations)
    }

    fn place(&mut self, arena: &Arena, pursuers: &[NodeId], rng: &mut ChaCha8Rng) -> NodeId {
        super::FleeingHider.place(arena, pursuers, rng)
    }

    fn choose(&mut self, info: &EvaderInfo<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        let sampler = info.pursuer_belief.sampler();
        let root = Root {
            pursuers: info.pursuers,
            belief: &sampler,
            seen: info.pursuer_belief.size() == 1,
            evader: Some(info.position),
            horizon: self.config.horizon.min(info.rounds_left).max(1),
        };
        let s = self.search(info.arena, &root, rng);
        let moves = info.arena.moves(info.position);
        match s.evader.most_visited(0) {
            Some((slot, _)) => moves[slot as usize],
            None => flee_step(info.arena, info.position, info.pursuers, rng),
        }
    }
}
