//! Certified global optimisation of a Markov policy: spatial branch and bound over boxes of
//! transition entries.
//!
//! A node is a box `lo ≤ α ≤ hi` on one support's entries (first tightened against the row
//! sums). Its lower bound on the worst-case loss is the larger of two valid bounds, both
//! resting on the fact that every capture probability is a polynomial with non-negative
//! coefficients in the entries ([`super::chain`]):
//! - the interval bound ([`super::chain::Chain::capture_upper`]), cheap and first order in the
//!   box width, and, when that cannot prune the box,
//! - the LP relaxation ([`super::relax`]), second order in the width and coupling all attacks
//!   through one policy.
//!
//! Every box also yields feasible policies (a point inside it and the relaxation's optimum),
//! whose exact loss updates the incumbent. Boxes are split at the midpoint of the entry that
//! contributes most to the relaxation's error, explored best first, and discarded once their
//! bound is within the tolerance of the incumbent. When the queue empties, the incumbent is
//! optimal up to the tolerance over every stationary Markov policy on every support searched.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::chain::Chain;
use super::local::LpStats;
use super::relax::relax;

/// What the branch and bound found.
pub(crate) struct Outcome {
    /// Index of the support holding the best policy.
    pub(crate) support: usize,
    /// The best policy's entries on that support.
    pub(crate) alpha: Vec<f64>,
    /// A certified lower bound on the loss of every Markov policy on every support searched.
    pub(crate) lower_bound: f64,
    /// Boxes evaluated.
    pub(crate) nodes: u64,
}

struct Node {
    bound: f64,
    order: u64,
    support: usize,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The entry to split.
    split: usize,
}

impl PartialEq for Node {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Node {
    /// Max-heap order: the smallest bound first, then the oldest node.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .bound
            .total_cmp(&self.bound)
            .then(other.order.cmp(&self.order))
    }
}

/// A box's evaluation.
struct Evaluated {
    bound: f64,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The best policy seen in the box and its exact loss.
    candidate: Vec<f64>,
    candidate_loss: f64,
    /// The entry to split if the box survives.
    split: Option<usize>,
}

/// Tightens a box against the row sums; `None` if no stochastic row fits.
fn tighten(chain: &Chain, lo: &mut [f64], hi: &mut [f64]) -> Option<()> {
    for i in 0..chain.rows() {
        let row = chain.row(i);
        let sum_lo: f64 = row.clone().map(|e| lo[e]).sum();
        let sum_hi: f64 = row.clone().map(|e| hi[e]).sum();
        if sum_lo > 1.0 + 1e-12 || sum_hi < 1.0 - 1e-12 {
            return None;
        }
        for e in row {
            let new_hi = hi[e].min(1.0 - (sum_lo - lo[e]));
            let new_lo = lo[e].max(1.0 - (sum_hi - hi[e]));
            hi[e] = new_hi.max(lo[e]);
            lo[e] = new_lo.min(hi[e]);
        }
    }
    Some(())
}

/// A stochastic point in the box: `lo` plus the missing mass spread in proportion to width.
fn feasible_point(chain: &Chain, lo: &[f64], hi: &[f64]) -> Vec<f64> {
    let mut x = lo.to_vec();
    for i in 0..chain.rows() {
        let row = chain.row(i);
        let sum_lo: f64 = row.clone().map(|e| lo[e]).sum();
        let slack: f64 = row.clone().map(|e| hi[e] - lo[e]).sum();
        if slack > 0.0 {
            for e in row.clone() {
                x[e] += (hi[e] - lo[e]) * (1.0 - sum_lo) / slack;
            }
        }
        let sum: f64 = row.clone().map(|e| x[e]).sum();
        for e in row {
            x[e] /= sum;
        }
    }
    x
}

