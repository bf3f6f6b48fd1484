//! What solving a patrolling game is asked for and what it returns: options, the solution
//! with its statistics, and why a game could not be solved.

use super::local::LpStats;
use super::lp::LpBackend;
use super::policy::Policy;
use crate::graph::NodeId;
use serde::Serialize;

/// Settings for [`solve_with`](crate::patrol::solve_with).
#[derive(Clone, Debug, PartialEq)]
pub struct SolveOptions {
    /// Absolute optimality tolerance on the value (in units of target value). Default 1e-5.
    pub tolerance: f64,
    /// Branch-and-bound box budget. A box costs at most one small LP (tenths of a
    /// millisecond), so the default 20 000 bounds the search to seconds; the tested instances
    /// (up to 5 vertices) certify within a few thousand boxes, symmetric ones (every vertex of
    /// a 4-cycle a target) need several hundred thousand.
    pub max_nodes: u64,
    /// The most connected supports to consider; beyond it only whole components are tried and
    /// the result is not certified. Default 4096.
    pub max_supports: usize,
    /// Supports optimised locally (by successive LP) before the branch and bound. Default 16.
    pub local_searches: usize,
    /// LP iterations per local search. Default 100.
    pub local_iterations: usize,
    /// Optimise time-dependent policies (one transition matrix per phase of the schedules'
    /// period) instead of stationary ones. Default false.
    pub time_dependent: bool,
    /// Random restarts of each team local search (several patrollers), besides the uniform
    /// start. Default 2.
    pub restarts: usize,
    /// Seed of the restarts' random starting policies. Default 0.
    pub seed: u64,
    /// Also search phase-locked time-dependent policies (implies
    /// [`SolveOptions::time_dependent`]): patrollers that are only at some vertices at some
    /// phases, e.g. keeping near the convoys they guard, and are attacked only there (see the
    /// [module docs](crate::patrol)). Found by local search on tubes, never certified. Default false.
    pub phase_locked: bool,
    /// With [`SolveOptions::phase_locked`] and a single patroller, also solve the full-phase
    /// time-dependent class (certified by branch and bound) and keep the better policy.
    /// Default true; false skips that stage, which is the slower one on instances where no
    /// full-phase policy can guard the convoys anyway (long timetables on a route).
    pub full_phase_candidate: bool,
    /// The LP solver of every linear program solved. Default [`LpBackend::default`].
    pub lp: LpBackend,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            tolerance: 1e-5,
            max_nodes: 20_000,
            max_supports: 4096,
            local_searches: 16,
            local_iterations: 100,
            time_dependent: false,
            restarts: 2,
            seed: 0,
            phase_locked: false,
            full_phase_candidate: true,
            lp: LpBackend::default(),
        }
    }
}

/// Work done by [`solve_with`](crate::patrol::solve_with).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct SolveStats {
    /// Connected supports enumerated (candidate support assignments for a team).
    pub supports: usize,
    /// Supports the branch and bound had to search (the rest were ruled out at once).
    pub supports_searched: usize,
    /// Local searches run.
    pub local_searches: usize,
    /// LP work of the local searches.
    pub lp: LpStats,
    /// LP work of the branch and bound (one relaxation per box the interval bound cannot
    /// prune).
    pub bnb_lp: LpStats,
    /// Branch-and-bound boxes evaluated.
    pub nodes: u64,
}

/// An optimal (or best found) patrolling policy.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Solution {
    /// The policy's value: the attacker's best expected gain against it (lower is better).
    pub value: f64,
    /// A certified lower bound on the value of every policy of the optimised class (0 when
    /// nothing better is known, as for teams).
    pub lower_bound: f64,
    /// Whether `value − lower_bound ≤ tolerance` over all supports (the policy is optimal up
    /// to the tolerance).
    pub exact: bool,
    /// The smallest capture probability over all attack options.
    pub capture_probability: f64,
    /// One policy per patroller (each restricted to one recurrent class for a single
    /// patroller).
    pub policies: Vec<Policy>,
    /// Per target and phase, the worst start for the attacker and the outcome there.
    pub threats: Vec<Threat>,
    /// Work done.
    pub stats: SolveStats,
}

/// The worst start for one target and phase against a team.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Threat {
    /// Index of the target in [`Instance::targets`](crate::patrol::Instance::targets).
    pub target: usize,
    /// The phase of the schedule period when the attack starts.
    pub phase: usize,
    /// Each patroller's vertex at the worst joint start.
    pub from: Vec<NodeId>,
    /// Probability that some patroller stands on the target during the attack.
    pub capture_probability: f64,
    /// The attacker's expected gain: the target's value times the escape probability.
    pub expected_loss: f64,
}
