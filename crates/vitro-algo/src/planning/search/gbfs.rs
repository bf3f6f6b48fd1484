//! Greedy best-first search: fast, not optimal.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::registry::StateRegistry;
use super::{SearchOutcome, SearchStats, SuccessorGenerator, trace_plan};
use crate::planning::heuristic::Heuristic;
use crate::planning::task::Task;

/// Greedy best-first search from the initial state of `task`, guided by `heuristic`.
///
/// Expands the open state of least h, ties in insertion order; every distinct state is
/// evaluated and queued once (no reopening). Returns a plan (not necessarily optimal) or
/// `None` once every reachable non-dead-end state has been expanded.
pub fn greedy_best_first(task: &Task, heuristic: &mut dyn Heuristic) -> SearchOutcome {
    greedy_best_first_bounded(task, heuristic, None)
}

/// [`greedy_best_first`] that gives up after `max_expanded` expansions (if given): the plan
/// is then `None` and [`SearchStats::truncated`] is set.
pub fn greedy_best_first_bounded(
    task: &Task,
    heuristic: &mut dyn Heuristic,
    max_expanded: Option<u64>,
) -> SearchOutcome {
    let succ = SuccessorGenerator::new(task);
    let mut registry = StateRegistry::new(task.words());
    let mut stats = SearchStats::default();
    let mut parent: Vec<u32> = Vec::new();
    let mut via: Vec<u32> = Vec::new();
    let mut open = BinaryHeap::new();
    let mut seq = 0u64;

    let init = task.initial_state();
    let (root, _) = registry.insert(&init);
    stats.evaluated += 1;
    stats.initial_h = heuristic.evaluate(&init);
    let Some(h0) = stats.initial_h else {
        return SearchOutcome { plan: None, stats };
    };
    parent.push(u32::MAX);
    via.push(u32::MAX);
    open.push(Reverse((h0, seq, root)));

    let mut applicable = Vec::new();
    let mut child = Vec::with_capacity(task.words());
    let mut state = Vec::with_capacity(task.words());
    while let Some(Reverse((_, _, id))) = open.pop() {
        state.clear();
        state.extend_from_slice(registry.get(id));
        if task.is_goal(&state) {
            let plan = trace_plan(&parent, &via, id);
            return SearchOutcome {
                plan: Some(plan),
                stats,
            };
        }
        if max_expanded.is_some_and(|max| stats.expanded >= max) {
            stats.truncated = true;
            return SearchOutcome { plan: None, stats };
        }
        stats.expanded += 1;
        succ.applicable(task, &state, &mut applicable);
        for &a in &applicable {
            stats.generated += 1;
            task.apply_into(a, &state, &mut child);
            let (cid, is_new) = registry.insert(&child);
            if !is_new {
                continue;
            }
            parent.push(id);
            via.push(a);
            stats.evaluated += 1;
            if let Some(hv) = heuristic.evaluate(&child) {
                seq += 1;
                open.push(Reverse((hv, seq, cid)));
            }
        }
    }
    SearchOutcome { plan: None, stats }
}
