//! The LM-cut heuristic (Helmert & Domshlak, ICAPS 2009): an admissible sum of
//! disjoint action landmarks found as cuts in the h^max justification graph.
//!
//! Each round computes h^max with the current (reduced) operator costs, marks the goal
//! zone (facts from which the goal is reached through zero-cost supporters), collects the
//! cut (operators reached before the zone that add a fact in it), adds the cheapest cut cost
//! to the estimate and subtracts it from every cut operator. h^max is then updated
//! incrementally from the cut's effects. The rounds end when h^max of the goal is 0.

use super::{BucketQueue, Heuristic, INF, RelaxedTask};
use crate::planning::task::{Task, for_each_fact};

/// Where a fact stands in the current round.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Zone {
    /// Reached by h^max (or not reached at all); not yet classified.
    Other,
    /// Reached from the state in the cut exploration, before the goal zone.
    BeforeGoal,
    /// In the goal zone.
    Goal,
}

/// LM-cut: admissible and much stronger than h^max; the heuristic for optimal A*.
///
/// ```
/// # use vitro_algo::planning::{Task, GroundAction};
/// use vitro_algo::planning::heuristic::{Heuristic, LmCut};
/// // Two independent facts each need their own action: h^max says 1, LM-cut says 2.
/// let act = |n: &str, f| GroundAction { name: n.into(), pre: vec![], add: vec![f], del: vec![], cost: 1 };
/// let task = Task {
///     facts: vec!["(a)".into(), "(b)".into()],
///     actions: vec![act("(make-a)", 0), act("(make-b)", 1)],
///     init: vec![],
///     goal: vec![0, 1],
/// };
/// assert_eq!(LmCut::new(&task).evaluate(&task.initial_state()), Some(2));
/// ```
#[derive(Debug, Clone)]
pub struct LmCut {
    relaxed: RelaxedTask,
    /// Current (reduced) operator costs.
    cost: Vec<u32>,
    fact_cost: Vec<u32>,
    unsatisfied: Vec<u32>,
    /// The h^max supporter (costliest precondition) of each reached operator, else INF.
    supporter: Vec<u32>,
    /// h^max cost of the supporter when it was last set.
    supporter_cost: Vec<u32>,
    zone: Vec<Zone>,
    queue: BucketQueue,
    stack: Vec<u32>,
    cut: Vec<u32>,
    state_facts: Vec<u32>,
}

impl LmCut {
    /// Prepares LM-cut for `task`.
    pub fn new(task: &Task) -> Self {
        let relaxed = RelaxedTask::new(task);
        let (nf, no) = (relaxed.num_facts, relaxed.num_ops());
        LmCut {
            cost: relaxed.cost.clone(),
            fact_cost: vec![INF; nf],
            unsatisfied: vec![0; no],
            supporter: vec![INF; no],
            supporter_cost: vec![0; no],
            zone: vec![Zone::Other; nf],
            queue: BucketQueue::default(),
            stack: Vec::new(),
            cut: Vec::new(),
            state_facts: Vec::new(),
            relaxed,
        }
    }

    fn enqueue(&mut self, fact: u32, cost: u32) {
        if cost < self.fact_cost[fact as usize] {
            self.fact_cost[fact as usize] = cost;
            self.queue.push(cost, fact);
        }
    }

    /// Full h^max exploration from the state facts with the current costs.
    fn first_exploration(&mut self) {
        let r = &self.relaxed;
        self.fact_cost.fill(INF);
        self.supporter.fill(INF);
        for op in 0..r.num_ops() {
            self.unsatisfied[op] = r.pre_len(op);
        }
        self.queue.clear();
        for i in 0..self.state_facts.len() {
            let f = self.state_facts[i];
            self.enqueue(f, 0);
        }
        while let Some((cost, fact)) = self.queue.pop() {
            if cost > self.fact_cost[fact as usize] {
                continue;
            }
            for i in 0..self.relaxed.pre_of.row(fact).len() {
                let op = self.relaxed.pre_of.row(fact)[i] as usize;
                self.unsatisfied[op] -= 1;
                if self.unsatisfied[op] == 0 {
                    self.supporter[op] = fact;
                    self.supporter_cost[op] = cost;
                    let target = cost + self.cost[op];
                    for j in 0..self.relaxed.eff.row(op as u32).len() {
                        let e = self.relaxed.eff.row(op as u32)[j];
                        self.enqueue(e, target);
                    }
                }
            }
        }
    }

