//! A* with reopening: optimal with any admissible heuristic (consistent or not).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::registry::StateRegistry;
use super::{SearchOutcome, SearchStats, SuccessorGenerator, trace_plan};
use crate::planning::heuristic::Heuristic;
use crate::planning::task::Task;

/// Marks states the heuristic found to be dead ends.
const DEAD: u32 = u32::MAX;

/// A* search from the initial state of `task` guided by `heuristic`.
///
/// With an admissible heuristic the plan is optimal. The open list orders by f = g + h,
/// then by smaller h (deeper nodes first), then by insertion order. A state closed and
/// later reached more cheaply is reopened, so inconsistent heuristics such as LM-cut keep
/// optimality. Heuristic values are computed once per distinct state.
pub fn astar(task: &Task, heuristic: &mut dyn Heuristic) -> SearchOutcome {
    let succ = SuccessorGenerator::new(task);
    let mut registry = StateRegistry::new(task.words());
    let mut stats = SearchStats::default();
    let mut g: Vec<u32> = Vec::new();
    let mut h: Vec<u32> = Vec::new();
    let mut parent: Vec<u32> = Vec::new();
    let mut via: Vec<u32> = Vec::new();
    let mut closed: Vec<bool> = Vec::new();
    let mut open = BinaryHeap::new();
    let mut seq = 0u64;

    let init = task.initial_state();
    let (root, _) = registry.insert(&init);
    stats.evaluated += 1;
    stats.initial_h = heuristic.evaluate(&init);
    let Some(h0) = stats.initial_h else {
        return SearchOutcome { plan: None, stats };
    };
    g.push(0);
    h.push(h0);
    parent.push(u32::MAX);
    via.push(u32::MAX);
    closed.push(false);
    open.push(Reverse((h0, h0, seq, root)));

    let mut applicable = Vec::new();
    let mut child = Vec::with_capacity(task.words());
    let mut state = Vec::with_capacity(task.words());
    while let Some(Reverse((f, _, _, id))) = open.pop() {
        let i = id as usize;
        if closed[i] || f != g[i] + h[i] {
            continue; // stale entry: expanded already or reached more cheaply since
        }
        state.clear();
        state.extend_from_slice(registry.get(id));
        if task.is_goal(&state) {
            let plan = trace_plan(&parent, &via, id);
            return SearchOutcome {
                plan: Some(plan),
                stats,
            };
        }
        closed[i] = true;
        stats.expanded += 1;
        succ.applicable(task, &state, &mut applicable);
        for &a in &applicable {
            stats.generated += 1;
            task.apply_into(a, &state, &mut child);
            let new_g = g[i] + task.actions[a as usize].cost;
            let (cid, is_new) = registry.insert(&child);
            let c = cid as usize;
            if is_new {
                stats.evaluated += 1;
                let hv = heuristic.evaluate(&child).unwrap_or(DEAD);
                g.push(new_g);
                h.push(hv);
                parent.push(id);
                via.push(a);
                closed.push(false);
                if hv != DEAD {
                    seq += 1;
                    open.push(Reverse((new_g + hv, hv, seq, cid)));
                }
            } else if h[c] != DEAD && new_g < g[c] {
                g[c] = new_g;
                parent[c] = id;
                via[c] = a;
                if closed[c] {
                    closed[c] = false;
                    stats.reopened += 1;
                }
                seq += 1;
                open.push(Reverse((new_g + h[c], h[c], seq, cid)));
            }
        }
    }
    SearchOutcome { plan: None, stats }
}
