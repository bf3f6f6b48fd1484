//! Strongly connected components of a directed graph, on petgraph's Tarjan.
//!
//! The components are numbered by their lowest vertex (the component of vertex 0 is 0, the
//! next vertex of another component opens component 1, ...), so the numbering depends only
//! on the graph, not on the order the search found them in.
//!
//! ```
//! use vitro_algo::scc::strong_components;
//!
//! // 0 -> 1 -> 2 -> 0 is a cycle; 3 only leads into it; 4 has a loop of its own.
//! let arcs = [(0, 1), (1, 2), (2, 0), (3, 0), (4, 4)];
//! assert_eq!(strong_components(5, arcs), [0, 0, 0, 1, 2]);
//! ```

use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};

/// The component of every vertex of the directed graph on `0..count` whose arcs are `arcs`
/// (arcs naming a vertex outside `0..count` are left out), numbered by lowest vertex.
pub fn strong_components(
    count: usize,
    arcs: impl IntoIterator<Item = (usize, usize)>,
) -> Vec<usize> {
    let mut g = DiGraph::<(), (), usize>::with_capacity(count, 0);
    for _ in 0..count {
        g.add_node(());
    }
    for (u, v) in arcs {
        if u < count && v < count {
            g.add_edge(NodeIndex::new(u), NodeIndex::new(v), ());
        }
    }
    let mut found = vec![usize::MAX; count];
    for (c, members) in tarjan_scc(&g).iter().enumerate() {
        for v in members {
            found[v.index()] = c;
        }
    }
    // Renumber by lowest vertex.
    let mut number = vec![usize::MAX; count];
    let mut next = 0;
    found
        .iter()
        .map(|&c| {
            if number[c] == usize::MAX {
                number[c] = next;
                next += 1;
            }
            number[c]
        })
        .collect()
}

/// Membership of the largest strongly connected component (ties to the one with the lowest
/// vertex), as in [`strong_components`].
pub fn largest_component(
    count: usize,
    arcs: impl IntoIterator<Item = (usize, usize)>,
) -> Vec<bool> {
    let component = strong_components(count, arcs);
    let mut sizes = Vec::new();
    for &c in &component {
        if c == sizes.len() {
            sizes.push(0usize);
        }
        sizes[c] += 1;
    }
    // The first of the largest: components are in order of their lowest vertex.
    let best = sizes
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(&a.0)))
        .map(|(c, _)| c);
    component.iter().map(|&c| Some(c) == best).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_of_a_chain_of_cycles() {
        // Two 2-cycles joined one way, then a sink.
        let arcs = [(2, 3), (3, 2), (0, 1), (1, 0), (1, 2), (3, 4)];
        assert_eq!(strong_components(5, arcs), [0, 0, 1, 1, 2]);
        // Ties between the two 2-cycles go to the one with vertex 0.
        assert_eq!(
            largest_component(5, arcs),
            [true, true, false, false, false]
        );
        assert!(strong_components(0, []).is_empty());
        assert!(largest_component(0, []).is_empty());
    }
}
