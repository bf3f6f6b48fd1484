//! Classical planning: PDDL (STRIPS with typing) in, plans out.
//!
//! The pipeline is [`pddl`] (parse and check) → [`ground()`] (reachability-based grounding to
//! a compact [`Task`]) → [`search`] (A* with [`heuristic::LmCut`] for optimal plans, greedy
//! best-first with [`heuristic::FfHeuristic`] for fast ones). [`validate::validate_plan`]
//! checks a plan against the PDDL semantics on a separate code path.
//!
//! ```
//! use vitro_algo::planning::{solve, PddlSource, Planner};
//!
//! let domain = "(define (domain lights) (:predicates (on ?l) (off ?l))
//!   (:action switch :parameters (?l) :precondition (off ?l)
//!    :effect (and (on ?l) (not (off ?l)))))";
//! let problem = "(define (problem two) (:domain lights) (:objects a b)
//!   (:init (off a) (off b)) (:goal (and (on a) (on b))))";
//! let result = solve(
//!     PddlSource::new("lights.pddl", domain),
//!     PddlSource::new("two.pddl", problem),
//!     Planner::Optimal,
//! )?;
//! assert_eq!(result.plan, ["(switch a)", "(switch b)"]);
//! # Ok::<(), vitro_algo::planning::PlanError>(())
//! ```

mod ground;
pub mod heuristic;
pub mod pddl;
pub mod search;
mod task;
pub mod validate;

use std::fmt;
use std::path::Path;

use thiserror::Error;

pub use ground::{GroundError, ground};
pub use task::{ActionId, FactId, GroundAction, Task};

use heuristic::{FfHeuristic, LmCut};
use pddl::ParseError;
use search::{SearchOutcome, astar, greedy_best_first};

/// Which planner to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Planner {
    /// A* with LM-cut: a shortest plan (unit action costs).
    Optimal,
    /// Greedy best-first search with the FF heuristic: a plan, quickly, maybe longer.
    Satisficing,
}

impl fmt::Display for Planner {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Planner::Optimal => "optimal (A*, LM-cut)",
            Planner::Satisficing => "satisficing (GBFS, FF)",
        })
    }
}

/// PDDL text with the name its errors should carry (usually the file path).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PddlSource<'a> {
    /// Name used in error messages.
    pub name: &'a str,
    /// The PDDL text.
    pub text: &'a str,
}

impl<'a> PddlSource<'a> {
    /// Names `text` as `name`.
    pub fn new(name: &'a str, text: &'a str) -> Self {
        PddlSource { name, text }
    }
}

/// A plan and how it was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanResult {
    /// Ground actions in order, e.g. `(move r1 l1 l2)`.
    pub plan: Vec<String>,
    /// Number of actions.
    pub length: usize,
    /// Sum of action costs (equal to `length` for unit costs).
    pub cost: u64,
    /// States expanded.
    pub expanded: u64,
    /// Successor states generated.
    pub generated: u64,
    /// Heuristic evaluations.
    pub evaluated: u64,
    /// Heuristic estimate of the initial state.
    pub initial_h: u32,
    /// Facts in the ground task.
    pub facts: usize,
    /// Actions in the ground task.
    pub actions: usize,
}

/// Why no plan was returned.
#[derive(Debug, Error)]
pub enum PlanError {
    /// A file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The domain or problem is not valid PDDL of the supported fragment.
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// Grounding failed (an unreachable goal means no plan exists).
    #[error("no plan: {0}")]
    Ground(#[from] GroundError),
    /// Search exhausted the reachable states without reaching the goal.
    #[error("no plan: the goal is unreachable ({expanded} states expanded)")]
    Unsolvable {
        /// States expanded before giving up.
        expanded: u64,
    },
}

/// Parses, grounds and solves a planning problem.
///
/// # Errors
/// [`PlanError::Parse`] (with file, line and column), or [`PlanError::Ground`] /
/// [`PlanError::Unsolvable`] when there is no plan.
pub fn solve(
    domain: PddlSource<'_>,
    problem: PddlSource<'_>,
    planner: Planner,
) -> Result<PlanResult, PlanError> {
    let d = pddl::parse_domain(domain.text, domain.name)?;
    let p = pddl::parse_problem(&d, problem.text, problem.name)?;
    let task = ground(&d, &p)?;
    let outcome = plan_task(&task, planner);
    let stats = outcome.stats;
    let actions = outcome.plan.ok_or(PlanError::Unsolvable {
        expanded: stats.expanded,
    })?;
    Ok(PlanResult {
        length: actions.len(),
        cost: actions
            .iter()
            .map(|&a| u64::from(task.actions[a as usize].cost))
            .sum(),
        plan: actions
            .iter()
            .map(|&a| task.actions[a as usize].name.clone())
            .collect(),
        expanded: stats.expanded,
        generated: stats.generated,
        evaluated: stats.evaluated,
        initial_h: stats.initial_h.unwrap_or(u32::MAX),
        facts: task.facts.len(),
        actions: task.actions.len(),
    })
}

/// [`solve`] on two files; errors name the files as given.
///
/// # Errors
/// [`PlanError::Io`] when a file cannot be read, otherwise as [`solve`].
pub fn solve_files(
    domain: &Path,
    problem: &Path,
    planner: Planner,
) -> Result<PlanResult, PlanError> {
    let read = |path: &Path| {
        std::fs::read_to_string(path).map_err(|source| PlanError::Io {
            path: path.display().to_string(),
            source,
        })
    };
    let (dt, pt) = (read(domain)?, read(problem)?);
    let (dn, pn) = (domain.display().to_string(), problem.display().to_string());
    solve(
        PddlSource::new(&dn, &dt),
        PddlSource::new(&pn, &pt),
        planner,
    )
}

/// Runs `planner` on a ground task.
pub fn plan_task(task: &Task, planner: Planner) -> SearchOutcome {
    match planner {
        Planner::Optimal => astar(task, &mut LmCut::new(task)),
        Planner::Satisficing => greedy_best_first(task, &mut FfHeuristic::new(task)),
    }
}
