//! Minimax over the pursuers' information states (no determinization, no strategy fusion).
//!
//! A search state is what the team knows: its own positions and the **set** `S` of vertices
//! the evader may occupy. The team picks a joint move `m`; no capture means the evader is in
//! `S1 = S \ m` (if `S1` is empty, every consistent evader is caught: capture). The evader
//! then steps to `S2 = N[S1] \ m` (it never steps onto a pursuer), and the adversary chooses
//! the observation: "seen at `v`" for a vertex `v` of `S2` the team sees, or "not seen" with
//! the unseen rest of `S2`. The value is the max over the team's moves of the min over the
//! adversary's observations, so a move's value is what it **guarantees** against every
//! evader consistent with the team's information: the team's choices depend only on what it
//! knows, and the evader is worst-case (omniscient). With full visibility every `S` is a
//! single vertex and this is plain alpha-beta on the cops-and-robber game.
//!
//! The search deepens one round at a time until the budget of expanded nodes runs out and
//! plays the best move of the last completed depth. Pursuers are interchangeable, so joint
//! moves that are permutations of one another are searched once. Leaves are scored (team's
//! view, in `[0, 1]`) by `0.4 * [evader located] + 0.3 * (1 - (|S| - 1) / n) + 0.3 * (1 -
//! d / D)`, with `d` the mean over `S` of the distance to the nearest pursuer and `D` the
//! diameter: the objectives again, capture first (capture scores `10 - 0.01 * round`), then
//! sight and a small information set. (The leaf score is a heuristic; only the max–min over
//! moves and observations is worst-case. Where no capture can be guaranteed within the
//! depth, the values are heuristic guarantees only, and the search is weak: see the anytime
//! evidence.)

use super::super::Budget;
use super::super::sim::chase_step;
use super::{Arena, TeamStrategy, TeamView};
use crate::graph::NodeId;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;
use std::time::Instant;

/// Settings of [`WorstCaseMinimax`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorstCaseMinimaxConfig {
    /// Node expansions per move, and an optional time limit.
    pub budget: Budget,
    /// Deepest search, in rounds. Default 12.
    pub max_depth: u32,
}

impl Default for WorstCaseMinimaxConfig {
    fn default() -> Self {
        WorstCaseMinimaxConfig {
            budget: Budget::iterations(3000),
            max_depth: 12,
        }
    }
}

/// Iterative-deepening alpha-beta over information states (see the [game](super) module docs).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct WorstCaseMinimax {
    /// Settings.
    pub config: WorstCaseMinimaxConfig,
    /// Deepest completed depth at the last move (0: fell back to the greedy move).
    pub last_depth: u32,
}

impl WorstCaseMinimax {
    /// A searcher with these settings.
    pub fn new(config: WorstCaseMinimaxConfig) -> WorstCaseMinimax {
        WorstCaseMinimax {
            config,
            last_depth: 0,
        }
    }
}

const CAPTURE: f64 = 10.0;

struct Search<'a> {
    arena: &'a Arena,
    nodes: u64,
    limit: u64,
    deadline: Option<Instant>,
}

