//! Heuristic state-space search over a [`Task`]: optimal A* and greedy best-first search.
//!
//! Both are deterministic: open lists order by integer keys and then by insertion
//! sequence; the state table hashes states only to detect duplicates.

mod astar;
mod gbfs;
mod registry;

pub use astar::astar;
pub use gbfs::{greedy_best_first, greedy_best_first_bounded};

use super::heuristic::Rows;
use super::task::{ActionId, FactId, Task, for_each_fact};

/// Counters of one search.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SearchStats {
    /// States whose successors were generated.
    pub expanded: u64,
    /// Successor states generated (duplicates included).
    pub generated: u64,
    /// Heuristic evaluations (once per distinct state).
    pub evaluated: u64,
    /// Closed states put back on the open list after a cheaper path was found (A* only).
    pub reopened: u64,
    /// Heuristic value of the initial state (`None`: a dead end).
    pub initial_h: Option<u32>,
    /// The search stopped at its expansion bound, before finding a plan or exhausting the
    /// reachable states ([`greedy_best_first_bounded`]).
    pub truncated: bool,
}

/// What a search found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SearchOutcome {
    /// The plan as action ids, or `None` when the search space was exhausted.
    pub plan: Option<Vec<ActionId>>,
    /// Counters.
    pub stats: SearchStats,
}

/// Finds the actions applicable in a state without testing every action.
///
/// Each action is filed under one of its preconditions; a state only looks at the actions
/// filed under its true facts.
#[derive(Debug, Clone)]
pub(crate) struct SuccessorGenerator {
    by_fact: Rows,
    no_pre: Vec<ActionId>,
}

impl SuccessorGenerator {
    pub fn new(task: &Task) -> Self {
        // File each action under the precondition with the fewest actions filed so far,
        // which keeps the lists short and balanced.
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); task.facts.len()];
        let mut no_pre = Vec::new();
        for (id, a) in task.actions.iter().enumerate() {
            match a.pre.iter().min_by_key(|&&f| lists[f as usize].len()) {
                Some(&f) => lists[f as usize].push(id as ActionId),
                None => no_pre.push(id as ActionId),
            }
        }
        SuccessorGenerator {
            by_fact: Rows::from_lists(&lists),
            no_pre,
        }
    }

    /// Writes into `out` the actions applicable in `state`, sorted by id.
    pub fn applicable(&self, task: &Task, state: &[u64], out: &mut Vec<ActionId>) {
        out.clear();
        out.extend_from_slice(&self.no_pre);
        for_each_fact(state, |f: FactId| {
            for &a in self.by_fact.row(f) {
                if task.applicable(a, state) {
                    out.push(a);
                }
            }
        });
        out.sort_unstable();
    }
}

/// Follows parent links from `state` back to the root (parent `u32::MAX`).
fn trace_plan(parent: &[u32], via: &[ActionId], mut state: u32) -> Vec<ActionId> {
    let mut plan = Vec::new();
    while parent[state as usize] != u32::MAX {
        plan.push(via[state as usize]);
        state = parent[state as usize];
    }
    plan.reverse();
    plan
}
