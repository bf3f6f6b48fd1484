//! The hunt for the high-value target: the pursuit–evasion game of
//! [`vitro_algo::pursuit`] played on the town's walk graph, turn by turn, in the simulator.
//!
//! The lead pursuer keeps the team's information set about the target (a [`Belief`] over
//! walk-graph nodes): every turn it spreads the belief one step, then applies what the team
//! saw since the last turn (a sighting — its own or a contact report — collapses it; no
//! sighting removes every node the pursuers see). It then runs the configured search
//! (`[pursuit] lead`): a determinized one of [`vitro_algo::pursuit`] (IS-MCTS or minimax
//! over sampled determinizations, a scripted ε-greedy evader inside; the default), or a game
//! search of [`vitro_algo::pursuit::game`] (MO-ISMCTS, with the evader's decisions in its own
//! tree, or worst-case minimax over the team's information sets); an iteration budget, charged as
//! simulated thinking time) and orders each pursuer to its next node.
//!
//! Measured over 100 seeds per point (`experiments/mission_hunt.toml`), the game searches
//! catch this target less often than the determinized ones (MCTS at 3,000 iterations:
//! 0.63 against 0.87): they play against an evader that sees the pursuers, which the target
//! is not, so they guard against escapes it never tries.
//!
//! The game searches fit the mission's turn order as it is: a lead turn is the game's pursuer move,
//! taken after the target's moves since the last turn have been predicted and observed; the
//! board is the game's [`Board`] itself. The mission has no episode length, so each search
//! sees `[pursuit] horizon` rounds left.
//! The target evades with the older searches of [`vitro_algo::pursuit`] ([`Search`], in
//! [`super::red::Hvt`]): the game's evaders are omniscient (they see the pursuers and their
//! information set), which the target, knowing only its own camera, is not.

use crate::brief::{BLUE, Brief};
use crate::radio::{Evac, Radio};
use crate::scenario::{PursuitAlgorithm, PursuitLead, PursuitSpec};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::comm::{Address, Outgoing};
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::event::OwnEventId;
use vitro::sim::Context;
use vitro::time::{SimDuration, SimTime};
use vitro_algo::pursuit::game::{
    MoIsmcts, MoIsmctsConfig, TeamStrategy, TeamView, WorstCaseMinimax, WorstCaseMinimaxConfig,
};
use vitro_algo::pursuit::{
    Belief, Budget, EvaderStrategy, EvaderView, Mcts, MctsConfig, Minimax, MinimaxConfig,
    PursuerStrategy, PursuerView,
};
use vitro_behaviour::belief::Whereabouts;
use vitro_site::map::Mode;
use vitro_tactical::arena::OwnPose;

/// `Radio::Signal(SEARCH, "x y")`: the hunt lead's most likely place of the target (world
/// metres), sent to the blue group every turn.
pub const SEARCH: &str = "search";

/// How many of the lead's longest turns (two mean moves each, see the trooper's turn
/// fallback) a pursuer waits for a move from its hunt lead before it reports the lead
/// silent: one lost order or one long move is no silence.
pub const LEAD_SILENT_TURNS: f64 = 3.0;

/// `Radio::Signal(SILENT, id)`: pursuer → truck, hunt lead `id` has sent no move for
/// [`LEAD_SILENT_TURNS`] long turns.
pub const SILENT: &str = "silent";

/// The pursuit board shared by the hunters and the hunted: the walk graph with
/// line-of-sight visibility between its nodes.
pub type Board = vitro_algo::pursuit::Arena;

/// The hunt lead's search: one of the determinized searches (`lead = "determinized"`) or
/// one of the two game searches of [`vitro_algo::pursuit::game`] (`lead = "game"`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Lead {
    /// IS-MCTS or minimax over determinizations, a scripted evader inside.
    Determinized(Search),
    /// Multiple-observer information-set MCTS (`algorithm = "mcts"`).
    Mcts(MoIsmcts),
    /// Worst-case minimax over the team's information sets (`algorithm = "minimax"`).
    Minimax(WorstCaseMinimax),
}

