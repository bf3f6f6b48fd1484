//! Candidate supports (connected vertex sets) and a quick bound for each.

use super::chain::Chain;
use crate::graph::{Graph, NodeId};

/// Every connected vertex set of `graph` (each ascending), or `None` if there are more than
/// `limit`. Each set is produced once, grown from its smallest vertex by exclusive
/// neighbourhoods (Wernicke's ESU scheme).
pub(crate) fn connected(graph: &Graph, limit: usize) -> Option<Vec<Vec<NodeId>>> {
    let n = graph.node_count();
    let mut out = Vec::new();
    let mut in_set = vec![false; n];
    // How many set members each vertex is adjacent to (0 = not yet in the neighbourhood).
    let mut touching = vec![0u32; n];
    let mut set = Vec::new();
    for root in 0..n {
        let ext: Vec<NodeId> = graph
            .neighbors(root)
            .iter()
            .copied()
            .filter(|&w| w > root)
            .collect();
        add(graph, root, &mut set, &mut in_set, &mut touching);
        let ok = extend(
            graph,
            root,
            &mut set,
            ext,
            &mut in_set,
            &mut touching,
            &mut out,
            limit,
        );
        remove(graph, root, &mut set, &mut in_set, &mut touching);
        if !ok {
            return None;
        }
    }
    for s in &mut out {
        s.sort_unstable();
    }
    Some(out)
}

fn add(graph: &Graph, v: NodeId, set: &mut Vec<NodeId>, in_set: &mut [bool], touching: &mut [u32]) {
    set.push(v);
    in_set[v] = true;
    for &w in graph.neighbors(v) {
        touching[w] += 1;
    }
}

fn remove(
    graph: &Graph,
    v: NodeId,
    set: &mut Vec<NodeId>,
    in_set: &mut [bool],
    touching: &mut [u32],
) {
    set.pop();
    in_set[v] = false;
    for &w in graph.neighbors(v) {
        touching[w] -= 1;
    }
}

#[allow(clippy::too_many_arguments)]
fn extend(
    graph: &Graph,
    root: NodeId,
    set: &mut Vec<NodeId>,
    mut ext: Vec<NodeId>,
    in_set: &mut [bool],
    touching: &mut [u32],
    out: &mut Vec<Vec<NodeId>>,
    limit: usize,
) -> bool {
    if out.len() >= limit {
        return false;
    }
    out.push(set.clone());
    while let Some(w) = ext.pop() {
        // Exclusive neighbours of w: above the root, outside the set, not yet adjacent to it,
        // and not already waiting in ext.
        let mut next = ext.clone();
        for &u in graph.neighbors(w) {
            if u > root && !in_set[u] && touching[u] == 0 && !ext.contains(&u) {
                next.push(u);
            }
        }
        add(graph, w, set, in_set, touching);
        let ok = extend(graph, root, set, next, in_set, touching, out, limit);
        remove(graph, w, set, in_set, touching);
        if !ok {
            return false;
        }
    }
    true
}

/// A lower bound on the loss of every policy on `chain`'s support: an attack is never caught
/// if, at every step `s` of it, the target's vertex is outside the support or farther (within
/// the support) from the attack's start than `s` steps.
pub(crate) fn unreachable_loss(chain: &Chain) -> f64 {
    let n = chain.len();
    // Breadth-first distances inside the support (moves are symmetric), from every vertex.
    let dist: Vec<Vec<usize>> = (0..n)
        .map(|source| {
            let mut dist = vec![usize::MAX; n];
            dist[source] = 0;
            let mut queue = std::collections::VecDeque::from([source]);
            while let Some(x) = queue.pop_front() {
                for e in chain.row(x) {
                    let y = chain.to[e];
                    if dist[y] == usize::MAX {
                        dist[y] = dist[x] + 1;
                        queue.push_back(y);
                    }
                }
            }
            dist
        })
        .collect();
    let mut worst: f64 = 0.0;
    for target in &chain.targets {
        let escapes = (0..chain.period).any(|phase| {
            (0..n).any(|h| {
                (1..=target.deadline).all(|s| {
                    target.local[(phase + s) % chain.period].is_none_or(|at| dist[h][at] > s)
                })
            })
        });
        if escapes {
            worst = worst.max(target.value);
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;

    fn count(g: &Graph) -> usize {
        connected(g, usize::MAX).map_or(0, |s| s.len())
    }

    #[test]
    fn counts_connected_sets() {
        // Paths: n(n+1)/2 intervals; cycles: n(n-1) + 1; complete: 2^n - 1.
        assert_eq!(count(&graph::path(5).unwrap()), 15);
        assert_eq!(count(&graph::cycle(5).unwrap()), 21);
        assert_eq!(count(&graph::complete(5).unwrap()), 31);
        // The star K_{1,3}: 3 leaves alone + any non-empty leaf set with the centre + the centre.
        assert_eq!(count(&graph::tree(3, 1).unwrap()), 3 + 8);
        let sets = connected(&graph::petersen(), usize::MAX).unwrap();
        let mut sorted = sets.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), sets.len());
        assert!(connected(&graph::petersen(), 100).is_none());
    }
}
