//! Solving a patrol game: its plan, capture table and occupancy, and the plans this process
//! solved already.

use super::board::targets;
use super::steps::{CaptureTable, capture_table};
use std::sync::Mutex;
use vitro_algo::graph::{Graph, NodeId};
use vitro_algo::patrol::{PatrolPlan, PlanParams, Target};
use vitro_site::geo::P2;

/// Periods of the timetable the occupancy iteration runs before it averages (burn-in), and
/// then averages over.
const OCCUPANCY_PERIODS: usize = 64;

/// What a game is solved with, besides its timetable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Spec {
    /// Steps the second target runs ahead of the convoy (0: the convoy alone).
    pub ahead: usize,
    /// Steps an attack takes.
    pub attack_steps: u32,
    /// Plan units (Skeldars).
    pub units: usize,
    /// LP iterations per local search.
    pub iterations: usize,
    /// The solver's seed.
    pub seed: u64,
}

/// The parts of a game that do not depend on its timetable.
pub(super) struct Frame {
    /// The checkpoints, world points on the ground.
    pub points: Vec<[f64; 3]>,
    /// The patrol graph.
    pub graph: Graph,
    /// Seconds per step.
    pub step_s: f64,
    /// The longest edge, metres.
    pub reach_m: f64,
    /// The route's nodes, town metres.
    pub route: Vec<P2>,
    /// Distance along the route at each route node, metres.
    pub along: Vec<f64>,
}

/// A solved game: what [`solve_game`] gives.
pub(super) struct Solved {
    /// The plan.
    pub plan: PatrolPlan,
    /// The game's targets.
    pub targets: Vec<Target>,
    /// Per unit, target and phase: the capture probability from each state.
    pub capture: CaptureTable,
    /// Per unit, per phase: where the unit is in the long run.
    pub occupancy: Vec<Vec<Vec<(NodeId, f64)>>>,
    /// The least capture probability over the attacks that start during the trip.
    pub trip_capture_probability: f64,
}

/// Solves the game of the convoy's `trip` (its vertex at each of `steps` steps) on `graph`.
pub(super) fn solve_game(
    graph: Graph,
    trip: &[NodeId],
    steps: usize,
    spec: Spec,
) -> Result<Solved, String> {
    let targets = targets(&graph, trip, spec.ahead, spec.attack_steps)?;
    let plan = solve(
        graph,
        targets.clone(),
        spec.units,
        spec.iterations,
        spec.seed,
    )?;
    let capture = capture_table(&plan, &targets)?;
    let trip_capture_probability = plan
        .threats
        .iter()
        .filter(|t| t.phase < steps)
        .map(|t| t.capture_probability)
        .fold(1.0, f64::min);
    let occupancy = (0..plan.units())
        .map(|u| occupancy(&plan, u))
        .collect::<Result<_, _>>()?;
    Ok(Solved {
        plan,
        targets,
        capture,
        occupancy,
        trip_capture_probability,
    })
}

/// What a game is solved from.
#[derive(Clone, Debug, PartialEq)]
struct GameKey {
    graph: Graph,
    targets: Vec<Target>,
    units: usize,
    iterations: usize,
    seed: u64,
}

/// Plans solved in this process, most recent last: the runs of a batch share their games.
static SOLVED: Mutex<Vec<(GameKey, PatrolPlan)>> = Mutex::new(Vec::new());
/// Most plans kept in [`SOLVED`].
const SOLVED_KEPT: usize = 8;

/// Solves the game of `targets` on `graph` for `units` units with `iterations` LP
/// iterations per local search, no restarts and no full-phase candidate, or returns the plan
/// this process already solved for the same game (the solver is deterministic: the same
/// plan).
fn solve(
    graph: Graph,
    targets: Vec<Target>,
    units: usize,
    iterations: usize,
    seed: u64,
) -> Result<PatrolPlan, String> {
    let key = GameKey {
        graph,
        targets,
        units,
        iterations,
        seed,
    };
    if let Ok(solved) = SOLVED.lock()
        && let Some((_, plan)) = solved.iter().find(|(k, _)| *k == key)
    {
        return Ok(plan.clone());
    }
    let params = PlanParams {
        phase_locked: true,
        iterations,
        restarts: 0,
        seed,
        full_phase_candidate: false,
        ..PlanParams::default()
    };
    let plan =
        PatrolPlan::solve(&key.graph, &key.targets, units, &params).map_err(|e| e.to_string())?;
    if let Ok(mut solved) = SOLVED.lock() {
        if solved.len() >= SOLVED_KEPT {
            solved.remove(0);
        }
        solved.push((key, plan.clone()));
    }
    Ok(plan)
}

/// Where `unit` is in the long run at each phase of its policy: the distribution over its
/// states, propagated through the timetable from an even start, then averaged over
/// [`OCCUPANCY_PERIODS`] periods after as many of burn-in.
fn occupancy(plan: &PatrolPlan, unit: usize) -> Result<Vec<Vec<(NodeId, f64)>>, String> {
    let n = plan.graph.node_count();
    let period = plan.period.max(1);
    let policy = plan.policies.get(unit).ok_or("no such unit")?;
    let start = plan.vertices_at(unit, 0).map_err(|e| e.to_string())?;
    let mut d = vec![0.0; n];
    for &v in &start {
        d[v] = 1.0 / start.len() as f64;
    }
    let mut sum = vec![vec![0.0; n]; period];
    for round in 0..2 * OCCUPANCY_PERIODS {
        for (phase, acc) in sum.iter_mut().enumerate() {
            if round >= OCCUPANCY_PERIODS {
                for (a, x) in acc.iter_mut().zip(&d) {
                    *a += x;
                }
            }
            let mut next = vec![0.0; n];
            for (v, &p) in d.iter().enumerate() {
                if p > 0.0
                    && let Some(moves) = policy.moves_at(v, phase)
                {
                    for &(w, q) in moves {
                        next[w] += p * q;
                    }
                }
            }
            d = next;
        }
    }
    Ok(sum
        .into_iter()
        .map(|acc| {
            let total: f64 = acc.iter().sum();
            acc.into_iter()
                .enumerate()
                .filter(|&(_, x)| x > 1e-9 * total.max(1e-300))
                .map(|(v, x)| (v, x / total))
                .collect()
        })
        .collect())
}
