//! Delete-relaxation heuristics: h^max, FF (relaxed plan) and LM-cut.
//!
//! All work on a `RelaxedTask`: the task's actions plus an artificial goal action,
//! with an artificial always-true fact as the precondition of actions that have none.

mod ff;
mod hmax;
mod lmcut;

pub use ff::FfHeuristic;
pub use hmax::HMax;
pub use lmcut::LmCut;

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::task::{FactId, Task};

/// A state evaluator for heuristic search.
pub trait Heuristic {
    /// Estimated cost from `state` (a bitset over the task's facts) to the goal, or `None`
    /// when the goal is unreachable from it even ignoring deletes (a dead end).
    fn evaluate(&mut self, state: &[u64]) -> Option<u32>;
}

/// Compressed-row lists: `items[start[i]..start[i + 1]]` belongs to row `i`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Rows {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Rows {
    /// Builds rows from `(row, item)` pairs; items keep their order within a row.
    pub fn from_pairs(rows: usize, pairs: &[(u32, u32)]) -> Self {
        let mut start = vec![0u32; rows + 1];
        for &(r, _) in pairs {
            start[r as usize + 1] += 1;
        }
        for i in 0..rows {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut items = vec![0; pairs.len()];
        for &(r, x) in pairs {
            items[fill[r as usize] as usize] = x;
            fill[r as usize] += 1;
        }
        Rows { start, items }
    }

    /// Builds rows from per-row vectors.
    pub fn from_lists(lists: &[Vec<u32>]) -> Self {
        let mut start = Vec::with_capacity(lists.len() + 1);
        let mut items = Vec::new();
        start.push(0);
        for l in lists {
            items.extend_from_slice(l);
            start.push(items.len() as u32);
        }
        Rows { start, items }
    }

    /// The items of row `i`.
    #[inline]
    pub fn row(&self, i: u32) -> &[u32] {
        &self.items[self.start[i as usize] as usize..self.start[i as usize + 1] as usize]
    }
}

/// The delete relaxation of a task as flat arrays.
///
/// Facts `0..n` are the task's; fact `n` is always true, fact `n + 1` is the goal.
/// Operators `0..m` are the task's actions (same ids), operator `m` is the goal action.
#[derive(Debug, Clone)]
pub(crate) struct RelaxedTask {
    /// Number of facts including the two artificial ones.
    pub num_facts: usize,
    /// The always-true fact.
    pub true_fact: FactId,
    /// The artificial goal fact.
    pub goal_fact: FactId,
    /// Preconditions per operator (never empty).
    pub pre: Rows,
    /// Effects per operator (adds not already required).
    pub eff: Rows,
    /// Cost per operator (the goal operator costs 0).
    pub cost: Vec<u32>,
    /// Operators having each fact as a precondition.
    pub pre_of: Rows,
    /// Operators adding each fact.
    pub achievers: Rows,
}

impl RelaxedTask {
    pub fn new(task: &Task) -> Self {
        let n = task.facts.len() as u32;
        let (true_fact, goal_fact) = (n, n + 1);
        let mut pre = Vec::with_capacity(task.actions.len() + 1);
        let mut eff = Vec::with_capacity(task.actions.len() + 1);
        let mut cost = Vec::with_capacity(task.actions.len() + 1);
        for a in &task.actions {
            pre.push(if a.pre.is_empty() {
                vec![true_fact]
            } else {
                a.pre.clone()
            });
            eff.push(
                a.add
                    .iter()
                    .copied()
                    .filter(|f| a.pre.binary_search(f).is_err())
                    .collect(),
            );
            cost.push(a.cost);
        }
        pre.push(if task.goal.is_empty() {
            vec![true_fact]
        } else {
            task.goal.clone()
        });
        eff.push(vec![goal_fact]);
        cost.push(0);

        let num_facts = n as usize + 2;
        let mut pre_pairs = Vec::new();
        let mut eff_pairs = Vec::new();
        for (op, (p, e)) in pre.iter().zip(&eff).enumerate() {
            pre_pairs.extend(p.iter().map(|&f| (f, op as u32)));
            eff_pairs.extend(e.iter().map(|&f| (f, op as u32)));
        }
        RelaxedTask {
            num_facts,
            true_fact,
            goal_fact,
            pre: Rows::from_lists(&pre),
            eff: Rows::from_lists(&eff),
            cost,
            pre_of: Rows::from_pairs(num_facts, &pre_pairs),
            achievers: Rows::from_pairs(num_facts, &eff_pairs),
        }
    }

    /// Number of operators including the goal operator.
    pub fn num_ops(&self) -> usize {
        self.cost.len()
    }

    /// Number of preconditions of operator `op`.
    pub fn pre_len(&self, op: usize) -> u32 {
        self.pre.row(op as u32).len() as u32
    }
}

/// Costs below this go to buckets; larger ones to a binary heap.
const BUCKETS: u32 = 1 << 14;

/// A priority queue over integer costs: buckets for small costs, a heap beyond.
///
/// Pops return a least cost; among equal costs the most recently pushed comes first.
#[derive(Debug, Clone, Default)]
pub(crate) struct BucketQueue {
    buckets: Vec<Vec<u32>>,
    current: usize,
    in_buckets: usize,
    overflow: BinaryHeap<Reverse<(u32, u32)>>,
}

impl BucketQueue {
    pub fn push(&mut self, cost: u32, item: u32) {
        if cost >= BUCKETS {
            self.overflow.push(Reverse((cost, item)));
            return;
        }
        let c = cost as usize;
        if c >= self.buckets.len() {
            self.buckets.resize_with(c + 1, Vec::new);
        }
        self.buckets[c].push(item);
        self.current = self.current.min(c);
        self.in_buckets += 1;
    }

    /// Removes an item of least cost.
    pub fn pop(&mut self) -> Option<(u32, u32)> {
        if self.in_buckets == 0 {
            return self.overflow.pop().map(|Reverse(x)| x);
        }
        // Every bucketed item sits at or after `current`, so this stops at one.
        while self.buckets[self.current].is_empty() {
            self.current += 1;
        }
        self.in_buckets -= 1;
        let item = self.buckets[self.current].pop()?;
        Some((self.current as u32, item))
    }

    pub fn clear(&mut self) {
        if self.in_buckets > 0 {
            for b in &mut self.buckets[self.current..] {
                b.clear();
            }
        }
        self.overflow.clear();
        self.current = 0;
        self.in_buckets = 0;
    }
}

/// Unreached cost marker.
pub(crate) const INF: u32 = u32::MAX;
