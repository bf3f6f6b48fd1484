//! The h^max heuristic: the cost of the most expensive goal fact in the delete relaxation,
//! where a fact costs its cheapest achiever plus that achiever's costliest precondition.

use super::{BucketQueue, Heuristic, INF, RelaxedTask};
use crate::planning::task::{Task, for_each_fact};

/// h^max: admissible but weak; kept as a baseline for LM-cut (which dominates it).
///
/// ```
/// # use vitro_algo::planning::{Task, GroundAction};
/// use vitro_algo::planning::heuristic::{HMax, Heuristic};
/// // Two facts; one action turns fact 0 into fact 1, and the goal is fact 1.
/// let task = Task {
///     facts: vec!["(a)".into(), "(b)".into()],
///     actions: vec![GroundAction { name: "(go)".into(), pre: vec![0], add: vec![1], del: vec![0], cost: 1 }],
///     init: vec![0],
///     goal: vec![1],
/// };
/// let mut h = HMax::new(&task);
/// assert_eq!(h.evaluate(&task.initial_state()), Some(1));
/// ```
#[derive(Debug, Clone)]
pub struct HMax {
    relaxed: RelaxedTask,
    fact_cost: Vec<u32>,
    unsatisfied: Vec<u32>,
    queue: BucketQueue,
}

impl HMax {
    /// Prepares h^max for `task`.
    pub fn new(task: &Task) -> Self {
        let relaxed = RelaxedTask::new(task);
        HMax {
            fact_cost: vec![INF; relaxed.num_facts],
            unsatisfied: vec![0; relaxed.num_ops()],
            queue: BucketQueue::default(),
            relaxed,
        }
    }
}

impl Heuristic for HMax {
    fn evaluate(&mut self, state: &[u64]) -> Option<u32> {
        let r = &self.relaxed;
        self.fact_cost.fill(INF);
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
                return Some(cost);
            }
            for &op in r.pre_of.row(fact) {
                self.unsatisfied[op as usize] -= 1;
                if self.unsatisfied[op as usize] == 0 {
                    let target = cost + r.cost[op as usize];
                    for &e in r.eff.row(op) {
                        if target < self.fact_cost[e as usize] {
                            self.fact_cost[e as usize] = target;
                            self.queue.push(target, e);
                        }
                    }
                }
            }
        }
        None
    }
}