impl Lead {
    /// The search `spec` asks for: `budget` iterations (MO-ISMCTS) or node expansions
    /// (minimax) per turn, MO-ISMCTS playing out `horizon` rounds. No time limit, so the
    /// choice depends on the seed alone.
    pub fn new(spec: &PursuitSpec) -> Lead {
        if spec.lead == PursuitLead::Determinized {
            return Lead::Determinized(Search::new(spec));
        }
        let budget = Budget::iterations(u64::from(spec.budget.max(1)));
        match spec.algorithm {
            PursuitAlgorithm::Mcts => Lead::Mcts(MoIsmcts::new(MoIsmctsConfig {
                budget,
                horizon: spec.horizon.max(1),
                ..MoIsmctsConfig::default()
            })),
            PursuitAlgorithm::Minimax => {
                Lead::Minimax(WorstCaseMinimax::new(WorstCaseMinimaxConfig {
                    budget,
                    ..WorstCaseMinimaxConfig::default()
                }))
            }
        }
    }
    /// The pursuers' joint move: each pursuer's next node, in the order of `view.positions`
    /// (`turn`: the lead's turns so far, for the determinized searches).
    pub fn pursue(
        &mut self,
        view: &TeamView<'_>,
        turn: u32,
        rng: &mut rand_chacha::ChaCha8Rng,
    ) -> Vec<usize> {
        match self {
            Lead::Determinized(search) => {
                let view = PursuerView {
                    arena: view.arena,
                    positions: view.positions,
                    belief: view.belief,
                    turn,
                };
                match search {
                    Search::Mcts(s) => PursuerStrategy::choose(s, &view, rng),
                    Search::Minimax(s) => PursuerStrategy::choose(s, &view, rng),
                }
            }
            Lead::Mcts(s) => TeamStrategy::choose(s, view, rng),
            Lead::Minimax(s) => TeamStrategy::choose(s, view, rng),
        }
    }
    /// Its name.
    pub fn name(&self) -> &'static str {
        match self {
            Lead::Determinized(s) => s.name(),
            Lead::Mcts(_) => "MO-ISMCTS",
            Lead::Minimax(_) => "worst-case minimax",
        }
    }
}

/// One of the two older searches (determinized, scripted opponent), used by the target.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Search {
    /// Information-set Monte-Carlo tree search.
    Mcts(Mcts),
    /// Iterative-deepening minimax over sampled determinizations.
    Minimax(Minimax),
}

impl Search {
    /// The search `spec` asks for, with its iteration budget.
    pub fn new(spec: &PursuitSpec) -> Search {
        let budget = Budget::iterations(u64::from(spec.budget.max(1)));
        match spec.algorithm {
            PursuitAlgorithm::Mcts => Search::Mcts(Mcts::new(MctsConfig {
                budget,
                horizon: spec.horizon.max(1),
                ..MctsConfig::default()
            })),
            PursuitAlgorithm::Minimax => Search::Minimax(Minimax::new(MinimaxConfig {
                budget,
                ..MinimaxConfig::default()
            })),
        }
    }
    /// The evader's move.
    pub fn evade(&mut self, view: &EvaderView<'_>, rng: &mut rand_chacha::ChaCha8Rng) -> usize {
        match self {
            Search::Mcts(s) => EvaderStrategy::choose(s, view, rng),
            Search::Minimax(s) => EvaderStrategy::choose(s, view, rng),
        }
    }
    /// Its name.
    pub fn name(&self) -> &'static str {
        match self {
            Search::Mcts(_) => "MCTS",
            Search::Minimax(_) => "minimax",
        }
    }
}

/// The turn timer of a player of the hunt (the lead pursuer or the HVT): one pending turn
/// at a time. A turn starts when the player's move ends (no sooner than [`MIN_TURN`] after
/// the previous one began) or, failing an arrival, after a long fallback delay; whichever
/// comes first replaces the other.
#[derive(Debug, Default, Serialize, Deserialize)]
pub struct TurnClock {
    pending: Option<OwnEventId>,
    began: SimTime,
}

impl TurnClock {
    /// A turn begins now.
    pub fn begin(&mut self, cx: &Context<'_, Evac>) {
        self.pending = None;
        self.began = cx.now();
    }
    /// The next turn in `delay` (timer `key`), replacing the one pending.
    pub fn next_in(&mut self, delay: SimDuration, key: u64, cx: &mut Context<'_, Evac>) {
        if let Some(id) = self.pending.take() {
            cx.cancel(id);
        }
        self.pending = Some(cx.set_timer(delay, key));
    }
    /// The next turn after the move just ended: [`MIN_TURN`] after this one began at the
    /// earliest.
    pub fn after_move(&mut self, key: u64, cx: &mut Context<'_, Evac>) {
        let wait = MIN_TURN.saturating_sub(cx.now().saturating_since(self.began));
        self.next_in(wait, key, cx);
    }
}

/// Shortest time between two turns of a hunt player (a move along a short street still
/// takes this long).
pub const MIN_TURN: SimDuration = SimDuration::from_secs(10);

/// What the lead does after a turn's bookkeeping.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum HuntStep {
    /// The search ran; send the orders after this much thinking time.
    Think(SimDuration),
    /// Nothing to do (no board, or the hunt is over).
    Over,
}