    /// Lowers h^max after the costs of the operators in `self.cut` dropped.
    fn incremental_exploration(&mut self) {
        self.queue.clear();
        for i in 0..self.cut.len() {
            let op = self.cut[i] as usize;
            let target = self.supporter_cost[op] + self.cost[op];
            for j in 0..self.relaxed.eff.row(op as u32).len() {
                let e = self.relaxed.eff.row(op as u32)[j];
                self.enqueue(e, target);
            }
        }
        while let Some((cost, fact)) = self.queue.pop() {
            if cost > self.fact_cost[fact as usize] {
                continue;
            }
            for i in 0..self.relaxed.pre_of.row(fact).len() {
                let op = self.relaxed.pre_of.row(fact)[i] as usize;
                if self.supporter[op] != fact || self.supporter_cost[op] <= cost {
                    continue;
                }
                // The supporter got cheaper: the costliest precondition may now be another.
                let old = self.supporter_cost[op];
                let mut best = fact;
                for &p in self.relaxed.pre.row(op as u32) {
                    if self.fact_cost[p as usize] > self.fact_cost[best as usize] {
                        best = p;
                    }
                }
                self.supporter[op] = best;
                self.supporter_cost[op] = self.fact_cost[best as usize];
                if self.supporter_cost[op] < old {
                    let target = self.supporter_cost[op] + self.cost[op];
                    for j in 0..self.relaxed.eff.row(op as u32).len() {
                        let e = self.relaxed.eff.row(op as u32)[j];
                        self.enqueue(e, target);
                    }
                }
            }
        }
    }

    /// Marks the goal zone: facts reaching the goal through zero-cost supporters.
    fn mark_goal_zone(&mut self) {
        self.zone.fill(Zone::Other);
        self.stack.clear();
        self.stack.push(self.relaxed.goal_fact);
        while let Some(f) = self.stack.pop() {
            if self.zone[f as usize] == Zone::Goal {
                continue;
            }
            self.zone[f as usize] = Zone::Goal;
            for &op in self.relaxed.achievers.row(f) {
                let s = self.supporter[op as usize];
                if self.cost[op as usize] == 0 && s != INF && self.zone[s as usize] != Zone::Goal {
                    self.stack.push(s);
                }
            }
        }
    }

    /// Collects into `self.cut` the operators, reached from the state through their
    /// supporters without entering the goal zone, that add a goal-zone fact.
    fn find_cut(&mut self) {
        self.cut.clear();
        self.stack.clear();
        for &f in &self.state_facts {
            self.zone[f as usize] = Zone::BeforeGoal;
            self.stack.push(f);
        }
        while let Some(f) = self.stack.pop() {
            for &op in self.relaxed.pre_of.row(f) {
                if self.supporter[op as usize] != f {
                    continue;
                }
                let effects = self.relaxed.eff.row(op);
                if effects.iter().any(|&e| self.zone[e as usize] == Zone::Goal) {
                    self.cut.push(op);
                    continue;
                }
                for &e in effects {
                    if self.zone[e as usize] == Zone::Other {
                        self.zone[e as usize] = Zone::BeforeGoal;
                        self.stack.push(e);
                    }
                }
            }
        }
    }
}

impl Heuristic for LmCut {
    fn evaluate(&mut self, state: &[u64]) -> Option<u32> {
        self.state_facts.clear();
        self.state_facts.push(self.relaxed.true_fact);
        for_each_fact(state, |f| self.state_facts.push(f));
        self.cost.copy_from_slice(&self.relaxed.cost);

        self.first_exploration();
        let goal = self.relaxed.goal_fact as usize;
        if self.fact_cost[goal] == INF {
            return None;
        }
        let mut h = 0u32;
        while self.fact_cost[goal] != 0 {
            self.mark_goal_zone();
            self.find_cut();
            // Every cut operator has positive cost (zero-cost ones are in the zone's
            // plateau), and the cut is non-empty while the goal costs more than 0.
            let Some(step) = self.cut.iter().map(|&op| self.cost[op as usize]).min() else {
                break;
            };
            if step == 0 {
                break;
            }
            h += step;
            for &op in &self.cut {
                self.cost[op as usize] -= step;
            }
            self.incremental_exploration();
        }
        Some(h)
    }
}
