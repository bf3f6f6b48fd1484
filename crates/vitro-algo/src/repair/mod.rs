//! Multi-agent plans and their decentralized repair.
//!
//! A [`Scenario`] is a PDDL problem whose ground actions each belong to an agent (by default
//! the object of the action's first parameter: in the dock-worker domain each robot and each
//! crane is an agent, see [`Ownership`]), and a joint plan. When an agent finds that the
//! world is not what the plan expected (a step failed, a teammate is lost, the plan ended
//! short of the goal), a repairer plans anew, with greedy best-first search and FF
//! (optionally bounded), and tells the agents that own steps of the new plan they do not know
//! yet. The strategies ([`Strategy`]) differ in what the repairer plans for and when:
//!
//! - [`Replan`](Strategy::Replan): at every failure, a new plan from the current state to
//!   the goal, sent to every agent that owns a step of it.
//! - [`BackOnTrack`](Strategy::BackOnTrack): at every failure, a plan from the current state
//!   back to the state the plan expected after the failed step (its true facts), followed by
//!   the rest of the old plan. Only the owners of the new prefix are told: the others keep
//!   the rest of the plan they already know. If no such plan is found (none exists, or the
//!   bound cut the search), it falls back to replanning.
//! - [`Lazy`](Strategy::Lazy): failures of the original plan are not repaired at once: the
//!   agents go on with every step that still applies and skip the others; at the end of the
//!   plan, one repair plans from the state reached to the goal. Failures of that repair plan
//!   are handled by replanning (the lazy repair is made once).
//! - [`RepeatedLazy`](Strategy::RepeatedLazy): every plan, repair plans included, is
//!   executed lazily, and a lazy repair is made each time a plan ends short of the goal.
//!
//! Two faces: [`Repairer`] holds a team's plan for a caller that owns the world and the radio
//! (a mission's agents executing steps in parallel); [`planner`] makes one repair of a plan
//! executed turn by turn (the stand-alone dock-worker runs of `vitro_worlds::repair`, where
//! the plan is executed as agents in a simulation).
//!
//! ```
//! use vitro_algo::planning::PddlSource;
//! use vitro_algo::repair::planner::{JointPlan, Why, repair};
//! use vitro_algo::repair::{Ownership, Scenario, Strategy};
//!
//! let domain = "(define (domain lift) (:predicates (at ?w ?f) (adj ?a ?b))
//!   (:action go :parameters (?w ?a ?b) :precondition (and (at ?w ?a) (adj ?a ?b))
//!    :effect (and (at ?w ?b) (not (at ?w ?a)))))";
//! let problem = "(define (problem p) (:domain lift) (:objects ann bob f0 f1 f2)
//!   (:init (at ann f0) (at bob f2) (adj f0 f1) (adj f1 f0) (adj f1 f2) (adj f2 f1))
//!   (:goal (and (at ann f2) (at bob f0))))";
//! let scenario = Scenario::from_pddl(
//!     PddlSource::new("lift.pddl", domain),
//!     PddlSource::new("p.pddl", problem),
//!     &Ownership::first_parameter(),
//! )?;
//! let team = scenario.team();
//! let plan = JointPlan::original(team, Strategy::Replan);
//! // The plan has not started and the world is as it began: replanning from there reaches
//! // the goal in as many steps.
//! let fixed = repair(team, Strategy::Replan, None, &plan, Why::PlanEnd, &plan.start, 1);
//! assert_eq!(fixed.plan.unwrap().steps.len(), plan.steps.len());
//! # Ok::<(), vitro_algo::repair::RepairError>(())
//! ```

pub mod planner;
mod repairer;
mod scenario;

use std::fmt;

use thiserror::Error;

use crate::planning::PlanError;

pub use planner::RepairKind;
pub use repairer::{Cause, PlanStep, RepairSettings, RepairTally, Repairer, Revision, StepRef};
pub use scenario::{Ownership, Scenario, Team};

/// How the team reacts to a failure (see the [module](self) documentation).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum Strategy {
    /// A new plan from the current state to the goal at every failure.
    Replan,
    /// Back to the state the plan expected, then the rest of the plan.
    BackOnTrack,
    /// Go on with what still applies; one repair from the end state to the goal.
    Lazy,
    /// Lazy repair, repeated for repair plans too.
    RepeatedLazy,
}

impl Strategy {
    /// Every strategy, in a fixed order.
    pub const ALL: [Strategy; 4] = [
        Strategy::Replan,
        Strategy::BackOnTrack,
        Strategy::Lazy,
        Strategy::RepeatedLazy,
    ];
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Strategy::Replan => "replan",
            Strategy::BackOnTrack => "back-on-track",
            Strategy::Lazy => "lazy",
            Strategy::RepeatedLazy => "repeated-lazy",
        })
    }
}

/// Why a scenario could not be built or a repair not made.
#[derive(Debug, Error)]
pub enum RepairError {
    /// A file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The PDDL does not parse, or the problem has no plan.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A ground action has no parameter at the position that names its owner.
    #[error("action {action} has no parameter {parameter} to name its owner")]
    NoOwner {
        /// The ground action.
        action: String,
        /// The owning parameter's position.
        parameter: usize,
    },
    /// A fact the ground task does not have (a repairer's belief or goal).
    #[error("no fact {0} in the task")]
    UnknownFact(String),
}

/// Bitset helpers over fact ids (states are bitsets of `u64` words).
pub mod bits {
    use crate::planning::FactId;

    /// Sets fact `f` in `s`.
    pub fn set(s: &mut [u64], f: FactId) {
        s[(f / 64) as usize] |= 1 << (f % 64);
    }
    /// The set facts of `s`, in increasing order.
    pub fn facts(s: &[u64]) -> Vec<FactId> {
        let mut v = Vec::new();
        for (w, &word) in s.iter().enumerate() {
            let mut b = word;
            while b != 0 {
                v.push(w as FactId * 64 + b.trailing_zeros());
                b &= b - 1;
            }
        }
        v
    }
    /// A state of `words` words with `facts` set.
    pub fn state(words: usize, facts: &[FactId]) -> Vec<u64> {
        let mut s = vec![0; words];
        for &f in facts {
            set(&mut s, f);
        }
        s
    }
}