/// The lead pursuer's state.
#[derive(Debug, Serialize, Deserialize)]
pub struct Hunt {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<Brief>,
    /// Who is hunted.
    pub target: EntityId,
    team: Vec<EntityId>,
    belief: Option<Belief>,
    seen: Option<[f64; 3]>,
    search: Lead,
    orders: Vec<(EntityId, NodeId)>,
    /// Turns played.
    pub turns: u32,
    /// Set when the target was captured.
    pub over: bool,
    /// When the target was last seen.
    pub last_seen: Option<SimTime>,
}

impl Hunt {
    /// A hunt of `target` by `team` (the lead first).
    pub fn new(brief: Arc<Brief>, target: EntityId, team: Vec<EntityId>) -> Option<Hunt> {
        let search = Lead::new(&brief.pursuit);
        brief.board.as_ref()?;
        Some(Hunt {
            brief,
            target,
            team,
            belief: None,
            seen: None,
            search,
            orders: Vec::new(),
            turns: 0,
            over: false,
            last_seen: None,
        })
    }

    /// The pursuers from now on (the lead first): the belief stays.
    pub fn set_team(&mut self, team: Vec<EntityId>) {
        self.team = team;
    }

    /// Notes a sighting of the target (own or reported).
    pub fn observe(&mut self, now: SimTime, pos: [f64; 3]) {
        self.seen = Some(pos);
        self.last_seen = Some(now);
    }

    /// One turn: update the belief, run the search, keep the orders. The team is where
    /// `known` (the lead's position reports and sightings) puts them; a pursuer not heard
    /// from lately is left out of the turn.
    pub fn turn(&mut self, cx: &mut Context<'_, Evac>, known: &Whereabouts) -> HuntStep {
        let Some(board) = self.brief.board.clone() else {
            return HuntStep::Over;
        };
        if self.over {
            return HuntStep::Over;
        }
        let index = |n: NodeId| n.0 as usize;
        let mut team = Vec::new();
        let mut at = Vec::new();
        let (me, now) = (cx.me(), cx.now());
        for &id in &self.team {
            let pos = if id == me {
                cx.sense(&OwnPose).map(|p| p.pos)
            } else {
                known.estimate(id, now)
            };
            if let Some(n) = pos.and_then(|p| self.brief.walk_node(p)) {
                team.push(id);
                at.push(index(n));
            }
        }
        if at.is_empty() {
            return HuntStep::Over;
        }
        let n = board.node_count();
        let belief = self.belief.get_or_insert_with(|| Belief::uniform(n));
        belief.predict(&board);
        match self.seen.take().and_then(|p| self.brief.walk_node(p)) {
            Some(v) => belief.collapse(index(v)),
            None => belief.exclude_seen_by(&board, &at),
        }
        if belief.size() == 0 {
            *belief = Belief::uniform(n);
        }
        // Where the team should look: the most likely place, to every blue unit (the
        // aircraft free of the convoy search there).
        let likely = belief
            .most_likely()
            .and_then(|v| self.brief.node_point(Mode::Walk, NodeId(v as u32)));
        if let Some(p) = likely {
            let body = Radio::Signal(SEARCH.into(), format!("{:.1} {:.1}", p[0], p[1]));
            cx.send(Outgoing::new(Address::Group(BLUE), body));
        }
        let view = TeamView {
            arena: &board,
            positions: &at,
            belief,
            rounds_left: self.brief.pursuit.horizon.max(1),
        };
        let moves = self.search.pursue(&view, self.turns, cx.rng("hunt"));
        self.turns += 1;
        self.orders = team
            .into_iter()
            .zip(moves)
            .map(|(id, v)| (id, NodeId(v as u32)))
            .collect();
        let us = self.brief.pursuit.think_us_per_iteration * f64::from(self.brief.pursuit.budget);
        HuntStep::Think(SimDuration::from_secs_f64(us * 1e-6))
    }

    /// The orders of the last turn: each pursuer's next node.
    pub fn orders(&self) -> Vec<(EntityId, NodeId)> {
        self.orders.clone()
    }

    /// One line about the hunt.
    pub fn describe(&self) -> String {
        let size = self.belief.as_ref().map_or(0, |b| b.size());
        format!(
            "lead the HVT hunt ({}, turn {}, target in {} places)",
            self.search.name(),
            self.turns,
            size
        )
    }

    /// The team's belief about the target: each possible walk node with its probability.
    pub fn belief(&self) -> Vec<([f64; 3], f64)> {
        let Some(b) = &self.belief else {
            return Vec::new();
        };
        b.members()
            .filter_map(|v| {
                let p = self.brief.node_point(Mode::Walk, NodeId(v as u32))?;
                Some((p, b.prob(v)))
            })
            .collect()
    }

    /// The hunt's plan: where the belief puts the target most likely.
    pub fn plan(&self) -> Vec<String> {
        let best = self.belief.as_ref().and_then(|b| b.most_likely());
        best.map(|v| vec![format!("target most likely at node {v}")])
            .unwrap_or_default()
    }
}
