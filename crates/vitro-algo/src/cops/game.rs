//! The solved game for a fixed number of cops: retrograde analysis over every position, and
//! the optimal strategies read off the solved table.

use std::collections::VecDeque;

use super::multiset::Multisets;
use super::options::{CopOptions, CopsError};
use crate::graph::{Graph, NodeId};

const UNKNOWN: u32 = u32::MAX;

/// Successor lists are precomputed when they hold at most this many entries (64 MiB).
const MOVE_CACHE_LIMIT: u64 = 1 << 24;

/// For every cop placement, the ranks of the placements reachable in one move.
struct MoveCache {
    offsets: Vec<usize>,
    ranks: Vec<u32>,
}

impl MoveCache {
    fn new(closed: &[Vec<u32>], sets: &Multisets) -> MoveCache {
        let mut offsets = Vec::with_capacity(sets.len() + 1);
        let mut ranks = Vec::new();
        let mut scratch = Vec::new();
        offsets.push(0);
        for rank in 0..sets.len() {
            successor_ranks(closed, sets, rank, &mut scratch);
            ranks.extend_from_slice(&scratch);
            offsets.push(ranks.len());
        }
        MoveCache { offsets, ranks }
    }

    fn get(&self, rank: usize) -> &[u32] {
        &self.ranks[self.offsets[rank]..self.offsets[rank + 1]]
    }
}

/// Fills `out` with the ranks of the placements the cops can reach from placement `rank` in
/// one move (each cop along an edge or staying), sorted and deduplicated.
fn successor_ranks(closed: &[Vec<u32>], sets: &Multisets, rank: usize, out: &mut Vec<u32>) {
    out.clear();
    let here = sets.get(rank);
    let k = here.len();
    let mut digits = [0usize; 16];
    let mut tuple = [0u32; 16];
    if k > digits.len() {
        // More cops than the fixed buffers hold: fall back to heap buffers.
        let mut digits = vec![0usize; k];
        let mut tuple = vec![0u32; k];
        product_ranks(closed, sets, here, &mut digits, &mut tuple, out);
    } else {
        product_ranks(closed, sets, here, &mut digits[..k], &mut tuple[..k], out);
    }
    out.sort_unstable();
    out.dedup();
}

fn product_ranks(
    closed: &[Vec<u32>],
    sets: &Multisets,
    here: &[u32],
    digits: &mut [usize],
    tuple: &mut [u32],
    out: &mut Vec<u32>,
) {
    loop {
        for (i, (&c, &d)) in here.iter().zip(digits.iter()).enumerate() {
            tuple[i] = closed[c as usize][d];
        }
        tuple.sort_unstable();
        out.push(sets.rank(tuple) as u32);
        let mut carried = true;
        for (digit, &c) in digits.iter_mut().zip(here) {
            *digit += 1;
            if *digit < closed[c as usize].len() {
                carried = false;
                break;
            }
            *digit = 0;
        }
        if carried {
            return;
        }
    }
}

/// Whose move it is in a position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Turn {
    /// The cops move next (all of them at once, each along an edge or staying).
    Cops,
    /// The robber moves next (along an edge or staying).
    Robber,
}

/// The value of a position under optimal play.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Outcome {
    /// The cops force capture within this many further moves (plies, counting both sides'
    /// moves); 0 means the robber stands on a cop.
    CopsWin {
        /// Plies until capture when the cops hurry and the robber delays.
        plies: u32,
    },
    /// The robber can evade forever.
    RobberEscapes,
}

/// The cops-and-robber game on one graph with a fixed number of cops, solved exactly.
///
/// Rules: the cops are placed first, then the robber, seeing them; then the cops (all at once)
/// and the robber alternate, each piece moving along an edge or staying; the cops win when a
/// cop stands on the robber's vertex. Both sides see everything.
///
/// Solving is retrograde analysis (backward induction from the captured positions) over all
/// positions `(cop multiset, robber vertex, turn)`: cops are interchangeable, so a placement is a
/// sorted multiset, which shrinks the table by about `k!`. Positions are settled in breadth-first
/// order, which gives the exact minimax capture time as a by-product: the cops' strategy
/// captures as fast as possible, the robber's delays capture as long as possible (or evades).
///
/// ```
/// use vitro_algo::cops::{CopOptions, CopsGame};
/// use vitro_algo::graph;
///
/// let c4 = graph::cycle(4)?;
/// assert!(!CopsGame::solve(&c4, 1, &CopOptions::default())?.cops_win());
/// let game = CopsGame::solve(&c4, 2, &CopOptions::default())?;
/// assert!(game.cops_win());
/// let cops = game.cop_placement();
/// let robber = game.robber_placement(&cops)?;
/// let next = game.cop_move(&cops, robber)?;
/// assert!(next.contains(&robber) || game.robber_move(&next, robber).is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct CopsGame {
    graph: Graph,
    cops: usize,
    /// Closed neighbourhoods `N[v]` (v and its neighbours), sorted.
    closed: Vec<Vec<u32>>,
    sets: Multisets,
    /// Plies to capture for cop-to-move positions `rank * n + robber`; `UNKNOWN` = escapes.
    cop_turn: Vec<u32>,
    /// The same for robber-to-move positions.
    robber_turn: Vec<u32>,
}

