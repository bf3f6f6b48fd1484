//! The LP backends of good_lp the patrol solvers can use, behind one call.
//!
//! Both are pure Rust: [`LpBackend::Microlp`] (a dense simplex: vertex solutions, can hit a
//! singular basis on degenerate programs) and [`LpBackend::Clarabel`] (an interior-point
//! conic solver: solutions inside the optimal face, to its tolerance of about 1e-8). HiGHS
//! (good_lp's `highs` feature) needs cmake and a C++ build; it is not offered. Example
//! `lp_backends` measures both on the village and convoy instances.

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
