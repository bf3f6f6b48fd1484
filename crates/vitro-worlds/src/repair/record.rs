//! What a run records: the actions the world applied, each repair and why it was started,
//! and why a run failed.

use vitro::time::{SimDuration, SimTime};
use vitro_algo::repair::RepairKind;

/// One change of the world, as the experimenter sees it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Applied {
    /// When.
    pub time: SimTime,
    /// The agent that acted (`None` for a disturbance).
    pub by: Option<String>,
    /// What happened.
    pub kind: AppliedKind,
}

/// What an action execution or a disturbance did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AppliedKind {
    /// The intended action.
    Done {
        /// The action, e.g. `(move r1 l1 l2)`.
        action: String,
    },
    /// The action slipped: another action of the same agent happened.
    Slip {
        /// The action the agent meant.
        intended: String,
        /// The action that happened.
        actual: String,
    },
    /// The action failed without effect (the agent had no other applicable action).
    NoEffect {
        /// The action the agent meant.
        intended: String,
    },
    /// The environment applied an action no agent chose.
    Disturbance {
        /// The action that happened.
        action: String,
    },
}

impl Applied {
    /// The ground action that changed the world, if any.
    pub fn applied(&self) -> Option<&str> {
        match &self.kind {
            AppliedKind::Done { action } | AppliedKind::Disturbance { action } => Some(action),
            AppliedKind::Slip { actual, .. } => Some(actual),
            AppliedKind::NoEffect { .. } => None,
        }
    }
    /// Whether this was a failed execution (a slip or no effect).
    pub fn is_failure(&self) -> bool {
        matches!(
            self.kind,
            AppliedKind::Slip { .. } | AppliedKind::NoEffect { .. }
        )
    }
}

/// What made an agent repair.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Trigger {
    /// This step's precondition was false or its effect wrong.
    Failure {
        /// The step's action.
        action: String,
    },
    /// The plan ended without the goal.
    PlanEnd,
}

/// One repair.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RepairRecord {
    /// When the new plan was adopted.
    pub time: SimTime,
    /// The repairer.
    pub by: String,
    /// Why.
    pub trigger: Trigger,
    /// What was planned.
    pub kind: RepairKind,
    /// Back-on-track found no way back and replanned.
    pub fell_back: bool,
    /// States expanded.
    pub expanded: u64,
    /// A search was cut at the expansion bound.
    pub truncated: bool,
    /// Simulated planning time.
    pub planning_time: SimDuration,
    /// Steps the repair introduced.
    pub new_steps: usize,
    /// Agents sent the new plan.
    pub notified: usize,
}

/// Why a run did not reach the goal.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunFailure {
    /// A repair found no plan (none exists, or the expansion bound cut the search).
    #[error("repair {repairs} found no plan")]
    NoPlan {
        /// Repairs made, the failed one included.
        repairs: u32,
    },
    /// The repair limit was reached.
    #[error("gave up after {0} repairs")]
    TooManyRepairs(u32),
    /// An agent did not answer a state query.
    #[error("{agent} did not answer")]
    NoAnswer {
        /// The silent agent.
        agent: String,
    },
    /// The time limit passed.
    #[error("time limit reached")]
    TimeLimit,
}