impl CopsGame {
    /// Solves the game with `cops` cops on `graph` (any graph: disconnected ones included).
    ///
    /// # Errors
    /// [`CopsError::TooManyStates`] if the table would exceed `options.max_states` positions.
    pub fn solve(graph: &Graph, cops: usize, options: &CopOptions) -> Result<CopsGame, CopsError> {
        let n = graph.node_count();
        let sets = Multisets::new(n, cops, options.max_states)?;
        let states = (sets.len() as u64)
            .saturating_mul(n as u64)
            .saturating_mul(2);
        if states > options.max_states || sets.len() > u32::MAX as usize {
            return Err(CopsError::TooManyStates {
                cops,
                states,
                limit: options.max_states,
            });
        }
        let closed: Vec<Vec<u32>> = (0..n)
            .map(|v| {
                let mut list: Vec<u32> = graph.neighbors(v).iter().map(|&w| w as u32).collect();
                list.push(v as u32);
                list.sort_unstable();
                list
            })
            .collect();
        let mut game = CopsGame {
            graph: graph.clone(),
            cops,
            closed,
            sets,
            cop_turn: vec![UNKNOWN; states as usize / 2],
            robber_turn: vec![UNKNOWN; states as usize / 2],
        };
        game.retrograde();
        Ok(game)
    }

    fn retrograde(&mut self) {
        let n = self.graph.node_count();
        // Robber-to-move positions still needing this many of the robber's options to be lost.
        let mut pending: Vec<u32> = (0..self.cop_turn.len())
            .map(|s| self.closed[s % n].len() as u32)
            .collect();
        let mut queue: VecDeque<(usize, Turn)> = VecDeque::new();
        for rank in 0..self.sets.len() {
            let mut previous = None;
            for &c in self.sets.get(rank) {
                if previous == Some(c) {
                    continue;
                }
                previous = Some(c);
                let s = rank * n + c as usize;
                self.cop_turn[s] = 0;
                self.robber_turn[s] = 0;
                queue.push_back((s, Turn::Cops));
                queue.push_back((s, Turn::Robber));
            }
        }
        // Successor placements of each cop placement, computed once when they fit the budget.
        let widest = self.closed.iter().map(Vec::len).max().unwrap_or(1) as u64;
        let product = widest.saturating_pow(self.cops as u32);
        let cache = ((self.sets.len() as u64).saturating_mul(product) <= MOVE_CACHE_LIMIT)
            .then(|| MoveCache::new(&self.closed, &self.sets));
        let mut scratch = Vec::new();
        while let Some((s, turn)) = queue.pop_front() {
            let (rank, robber) = (s / n, s % n);
            match turn {
                Turn::Cops => {
                    // Lost for the robber: every robber position that could step here loses one option.
                    let depth = self.cop_turn[s] + 1;
                    for &from in &self.closed[robber] {
                        let p = rank * n + from as usize;
                        if self.robber_turn[p] == UNKNOWN {
                            pending[p] -= 1;
                            if pending[p] == 0 {
                                self.robber_turn[p] = depth;
                                queue.push_back((p, Turn::Robber));
                            }
                        }
                    }
                }
                Turn::Robber => {
                    // Won for the cops: every cop placement that can move here wins, one ply
                    // later (moves are symmetric, so predecessors are successors).
                    let depth = self.robber_turn[s] + 1;
                    let from: &[u32] = match &cache {
                        Some(cache) => cache.get(rank),
                        None => {
                            successor_ranks(&self.closed, &self.sets, rank, &mut scratch);
                            &scratch
                        }
                    };
                    for &m in from {
                        let p = m as usize * n + robber;
                        if self.cop_turn[p] == UNKNOWN {
                            self.cop_turn[p] = depth;
                            queue.push_back((p, Turn::Cops));
                        }
                    }
                }
            }
        }
    }