/// Bounds a box: first the cheap interval bound, then, if that cannot prune it, the LP
/// relaxation, which also proposes a policy and the entry to split.
fn evaluate(
    chain: &Chain,
    mut lo: Vec<f64>,
    mut hi: Vec<f64>,
    best_loss: f64,
    tolerance: f64,
    stats: &mut LpStats,
    scratch: &mut Vec<f64>,
) -> Option<Evaluated> {
    tighten(chain, &mut lo, &mut hi)?;
    chain.capture_upper(&lo, &hi, scratch);
    let interval_bound = chain.loss_from(scratch);
    let point = feasible_point(chain, &lo, &hi);
    let point_loss = chain.loss(&point, scratch);
    let mut evaluated = Evaluated {
        bound: interval_bound,
        lo,
        hi,
        candidate: point,
        candidate_loss: point_loss,
        split: None,
    };
    // Nothing in the box can beat the better of the incumbent and this point.
    if interval_bound >= best_loss.min(point_loss) - tolerance {
        return Some(evaluated);
    }
    // If the LP solver fails on this box (microlp can hit a singular basis; Clarabel may report no optimum), keep the interval
    // bound and split the widest entry: still valid, only slower.
    let Ok(relaxation) = relax(
        chain,
        &evaluated.lo,
        &evaluated.hi,
        &evaluated.candidate,
        stats,
    ) else {
        stats.failures += 1;
        let width = |e: usize| evaluated.hi[e] - evaluated.lo[e];
        evaluated.split = (0..chain.entries())
            .filter(|&e| width(e) > 1e-12)
            .max_by(|&a, &b| width(a).total_cmp(&width(b)).then(b.cmp(&a)));
        return Some(evaluated);
    };
    evaluated.bound = interval_bound.max(relaxation.bound);
    let relaxed_loss = chain.loss(&relaxation.alpha, scratch);
    if relaxed_loss < evaluated.candidate_loss {
        evaluated.candidate = relaxation.alpha;
        evaluated.candidate_loss = relaxed_loss;
    }
    let width = |e: usize| evaluated.hi[e] - evaluated.lo[e];
    let free = (0..chain.entries()).filter(|&e| width(e) > 1e-12);
    // The entry contributing most to the relaxation error; ties (and an error-free
    // relaxation) go to the widest entry, then the lowest index.
    evaluated.split = free.max_by(|&a, &b| {
        relaxation.score[a]
            .total_cmp(&relaxation.score[b])
            .then(width(a).total_cmp(&width(b)))
            .then(b.cmp(&a))
    });
    Some(evaluated)
}

/// Branch and bound over all `chains` (one per candidate support), starting from the
/// incumbent `(support, alpha, loss)` (`support` may be `usize::MAX` for a policy found
/// elsewhere); stops when the gap is below `tolerance` or after `max_nodes` boxes.
pub(crate) fn branch_and_bound(
    chains: &[Chain],
    incumbent: (usize, Vec<f64>, f64),
    tolerance: f64,
    max_nodes: u64,
    stats: &mut LpStats,
) -> Outcome {
    let (mut best_support, mut best_alpha, mut best_loss) = incumbent;
    let mut heap = BinaryHeap::new();
    let mut order = 0u64;
    let mut nodes = 0u64;
    // The smallest bound of any box discarded (pruned, or a point).
    let mut discarded = f64::INFINITY;
    let mut scratch = Vec::new();
    let mut pending: Vec<(usize, Vec<f64>, Vec<f64>, f64)> = chains
        .iter()
        .enumerate()
        .map(|(s, c)| (s, vec![0.0; c.entries()], vec![1.0; c.entries()], 0.0))
        .collect();
    loop {
        for (support, lo, hi, parent_bound) in pending.drain(..) {
            nodes += 1;
            let chain = &chains[support];
            let Some(ev) = evaluate(chain, lo, hi, best_loss, tolerance, stats, &mut scratch)
            else {
                continue;
            };
            if ev.candidate_loss < best_loss {
                (best_support, best_alpha, best_loss) = (support, ev.candidate, ev.candidate_loss);
            }
            // A box's bound is also bounded by its parent's.
            let bound = ev.bound.max(parent_bound);
            match ev.split {
                Some(split) if bound < best_loss - tolerance => {
                    order += 1;
                    heap.push(Node {
                        bound,
                        order,
                        support,
                        lo: ev.lo,
                        hi: ev.hi,
                        split,
                    });
                }
                _ => discarded = discarded.min(bound),
            }
        }
        let Some(node) = heap.pop() else {
            break;
        };
        if node.bound >= best_loss - tolerance {
            // Best first: every remaining box is at least as bad.
            discarded = discarded.min(node.bound);
            heap.clear();
            break;
        }
        if nodes >= max_nodes {
            heap.push(node);
            break;
        }
        let e = node.split;
        let middle = 0.5 * (node.lo[e] + node.hi[e]);
        let (mut lower_hi, mut upper_lo) = (node.hi.clone(), node.lo.clone());
        lower_hi[e] = middle;
        upper_lo[e] = middle;
        pending.push((node.support, node.lo, lower_hi, node.bound));
        pending.push((node.support, upper_lo, node.hi, node.bound));
    }
    let open = heap.iter().map(|n| n.bound).fold(f64::INFINITY, f64::min);
    Outcome {
        support: best_support,
        alpha: best_alpha,
        lower_bound: best_loss.min(discarded).min(open),
        nodes,
    }
}
