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
    work: Work,
}

/// Per-evaluation scratch data of LM-cut (kept apart from the relaxed task so that the
/// loops can read one while writing the other).
#[derive(Debug, Clone)]
struct Work {
    /// Current (reduced) operator costs.
    cost: Vec<u32>,
    fact_cost: Vec<u32>,
    unsatisfied: Vec<u32>,
    /// The h^max supporter (costliest precondition) of each reached operator, else INF.
    supporter: Vec<u32>,
    /// h^max cost of the supporter when it was last set.
    supporter_cost: Vec<u32>,
    /// Per fact, the first operator it supports (INF: none); the operators a fact
    /// supports form a doubly linked list through `next` and `prev`.
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
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
        let work = Work {
            cost: relaxed.cost.clone(),
            fact_cost: vec![INF; nf],
            unsatisfied: vec![0; no],
            supporter: vec![INF; no],
            supporter_cost: vec![0; no],
            head: vec![INF; nf],
            next: vec![INF; no],
            prev: vec![INF; no],
            zone: vec![Zone::Other; nf],
            queue: BucketQueue::default(),
            stack: Vec::new(),
            cut: Vec::new(),
            state_facts: Vec::new(),
        };
        LmCut { relaxed, work }
    }
}

impl Work {
    /// Makes `fact` the supporter of `op` (which has none).
    #[inline]
    fn link(&mut self, op: u32, fact: u32) {
        let h = self.head[fact as usize];
        self.next[op as usize] = h;
        self.prev[op as usize] = INF;
        if h != INF {
            self.prev[h as usize] = op;
        }
        self.head[fact as usize] = op;
        self.supporter[op as usize] = fact;
    }

    /// Removes `op` from the list of its supporter.
    #[inline]
    fn unlink(&mut self, op: u32) {
        let (p, n) = (self.prev[op as usize], self.next[op as usize]);
        if p == INF {
            self.head[self.supporter[op as usize] as usize] = n;
        } else {
            self.next[p as usize] = n;
        }
        if n != INF {
            self.prev[n as usize] = p;
        }
    }

    #[inline]
    fn enqueue(&mut self, fact: u32, cost: u32) {
        if cost < self.fact_cost[fact as usize] {
            self.fact_cost[fact as usize] = cost;
            self.queue.push(cost, fact);
        }
    }

    /// Full h^max exploration from the state facts with the current costs.
    fn first_exploration(&mut self, r: &RelaxedTask) {
        self.fact_cost.fill(INF);
        self.supporter.fill(INF);
        self.head.fill(INF);
        for (op, u) in self.unsatisfied.iter_mut().enumerate() {
            *u = r.pre_len(op);
        }
        self.queue.clear();
        for i in 0..self.state_facts.len() {
            self.enqueue(self.state_facts[i], 0);
        }
        while let Some((cost, fact)) = self.queue.pop() {
            if cost > self.fact_cost[fact as usize] {
                continue;
            }
            for &op in r.pre_of.row(fact) {
                let o = op as usize;
                self.unsatisfied[o] -= 1;
                if self.unsatisfied[o] == 0 {
                    self.link(op, fact);
                    self.supporter_cost[o] = cost;
                    let target = cost + self.cost[o];
                    for &e in r.eff.row(op) {
                        self.enqueue(e, target);
                    }
                }
            }
        }
    }

    /// Lowers h^max after the costs of the operators in `self.cut` dropped.
    fn incremental_exploration(&mut self, r: &RelaxedTask) {
        self.queue.clear();
        for i in 0..self.cut.len() {
            let op = self.cut[i];
            let target = self.supporter_cost[op as usize] + self.cost[op as usize];
            for &e in r.eff.row(op) {
                self.enqueue(e, target);
            }
        }
        while let Some((cost, fact)) = self.queue.pop() {
            if cost > self.fact_cost[fact as usize] {
                continue;
            }
            let mut op = self.head[fact as usize];
            while op != INF {
                let o = op as usize;
                let following = self.next[o];
                if self.supporter_cost[o] > cost {
                    // The supporter got cheaper: the costliest precondition may now be
                    // another one.
                    let old = self.supporter_cost[o];
                    let (mut best, mut best_cost) = (fact, cost);
                    for &p in r.pre.row(op) {
                        if self.fact_cost[p as usize] > best_cost {
                            best = p;
                            best_cost = self.fact_cost[p as usize];
                        }
                    }
                    if best != fact {
                        self.unlink(op);
                        self.link(op, best);
                    }
                    self.supporter_cost[o] = best_cost;
                    if best_cost < old {
                        let target = best_cost + self.cost[o];
                        for &e in r.eff.row(op) {
                            self.enqueue(e, target);
                        }
                    }
                }
                op = following;
            }
        }
    }

    /// Marks the goal zone: facts reaching the goal through zero-cost supporters.
    fn mark_goal_zone(&mut self, r: &RelaxedTask) {
        self.zone.fill(Zone::Other);
        self.stack.clear();
        self.stack.push(r.goal_fact);
        while let Some(f) = self.stack.pop() {
            if self.zone[f as usize] == Zone::Goal {
                continue;
            }
            self.zone[f as usize] = Zone::Goal;
            for &op in r.achievers.row(f) {
                let s = self.supporter[op as usize];
                if self.cost[op as usize] == 0 && s != INF && self.zone[s as usize] != Zone::Goal {
                    self.stack.push(s);
                }
            }
        }
    }

    /// Collects into `self.cut` the operators, reached from the state through their
    /// supporters without entering the goal zone, that add a goal-zone fact.
    fn find_cut(&mut self, r: &RelaxedTask) {
        self.cut.clear();
        self.stack.clear();
        for &f in &self.state_facts {
            self.zone[f as usize] = Zone::BeforeGoal;
            self.stack.push(f);
        }
        while let Some(f) = self.stack.pop() {
            let mut op = self.head[f as usize];
            while op != INF {
                let effects = r.eff.row(op);
                if effects.iter().any(|&e| self.zone[e as usize] == Zone::Goal) {
                    self.cut.push(op);
                } else {
                    for &e in effects {
                        if self.zone[e as usize] == Zone::Other {
                            self.zone[e as usize] = Zone::BeforeGoal;
                            self.stack.push(e);
                        }
                    }
                }
                op = self.next[op as usize];
            }
        }
    }
}

impl Heuristic for LmCut {
    fn evaluate(&mut self, state: &[u64]) -> Option<u32> {
        let (r, w) = (&self.relaxed, &mut self.work);
        w.state_facts.clear();
        w.state_facts.push(r.true_fact);
        for_each_fact(state, |f| w.state_facts.push(f));
        w.cost.copy_from_slice(&r.cost);

        w.first_exploration(r);
        let goal = r.goal_fact as usize;
        if w.fact_cost[goal] == INF {
            return None;
        }
        let mut h = 0u32;
        while w.fact_cost[goal] != 0 {
            w.mark_goal_zone(r);
            w.find_cut(r);
            // Every cut operator has positive cost (zero-cost ones are in the zone's
            // plateau), and the cut is non-empty while the goal costs more than 0.
            let Some(step) = w.cut.iter().map(|&op| w.cost[op as usize]).min() else {
                break;
            };
            if step == 0 {
                break;
            }
            h += step;
            for &op in &w.cut {
                w.cost[op as usize] -= step;
            }
            w.incremental_exploration(r);
        }
        Some(h)
    }
}