    /// The graph the game is played on.
    pub fn graph(&self) -> &Graph {
        &self.graph
    }

    /// The number of cops.
    pub fn cops(&self) -> usize {
        self.cops
    }

    /// Positions in the solved table (both turns).
    pub fn state_count(&self) -> usize {
        self.cop_turn.len() + self.robber_turn.len()
    }

    /// Positions from which the cops force capture (both turns).
    pub fn cop_winning_states(&self) -> usize {
        self.cop_turn
            .iter()
            .chain(&self.robber_turn)
            .filter(|&&d| d != UNKNOWN)
            .count()
    }

    /// Whether the cops, placing first, can force capture.
    pub fn cops_win(&self) -> bool {
        self.placement_value(self.best_placement_rank()).is_some()
    }

    /// Cop moves (rounds) until capture from the cops' best placement under optimal play, or
    /// `None` if the robber escapes.
    pub fn capture_time(&self) -> Option<u32> {
        self.placement_value(self.best_placement_rank())
            .map(|plies| plies.div_ceil(2))
    }

    /// The value of a position.
    ///
    /// # Errors
    /// [`CopsError::InvalidPosition`] if a vertex is out of range or the cop count is wrong.
    pub fn outcome(
        &self,
        cops: &[NodeId],
        robber: NodeId,
        turn: Turn,
    ) -> Result<Outcome, CopsError> {
        let s = self.state(cops, robber)?;
        let depth = match turn {
            Turn::Cops => self.cop_turn[s],
            Turn::Robber => self.robber_turn[s],
        };
        Ok(if depth == UNKNOWN {
            Outcome::RobberEscapes
        } else {
            Outcome::CopsWin { plies: depth }
        })
    }

    /// The cops' best placement (sorted): one that forces the quickest capture, or, when the
    /// cops cannot win, one that leaves the robber the fewest safe vertices.
    pub fn cop_placement(&self) -> Vec<NodeId> {
        if self.sets.len() == 0 {
            return Vec::new();
        }
        self.sets
            .get(self.best_placement_rank())
            .iter()
            .map(|&c| c as NodeId)
            .collect()
    }

    /// The robber's best placement against the given cops: a vertex from which he escapes
    /// forever if there is one (the one farthest from the nearest cop), otherwise the one that
    /// delays capture longest.
    ///
    /// # Errors
    /// [`CopsError::InvalidPosition`] for a wrong cop count or vertex; [`CopsError::EmptyGraph`]
    /// if there is nowhere to stand.
    pub fn robber_placement(&self, cops: &[NodeId]) -> Result<NodeId, CopsError> {
        let n = self.graph.node_count();
        if n == 0 {
            return Err(CopsError::EmptyGraph);
        }
        let rank = self.rank_of(cops)?;
        let distance = self.distance_to_cops(cops);
        (0..n)
            .max_by_key(|&r| {
                (
                    self.robber_preference(self.cop_turn[rank * n + r]),
                    distance[r],
                    std::cmp::Reverse(r),
                )
            })
            .ok_or(CopsError::EmptyGraph)
    }