/// The team's joint moves from `pursuers`, one per multiset of destinations, closest to
/// `toward` first.
fn joint_moves(arena: &Arena, pursuers: &[NodeId], toward: NodeId) -> Vec<Vec<NodeId>> {
    let mut out: Vec<Vec<NodeId>> = vec![Vec::new()];
    for &p in pursuers {
        let mut o = arena.moves(p).to_vec();
        o.sort_by_key(|&v| (arena.dist(v, toward), v));
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
    let mut seen = BTreeSet::new();
    out.retain(|m| {
        let mut key = m.clone();
        key.sort_unstable();
        seen.insert(key)
    });
    out.sort_by_key(|m| {
        m.iter()
            .map(|&v| u32::from(arena.dist(v, toward)))
            .sum::<u32>()
    });
    out
}

impl Search<'_> {
    fn over_budget(&mut self) -> bool {
        self.nodes += 1;
        self.nodes > self.limit
            || (self.nodes.is_multiple_of(256)
                && self.deadline.is_some_and(|d| Instant::now() >= d))
    }

    fn leaf(&self, pursuers: &[NodeId], set: &[NodeId]) -> f64 {
        let a = self.arena;
        let diameter = f64::from(a.diameter().max(1));
        // The mean over `S` of the distance to the nearest pursuer: progress in sweeping `S`
        // (its worst case is flat while no capture can be guaranteed).
        let total: u64 = set
            .iter()
            .map(|&s| u64::from(pursuers.iter().map(|&p| a.dist(p, s)).min().unwrap_or(0)))
            .sum();
        let mean = total as f64 / set.len().max(1) as f64;
        let located = if set.len() == 1 { 1.0 } else { 0.0 };
        let small = 1.0 - (set.len().saturating_sub(1)) as f64 / a.node_count() as f64;
        let near = 1.0 - (mean / diameter).min(1.0);
        0.4 * located + 0.3 * small + 0.3 * near
    }

    /// The adversary's replies to the team's move `m` from information set `set`: `None`
    /// when every consistent evader is caught, else the observation branches (unseen first).
    fn branches(&self, m: &[NodeId], set: &[NodeId]) -> Option<Vec<Vec<NodeId>>> {
        let a = self.arena;
        let n = a.node_count();
        let mut reach = vec![false; n];
        let mut any = false;
        for &s in set.iter().filter(|s| !m.contains(s)) {
            any = true;
            for &v in a.moves(s) {
                reach[v] = true;
            }
        }
        if !any {
            return None;
        }
        for &p in m {
            reach[p] = false;
        }
        let mut unseen = Vec::new();
        let mut seen = Vec::new();
        for v in (0..n).filter(|&v| reach[v]) {
            if m.iter().any(|&p| a.sees(p, v)) {
                seen.push(v);
            } else {
                unseen.push(v);
            }
        }
        // The seen ones farthest from the team first (likely the adversary's best).
        seen.sort_by_key(|&v| {
            std::cmp::Reverse(m.iter().map(|&p| a.dist(p, v)).min().unwrap_or(0))
        });
        let mut out = Vec::with_capacity(seen.len() + 1);
        if !unseen.is_empty() {
            out.push(unseen);
        }
        out.extend(seen.into_iter().map(|v| vec![v]));
        Some(out)
    }

    /// The team's guaranteed value of move `m` (then `depth - 1` more rounds).
    fn move_value(
        &mut self,
        m: &[NodeId],
        set: &[NodeId],
        depth: u32,
        round: u32,
        alpha: f64,
        beta: f64,
    ) -> Option<f64> {
        let Some(branches) = self.branches(m, set) else {
            return Some(CAPTURE - 0.01 * f64::from(round + 1));
        };
        let mut worst = f64::INFINITY;
        for b in branches {
            let v = self.value(m, &b, depth - 1, round + 1, alpha, beta.min(worst))?;
            worst = worst.min(v);
            if worst <= alpha {
                break;
            }
        }
        Some(worst)
    }

    /// Alpha-beta value of the team to move at `pursuers` knowing `set`.
    fn value(
        &mut self,
        pursuers: &[NodeId],
        set: &[NodeId],
        depth: u32,
        round: u32,
        mut alpha: f64,
        beta: f64,
    ) -> Option<f64> {
        if self.over_budget() {
            return None;
        }
        if depth == 0 {
            return Some(self.leaf(pursuers, set));
        }
        let mut best = f64::NEG_INFINITY;
        for m in joint_moves(self.arena, pursuers, set[set.len() / 2]) {
            let v = self.move_value(&m, set, depth, round, alpha, beta)?;
            best = best.max(v);
            alpha = alpha.max(best);
            if alpha >= beta {
                break;
            }
        }
        Some(best)
    }
}

impl TeamStrategy for WorstCaseMinimax {
    fn name(&self) -> String {
        format!(
            "worst-case minimax over information sets ({} nodes)",
            self.config.budget.iterations
        )
    }

    fn choose(&mut self, view: &TeamView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
        let arena = view.arena;
        let set: Vec<NodeId> = view.belief.members().collect();
        let target = view.belief.most_likely().unwrap_or(view.positions[0]);
        let greedy = |rng: &mut ChaCha8Rng| -> Vec<NodeId> {
            view.positions
                .iter()
                .map(|&p| chase_step(arena, p, target, rng))
                .collect()
        };
        self.last_depth = 0;
        if set.is_empty() {
            return greedy(rng);
        }
        let mut roots = joint_moves(arena, view.positions, set[set.len() / 2]);
        let mut search = Search {
            arena,
            nodes: 0,
            limit: self.config.budget.iterations.max(1),
            deadline: self.config.budget.deadline(),
        };
        let max_depth = self.config.max_depth.min(view.rounds_left).max(1);
        'deepen: for depth in 1..=max_depth {
            let mut best: Option<(usize, f64)> = None;
            for (i, m) in roots.iter().enumerate() {
                let alpha = best.map_or(f64::NEG_INFINITY, |(_, v)| v);
                match search.move_value(m, &set, depth, 0, alpha, f64::INFINITY) {
                    Some(v) => {
                        if best.is_none_or(|(_, b)| v > b) {
                            best = Some((i, v));
                        }
                    }
                    None => break 'deepen,
                }
            }
            if let Some((i, v)) = best {
                // The best move first at the next depth (better cut-offs).
                let m = roots.remove(i);
                roots.insert(0, m);
                self.last_depth = depth;
                if v >= CAPTURE - 1.0 {
                    break;
                }
            }
        }
        if self.last_depth == 0 {
            return greedy(rng);
        }
        roots.swap_remove(0)
    }
}
