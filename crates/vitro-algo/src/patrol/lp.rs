//! The LP backends of good_lp the patrol solvers can use, behind one call.
//!
//! Both are pure Rust: [`LpBackend::Microlp`], the default (a dense simplex: vertex
//! solutions, can hit a singular basis on degenerate programs), and [`LpBackend::Clarabel`]
//! (an interior-point conic solver: solutions inside the optimal face, to its tolerance of
//! about 1e-8). HiGHS (good_lp's `highs` feature) needs cmake and a C++ build; it
//! is not offered. Example `lp_backends` measures both on the village and convoy instances
//! (release build, one core of the shared 2-core machine): on the convoy game both certify
//! the same optima in milliseconds; on the village game (phase-locked team local search, no
//! restarts) Clarabel reaches a loss of 0.500 in 20 LP iterations per search (86 s, 60 LPs,
//! no failure) where microlp stops at 0.599 (40 s, 42 LPs, one failed solve), and 0.878
//! against 0.999 in 5 iterations (20 s each) — a better step per LP at about 1.5 times the
//! time per LP. Microlp is the default all the same: with Clarabel the branch and bound does
//! not certify one of the small test instances (`exact_solutions_match_a_brute_force_grid`)
//! within its box budget — its relaxation bounds, good to Clarabel's tolerance only, prune
//! less — and the debug test suite runs longer. Ask for Clarabel
//! ([`SolveOptions::lp`](super::SolveOptions::lp), [`PlanParams::lp`](super::PlanParams::lp))
//! for large local searches.

use good_lp::{Constraint, ProblemVariables, Solution, SolverModel, Variable};
use serde::Serialize;

use super::PatrolError;

/// Which LP solver the patrol solvers call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
pub enum LpBackend {
    /// good_lp's `microlp` (dense simplex).
    #[default]
    Microlp,
    /// good_lp's `clarabel` (interior point).
    Clarabel,
}

impl LpBackend {
    /// Every backend, default first.
    pub const ALL: [LpBackend; 2] = [LpBackend::Microlp, LpBackend::Clarabel];

    /// Its name (`"microlp"`, `"clarabel"`).
    pub fn name(self) -> &'static str {
        match self {
            LpBackend::Microlp => "microlp",
            LpBackend::Clarabel => "clarabel",
        }
    }
}

/// Minimises `objective` over `vars` subject to `rows` with `backend`: the solution, whose
/// [`Solution::value`] reads any variable of `vars`.
///
/// # Errors
/// [`PatrolError::Lp`] if the solver reports no optimum.
pub(crate) fn minimise(
    vars: ProblemVariables,
    objective: Variable,
    rows: Vec<Constraint>,
    backend: LpBackend,
) -> Result<Box<dyn Solution>, PatrolError> {
    let lp = |e: good_lp::ResolutionError| PatrolError::Lp(e.to_string());
    let problem = vars.minimise(objective);
    Ok(match backend {
        LpBackend::Microlp => Box::new(
            problem
                .using(good_lp::microlp)
                .with_all(rows)
                .solve()
                .map_err(lp)?,
        ),
        LpBackend::Clarabel => Box::new(
            problem
                .using(good_lp::clarabel)
                .with_all(rows)
                .solve()
                .map_err(lp)?,
        ),
    })
}
