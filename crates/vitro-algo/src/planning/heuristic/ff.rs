//! The FF heuristic: the cost of a relaxed plan extracted from h^add best supporters.

use super::{BucketQueue, Heuristic, INF, RelaxedTask};
use crate::planning::task::{ActionId, Task, for_each_fact};

/// FF (relaxed plan) heuristic: informative but not admissible, for satisficing search.
///
/// Facts get h^add costs; each reached fact remembers its cheapest achiever (ties go to
/// the first found), and the relaxed plan is the set of achievers needed, traced back from
/// the goal. [`FfHeuristic::relaxed_plan`] gives that plan after an evaluation.
#[derive(Debug, Clone)]
pub struct FfHeuristic {
    relaxed: RelaxedTask,
    fact_cost: Vec<u32>,
    supporter: Vec<u32>,
    unsatisfied: Vec<u32>,
    op_pre_cost: Vec<u32>,
    queue: BucketQueue,
    marked_fact: Vec<u32>,
    marked_op: Vec<u32>,
    stamp: u32,
    plan: Vec<ActionId>,
    stack: Vec<u32>,
}

impl FfHeuristic {
    /// Prepares the FF heuristic for `task`.
    pub fn new(task: &Task) -> Self {
        let relaxed = RelaxedTask::new(task);
        let (nf, no) = (relaxed.num_facts, relaxed.num_ops());
        FfHeuristic {
            fact_cost: vec![INF; nf],
            supporter: vec![INF; nf],
            unsatisfied: vec![0; no],
            op_pre_cost: vec![0; no],
            queue: BucketQueue::default(),
            marked_fact: vec![0; nf],
            marked_op: vec![0; no],
            stamp: 0,
            plan: Vec::new(),
            stack: Vec::new(),
            relaxed,
        }
    }

    /// The relaxed plan of the last successful evaluation, in extraction order.
    pub fn relaxed_plan(&self) -> &[ActionId] {
        &self.plan
    }

    /// h^add exploration from `state`; returns whether the goal fact was reached.
    fn explore(&mut self, state: &[u64]) -> bool {
        let r = &self.relaxed;
        self.fact_cost.fill(INF);
        self.supporter.fill(INF);
        self.op_pre_cost.fill(0);
        for op in 0..r.num_ops() {
            self.unsatisfied[op] = r.pre_len(op);
        }
        self.queue.clear();
        let mut start = |f: u32| {
            self.fact_cost[f as usize] = 0;
            self.queue.push(0, f);
        };
        start(r.true_fact);
        for_each_fact(state, start);
        while let Some((cost, fact)) = self.queue.pop() {
            if cost > self.fact_cost[fact as usize] {
                continue;
            }
            if fact == r.goal_fact {
                self.queue.clear();
                return true;
            }
            for &op in r.pre_of.row(fact) {
                let o = op as usize;
                self.op_pre_cost[o] = self.op_pre_cost[o].saturating_add(cost);
                self.unsatisfied[o] -= 1;
                if self.unsatisfied[o] == 0 {
                    let target = self.op_pre_cost[o].saturating_add(r.cost[o]);
                    for &e in r.eff.row(op) {
                        if target < self.fact_cost[e as usize] {
                            self.fact_cost[e as usize] = target;
                            self.supporter[e as usize] = op;
                            self.queue.push(target, e);
                        }
                    }
                }
            }
        }
        false
    }
}

impl Heuristic for FfHeuristic {
    fn evaluate(&mut self, state: &[u64]) -> Option<u32> {
        self.plan.clear();
        if !self.explore(state) {
            return None;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.marked_fact.fill(0);
            self.marked_op.fill(0);
            self.stamp = 1;
        }
        let r = &self.relaxed;
        let goal_op = (r.num_ops() - 1) as u32;
        let mut h = 0u32;
        self.stack.clear();
        self.stack.extend_from_slice(r.pre.row(goal_op));
        while let Some(f) = self.stack.pop() {
            if self.marked_fact[f as usize] == self.stamp {
                continue;
            }
            self.marked_fact[f as usize] = self.stamp;
            let op = self.supporter[f as usize];
            if op == INF || self.marked_op[op as usize] == self.stamp {
                continue;
            }
            self.marked_op[op as usize] = self.stamp;
            h = h.saturating_add(r.cost[op as usize]);
            self.plan.push(op);
            self.stack.extend_from_slice(r.pre.row(op));
        }
        Some(h)
    }
}
