//! What a repairer plans when steps run turn by turn: the new joint plan for each strategy,
//! from its belief of the current state and the plan it holds. Pure functions of their
//! inputs (the agents of `vitro_worlds::repair` call them).

use serde::Serialize;

use super::scenario::Team;
use super::{Strategy, bits};
use crate::planning::heuristic::FfHeuristic;
use crate::planning::search::greedy_best_first_bounded;
use crate::planning::{ActionId, FactId, Task};

/// A step's identity: the plan version that introduced it and its position there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct StepId {
    /// The plan version that introduced the step.
    pub version: u32,
    /// Its position in that version.
    pub index: u32,
}

/// One step of a joint plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Step {
    /// Its identity.
    pub id: StepId,
    /// The ground action.
    pub action: ActionId,
}

/// A joint plan as an agent holds it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct JointPlan {
    /// The number of repairs that led to it (0: the original plan).
    pub version: u32,
    /// The state it starts from (as its author believed it).
    pub start: Vec<u64>,
    /// Its steps.
    pub steps: Vec<Step>,
    /// Executed lazily: failed steps are ignored, inapplicable ones skipped.
    pub deferred: bool,
}

impl JointPlan {
    /// The original plan of a team.
    pub fn original(team: &Team, strategy: Strategy) -> Self {
        JointPlan {
            version: 0,
            start: team.task.initial_state(),
            steps: new_steps(0, &team.plan),
            deferred: matches!(strategy, Strategy::Lazy | Strategy::RepeatedLazy),
        }
    }

    /// The position of step `id`.
    pub fn position(&self, id: StepId) -> Option<usize> {
        self.steps.iter().position(|s| s.id == id)
    }

    /// The state the plan expects after its first `n` steps.
    pub fn expected_after(&self, team: &Team, n: usize) -> Vec<u64> {
        let mut state = self.start.clone();
        for s in &self.steps[..n] {
            state = team.apply(s.action, &state);
        }
        state
    }
}

fn new_steps(version: u32, actions: &[ActionId]) -> Vec<Step> {
    actions
        .iter()
        .enumerate()
        .map(|(i, &action)| Step {
            id: StepId {
                version,
                index: i as u32,
            },
            action,
        })
        .collect()
}

/// What triggered a repair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Why {
    /// The step at this position failed (its precondition was false or its effect wrong).
    Failure(usize),
    /// The plan ended without the goal.
    PlanEnd,
}

/// The kind of repair made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RepairKind {
    /// A plan from the current state to the goal.
    Replan,
    /// A plan back to the expected state, then the rest of the old plan.
    BackOnTrack,
    /// A plan from the end state of a lazily executed plan to the goal.
    Lazy,
}

/// A repairer's decision.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Repair {
    /// The kind of repair made.
    pub kind: RepairKind,
    /// Back-on-track found no plan and replanned instead.
    pub fell_back: bool,
    /// States expanded by every search of this repair.
    pub expanded: u64,
    /// A search stopped at the expansion bound.
    pub truncated: bool,
    /// The new plan, `None` if no search found one.
    pub plan: Option<JointPlan>,
    /// Steps the new plan introduces.
    pub new_steps: usize,
}

/// One bounded greedy best-first search (FF) from `from` to the facts `goal`.
struct Found {
    plan: Option<Vec<ActionId>>,
    expanded: u64,
    truncated: bool,
}

fn search(team: &Team, from: &[u64], goal: Vec<FactId>, bound: Option<u64>) -> Found {
    let task = Task {
        facts: team.task.facts.clone(),
        actions: team.task.actions.clone(),
        init: bits::facts(from),
        goal,
    };
    let outcome = greedy_best_first_bounded(&task, &mut FfHeuristic::new(&task), bound);
    Found {
        plan: outcome.plan,
        expanded: outcome.stats.expanded,
        truncated: outcome.stats.truncated,
    }
}

/// Plans the repair of `old` for `strategy`, from `belief`, as plan `version`.
pub fn repair(
    team: &Team,
    strategy: Strategy,
    bound: Option<u64>,
    old: &JointPlan,
    why: Why,
    belief: &[u64],
    version: u32,
) -> Repair {
    let to_goal = |kind: RepairKind, deferred: bool| {
        let found = search(team, belief, team.task.goal.clone(), bound);
        finish(kind, found, |prefix| JointPlan {
            version,
            start: belief.to_vec(),
            steps: new_steps(version, &prefix),
            deferred,
        })
    };
    match strategy {
        Strategy::BackOnTrack => {
            let resume = match why {
                Why::Failure(i) => (i + 1).min(old.steps.len()),
                Why::PlanEnd => old.steps.len(),
            };
            let target = bits::facts(&old.expected_after(team, resume));
            let back = search(team, belief, target, bound);
            let (expanded, truncated) = (back.expanded, back.truncated);
            if back.plan.is_some() {
                return finish(RepairKind::BackOnTrack, back, |prefix| {
                    let mut steps = new_steps(version, &prefix);
                    steps.extend_from_slice(&old.steps[resume..]);
                    JointPlan {
                        version,
                        start: belief.to_vec(),
                        steps,
                        deferred: false,
                    }
                });
            }
            let mut r = to_goal(RepairKind::BackOnTrack, false);
            r.fell_back = true;
            r.expanded += expanded;
            r.truncated |= truncated;
            r
        }
        Strategy::Lazy | Strategy::RepeatedLazy if old.deferred => {
            to_goal(RepairKind::Lazy, strategy == Strategy::RepeatedLazy)
        }
        Strategy::Replan | Strategy::Lazy | Strategy::RepeatedLazy => {
            to_goal(RepairKind::Replan, false)
        }
    }
}

fn finish(
    kind: RepairKind,
    found: Found,
    build: impl FnOnce(Vec<ActionId>) -> JointPlan,
) -> Repair {
    let new_steps = found.plan.as_ref().map_or(0, Vec::len);
    Repair {
        kind,
        fell_back: false,
        expanded: found.expanded,
        truncated: found.truncated,
        plan: found.plan.map(build),
        new_steps,
    }
}
