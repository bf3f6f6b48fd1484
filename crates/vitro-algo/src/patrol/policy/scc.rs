//! Strongly connected components, for checking that a policy's chain is irreducible.

/// Strongly connected components of the graph on `0..count` given by `successors`
/// (Kosaraju, iterative): the component index of every vertex.
pub(super) fn strong_components(
    count: usize,
    successors: &dyn Fn(usize) -> Vec<usize>,
) -> Vec<usize> {
    // First pass: finishing order of a depth-first search.
    let mut seen = vec![false; count];
    let mut order = Vec::with_capacity(count);
    for root in 0..count {
        if seen[root] {
            continue;
        }
        seen[root] = true;
        let mut stack = vec![(root, successors(root), 0usize)];
        while let Some((v, next, i)) = stack.last_mut() {
            if let Some(&w) = next.get(*i) {
                *i += 1;
                if !seen[w] {
                    seen[w] = true;
                    let onward = successors(w);
                    stack.push((w, onward, 0));
                }
            } else {
                order.push(*v);
                stack.pop();
            }
        }
    }
    // Second pass: the reverse graph, in reverse finishing order.
    let mut reverse = vec![Vec::new(); count];
    for v in 0..count {
        for w in successors(v) {
            reverse[w].push(v);
        }
    }
    let mut component = vec![usize::MAX; count];
    let mut next_component = 0;
    for &root in order.iter().rev() {
        if component[root] != usize::MAX {
            continue;
        }
        component[root] = next_component;
        let mut stack = vec![root];
        while let Some(v) = stack.pop() {
            for &w in &reverse[v] {
                if component[w] == usize::MAX {
                    component[w] = next_component;
                    stack.push(w);
                }
            }
        }
        next_component += 1;
    }
    component
}