    /// The cops' move: new positions, in the same order as `cops` (each cop steps along an edge
    /// or stays). From a winning position it captures as fast as possible; from a losing one
    /// the cops close in on the robber (least total distance), which he can still evade.
    ///
    /// # Errors
    /// [`CopsError::InvalidPosition`] for a bad position, [`CopsError::AlreadyCaptured`] if a
    /// cop already stands on the robber.
    pub fn cop_move(&self, cops: &[NodeId], robber: NodeId) -> Result<Vec<NodeId>, CopsError> {
        let s = self.state(cops, robber)?;
        if self.cop_turn[s] == 0 {
            return Err(CopsError::AlreadyCaptured);
        }
        let n = self.graph.node_count();
        let distance = self.graph.distances_from(robber);
        let far = n + 1;
        let k = self.cops;
        let mut digits = vec![0usize; k];
        let mut tuple = vec![0u32; k];
        let mut sorted = vec![0u32; k];
        let mut best: Option<((u32, usize), Vec<u32>)> = None;
        'product: loop {
            for i in 0..k {
                tuple[i] = self.closed[cops[i]][digits[i]];
            }
            sorted.copy_from_slice(&tuple);
            sorted.sort_unstable();
            let depth = self.robber_turn[self.sets.rank(&sorted) * n + robber];
            let closeness: usize = tuple
                .iter()
                .map(|&c| distance[c as usize].unwrap_or(far))
                .sum();
            let key = (depth, closeness);
            if best.as_ref().is_none_or(|(b, _)| key < *b) {
                best = Some((key, tuple.clone()));
            }
            for i in 0..k {
                digits[i] += 1;
                if digits[i] < self.closed[cops[i]].len() {
                    continue 'product;
                }
                digits[i] = 0;
            }
            break;
        }
        let (_, chosen) = best.ok_or(CopsError::AlreadyCaptured)?;
        Ok(chosen.into_iter().map(|c| c as NodeId).collect())
    }

    /// The robber's move (his new vertex): to a position from which he escapes forever if one
    /// exists (keeping as far from the cops as possible), otherwise the one delaying capture
    /// longest.
    ///
    /// # Errors
    /// As for [`CopsGame::cop_move`].
    pub fn robber_move(&self, cops: &[NodeId], robber: NodeId) -> Result<NodeId, CopsError> {
        let s = self.state(cops, robber)?;
        if self.robber_turn[s] == 0 {
            return Err(CopsError::AlreadyCaptured);
        }
        let n = self.graph.node_count();
        let rank = s / n;
        let distance = self.distance_to_cops(cops);
        self.closed[robber]
            .iter()
            .map(|&r| r as usize)
            .max_by_key(|&r| {
                (
                    self.robber_preference(self.cop_turn[rank * n + r]),
                    distance[r],
                    std::cmp::Reverse(r),
                )
            })
            .ok_or(CopsError::AlreadyCaptured)
    }

    /// Larger is better for the robber: escaping beats everything, then longer survival.
    fn robber_preference(&self, depth: u32) -> u64 {
        if depth == UNKNOWN {
            u64::MAX
        } else {
            u64::from(depth)
        }
    }

    /// For each vertex, the distance to the nearest cop (`usize::MAX` if unreachable).
    fn distance_to_cops(&self, cops: &[NodeId]) -> Vec<usize> {
        let mut best = vec![usize::MAX; self.graph.node_count()];
        for &c in cops {
            for (v, d) in self.graph.distances_from(c).into_iter().enumerate() {
                if let Some(d) = d {
                    best[v] = best[v].min(d);
                }
            }
        }
        best
    }

    /// Worst-case plies to capture after placing cops at `rank`, or `None` if some robber
    /// vertex escapes.
    fn placement_value(&self, rank: usize) -> Option<u32> {
        let n = self.graph.node_count();
        if self.sets.len() == 0 {
            return None;
        }
        let row = &self.cop_turn[rank * n..rank * n + n];
        if row.contains(&UNKNOWN) {
            None
        } else {
            Some(row.iter().copied().max().unwrap_or(0))
        }
    }

    fn best_placement_rank(&self) -> usize {
        let n = self.graph.node_count();
        (0..self.sets.len())
            .min_by_key(|&rank| {
                let row = &self.cop_turn[rank * n..rank * n + n];
                let escapes = row.iter().filter(|&&d| d == UNKNOWN).count();
                let worst = row.iter().copied().filter(|&d| d != UNKNOWN).max();
                (escapes, worst.unwrap_or(0))
            })
            .unwrap_or(0)
    }

    fn rank_of(&self, cops: &[NodeId]) -> Result<usize, CopsError> {
        let n = self.graph.node_count();
        if cops.len() != self.cops {
            return Err(CopsError::InvalidPosition(format!(
                "{} cop positions given, the game has {} cops",
                cops.len(),
                self.cops
            )));
        }
        let mut sorted = Vec::with_capacity(cops.len());
        for &c in cops {
            if c >= n {
                return Err(CopsError::InvalidPosition(format!(
                    "cop vertex {c} is not in the graph (0..{n})"
                )));
            }
            sorted.push(c as u32);
        }
        sorted.sort_unstable();
        Ok(self.sets.rank(&sorted))
    }

    fn state(&self, cops: &[NodeId], robber: NodeId) -> Result<usize, CopsError> {
        let n = self.graph.node_count();
        if robber >= n {
            return Err(CopsError::InvalidPosition(format!(
                "robber vertex {robber} is not in the graph (0..{n})"
            )));
        }
        Ok(self.rank_of(cops)? * n + robber)
    }
}
