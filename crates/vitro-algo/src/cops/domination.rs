//! Dominating sets: `k` cops on a dominating set catch the robber on their first move, so the
//! smallest `k` with a dominating set of size `k` bounds the cop number from above.

use crate::graph::{Graph, NodeId};

/// A dominating set of exactly `k` vertices (every vertex is in it or next to it), if one
/// exists, found by exhaustive search over `k`-subsets in lexicographic order.
///
/// Returns `None` without searching when there are more than `budget` subsets to try.
pub(crate) fn dominating_set(graph: &Graph, k: usize, budget: u64) -> Option<Vec<NodeId>> {
    let n = graph.node_count();
    if k > n || subsets(n, k) > budget {
        return None;
    }
    let words = n.div_ceil(64).max(1);
    let mut closed = vec![0u64; n * words];
    for v in 0..n {
        for &w in graph.neighbors(v).iter().chain(std::iter::once(&v)) {
            closed[v * words + w / 64] |= 1 << (w % 64);
        }
    }
    let mut full = vec![u64::MAX; words];
    if !n.is_multiple_of(64) {
        full[words - 1] = (1u64 << (n % 64)) - 1;
    }
    if n == 0 {
        full[0] = 0;
    }
    let mut chosen = Vec::with_capacity(k);
    // covered[d] = union of the closed neighbourhoods of the first d chosen vertices.
    let mut covered = vec![0u64; (k + 1) * words];
    search(&closed, &full, words, n, k, &mut chosen, &mut covered).then_some(chosen)
}

fn search(
    closed: &[u64],
    full: &[u64],
    words: usize,
    n: usize,
    k: usize,
    chosen: &mut Vec<NodeId>,
    covered: &mut [u64],
) -> bool {
    let depth = chosen.len();
    if depth == k {
        return covered[depth * words..(depth + 1) * words] == *full;
    }
    let first = chosen.last().map_or(0, |&v| v + 1);
    // Leave room for the remaining picks.
    for v in first..=(n - (k - depth)) {
        for w in 0..words {
            covered[(depth + 1) * words + w] = covered[depth * words + w] | closed[v * words + w];
        }
        chosen.push(v);
        if search(closed, full, words, n, k, chosen, covered) {
            return true;
        }
        chosen.pop();
    }
    false
}

/// C(n, k), saturating at `u64::MAX`.
fn subsets(n: usize, k: usize) -> u64 {
    if k > n {
        return 0;
    }
    let k = k.min(n - k);
    let mut result: u128 = 1;
    for i in 0..k {
        // result = C(n, i) here, so the division is exact.
        result = result * (n - i) as u128 / (i + 1) as u128;
        if result > u64::MAX as u128 {
            return u64::MAX;
        }
    }
    result as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;

    #[test]
    fn finds_dominating_sets_of_the_right_size() {
        let p = graph::petersen();
        assert!(dominating_set(&p, 2, u64::MAX).is_none());
        assert!(dominating_set(&p, 3, u64::MAX).is_some());
        let star = graph::tree(5, 1).unwrap();
        assert_eq!(dominating_set(&star, 1, u64::MAX), Some(vec![0]));
        let grid = graph::grid(3, 3).unwrap();
        assert!(dominating_set(&grid, 2, u64::MAX).is_none());
        assert!(dominating_set(&grid, 3, u64::MAX).is_some());
        assert!(dominating_set(&grid, 3, 10).is_none());
        assert_eq!(subsets(10, 3), 120);
        assert_eq!(subsets(5, 0), 1);
        assert_eq!(subsets(5, 5), 1);
    }
}
