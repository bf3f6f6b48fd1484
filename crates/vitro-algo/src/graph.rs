//! Simple undirected graphs: edge-list loading with line/column errors, and named generators.
//!
//! Vertices are the integers `0..n`. The edge-list text format is one edge `u v` per line;
//! a line holding a single integer declares a vertex (so isolated vertices can be written);
//! `#` starts a comment that runs to the end of the line; blank lines are ignored. The vertex
//! count is the largest id mentioned plus one, so ids that never appear are isolated vertices.
//! Self-loops are accepted and dropped (in the games built on these graphs a player may always
//! stay put), and repeated edges are merged.
//!
//! ```
//! use vitro_algo::graph::{self, Graph};
//!
//! let g = Graph::parse_edge_list("# a triangle\n0 1\n1 2\n2 0\n")?;
//! assert_eq!((g.node_count(), g.edge_count()), (3, 3));
//! assert_eq!(graph::cycle(3)?.edges().collect::<Vec<_>>(), g.edges().collect::<Vec<_>>());
//! # Ok::<(), vitro_algo::graph::GraphError>(())
//! ```

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

/// A vertex of a [`Graph`], an index in `0..node_count()`.
pub type NodeId = usize;

/// The largest vertex count a [`Graph`] may have (guards against a typo such as `1 10000000000`
/// allocating gigabytes).
pub const MAX_NODES: usize = 1 << 24;

/// Errors from building, loading or generating a [`Graph`].
#[derive(Debug, thiserror::Error)]
pub enum GraphError {
    /// The edge-list text is malformed at the given 1-based line and column.
    #[error("line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// 1-based column (in characters) where the offending token starts.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// An edge names a vertex outside `0..node_count`.
    #[error("edge ({u}, {v}) names a vertex outside 0..{node_count}")]
    NodeOutOfRange {
        /// One end.
        u: NodeId,
        /// The other end.
        v: NodeId,
        /// The graph's vertex count.
        node_count: usize,
    },
    /// A vertex list names the same vertex twice.
    #[error("vertex {0} is listed twice")]
    DuplicateNode(NodeId),
    /// The requested graph would have more than [`MAX_NODES`] vertices.
    #[error("graph too large: {nodes} vertices requested, at most {MAX_NODES} allowed")]
    TooLarge {
        /// The vertex count asked for (saturated on overflow).
        nodes: usize,
    },
}

/// An undirected simple graph on vertices `0..n`, stored as sorted adjacency lists.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Graph {
    adjacency: Vec<Vec<NodeId>>,
    edge_count: usize,
}

impl Graph {
    /// Builds a graph on `node_count` vertices from edges; self-loops are dropped and repeated
    /// edges merged.
    ///
    /// ```
    /// let g = vitro_algo::graph::Graph::from_edges(4, &[(0, 1), (1, 0), (2, 2)])?;
    /// assert_eq!(g.edge_count(), 1);
    /// assert!(g.neighbors(3).is_empty());
    /// # Ok::<(), vitro_algo::graph::GraphError>(())
    /// ```
    pub fn from_edges(node_count: usize, edges: &[(NodeId, NodeId)]) -> Result<Graph, GraphError> {
        if node_count > MAX_NODES {
            return Err(GraphError::TooLarge { nodes: node_count });
        }
        let mut adjacency = vec![Vec::new(); node_count];
        for &(u, v) in edges {
            if u >= node_count || v >= node_count {
                return Err(GraphError::NodeOutOfRange { u, v, node_count });
            }
            if u != v {
                adjacency[u].push(v);
                adjacency[v].push(u);
            }
        }
        let mut twice = 0;
        for list in &mut adjacency {
            list.sort_unstable();
            list.dedup();
            twice += list.len();
        }
        Ok(Graph {
            adjacency,
            edge_count: twice / 2,
        })
    }

    /// Parses the edge-list text format described in the [module docs](self).
    pub fn parse_edge_list(text: &str) -> Result<Graph, GraphError> {
        let mut edges = Vec::new();
        let mut node_count = 0usize;
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let content = raw.split('#').next().unwrap_or("");
            let tokens = tokens_with_columns(content);
            let ids = tokens
                .iter()
                .map(|&(column, token)| parse_id(token, line, column))
                .collect::<Result<Vec<_>, _>>()?;
            match ids.as_slice() {
                [] => {}
                [v] => node_count = node_count.max(v + 1),
                [u, v] => {
                    node_count = node_count.max(u.max(v) + 1);
                    edges.push((*u, *v));
                }
                [_, _, ..] => {
                    return Err(GraphError::Parse {
                        line,
                        column: tokens[2].0,
                        message: "expected `u v` (two vertex ids) or a single vertex id".into(),
                    });
                }
            }
        }
        Graph::from_edges(node_count, &edges)
    }

    /// Reads and parses an edge-list file (see [`Graph::parse_edge_list`]).
    pub fn load(path: impl AsRef<Path>) -> Result<Graph, GraphError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| GraphError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Graph::parse_edge_list(&text)
    }

    /// Number of vertices.
    pub fn node_count(&self) -> usize {
        self.adjacency.len()
    }

    /// Number of (undirected) edges.
    pub fn edge_count(&self) -> usize {
        self.edge_count
    }

    /// The neighbours of `v`, sorted ascending (without `v` itself).
    ///
    /// # Panics
    /// If `v` is not a vertex of the graph.
    pub fn neighbors(&self, v: NodeId) -> &[NodeId] {
        &self.adjacency[v]
    }

    /// Whether `u` and `v` are joined by an edge (false when either is not a vertex).
    pub fn has_edge(&self, u: NodeId, v: NodeId) -> bool {
        self.adjacency
            .get(u)
            .is_some_and(|list| list.binary_search(&v).is_ok())
    }

    /// Every edge once, as `(u, v)` with `u < v`, in ascending order.
    pub fn edges(&self) -> impl Iterator<Item = (NodeId, NodeId)> + '_ {
        self.adjacency.iter().enumerate().flat_map(|(u, list)| {
            list.iter()
                .copied()
                .filter(move |&v| u < v)
                .map(move |v| (u, v))
        })
    }

    /// The connected components, each sorted ascending, ordered by their smallest vertex.
    pub fn components(&self) -> Vec<Vec<NodeId>> {
        let mut seen = vec![false; self.node_count()];
        let mut components = Vec::new();
        for start in 0..self.node_count() {
            if seen[start] {
                continue;
            }
            seen[start] = true;
            let mut component = vec![start];
            let mut queue = VecDeque::from([start]);
            while let Some(u) = queue.pop_front() {
                for &v in &self.adjacency[u] {
                    if !seen[v] {
                        seen[v] = true;
                        component.push(v);
                        queue.push_back(v);
                    }
                }
            }
            component.sort_unstable();
            components.push(component);
        }
        components
    }

    /// The subgraph induced by `nodes`, relabelled so that `nodes[i]` becomes vertex `i`.
    ///
    /// # Errors
    /// [`GraphError::NodeOutOfRange`] if a vertex is not in the graph,
    /// [`GraphError::DuplicateNode`] if a vertex is listed twice.
    pub fn induced_subgraph(&self, nodes: &[NodeId]) -> Result<Graph, GraphError> {
        let mut index = vec![usize::MAX; self.node_count()];
        for (i, &v) in nodes.iter().enumerate() {
            if v >= self.node_count() {
                return Err(GraphError::NodeOutOfRange {
                    u: v,
                    v,
                    node_count: self.node_count(),
                });
            }
            if index[v] != usize::MAX {
                return Err(GraphError::DuplicateNode(v));
            }
            index[v] = i;
        }
        let mut edges = Vec::new();
        for (i, &u) in nodes.iter().enumerate() {
            for &v in &self.adjacency[u] {
                if index[v] != usize::MAX && i < index[v] {
                    edges.push((i, index[v]));
                }
            }
        }
        Graph::from_edges(nodes.len(), &edges)
    }

    /// Breadth-first distances from `source`; `None` for unreachable vertices.
    ///
    /// # Panics
    /// If `source` is not a vertex of the graph.
    pub fn distances_from(&self, source: NodeId) -> Vec<Option<usize>> {
        let mut dist = vec![None; self.node_count()];
        dist[source] = Some(0);
        let mut queue = VecDeque::from([(source, 0)]);
        while let Some((u, d)) = queue.pop_front() {
            for &v in &self.adjacency[u] {
                if dist[v].is_none() {
                    dist[v] = Some(d + 1);
                    queue.push_back((v, d + 1));
                }
            }
        }
        dist
    }

    /// The edge-list text of this graph (readable by [`Graph::parse_edge_list`]); isolated
    /// vertices are written as single ids.
    pub fn to_edge_list(&self) -> String {
        let mut out = String::new();
        for (v, list) in self.adjacency.iter().enumerate() {
            if list.is_empty() {
                out.push_str(&format!("{v}\n"));
            }
        }
        for (u, v) in self.edges() {
            out.push_str(&format!("{u} {v}\n"));
        }
        out
    }
}

fn tokens_with_columns(content: &str) -> Vec<(usize, &str)> {
    let mut tokens = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte offset, column)
    for (column0, (offset, ch)) in content.char_indices().enumerate() {
        if ch.is_whitespace() {
            if let Some((begin, column)) = start.take() {
                tokens.push((column, &content[begin..offset]));
            }
        } else if start.is_none() {
            start = Some((offset, column0 + 1));
        }
    }
    if let Some((begin, column)) = start {
        tokens.push((column, &content[begin..]));
    }
    tokens
}

fn parse_id(token: &str, line: usize, column: usize) -> Result<NodeId, GraphError> {
    let id: NodeId = token.parse().map_err(|_| GraphError::Parse {
        line,
        column,
        message: format!("`{token}` is not a vertex id (a non-negative integer)"),
    })?;
    if id >= MAX_NODES {
        return Err(GraphError::Parse {
            line,
            column,
            message: format!("vertex id {id} is too large (at most {})", MAX_NODES - 1),
        });
    }
    Ok(id)
}

fn checked_nodes(nodes: Option<usize>) -> Result<usize, GraphError> {
    match nodes {
        Some(n) if n <= MAX_NODES => Ok(n),
        Some(n) => Err(GraphError::TooLarge { nodes: n }),
        None => Err(GraphError::TooLarge { nodes: usize::MAX }),
    }
}

/// The path `0 - 1 - ... - (n-1)`.
pub fn path(n: usize) -> Result<Graph, GraphError> {
    let n = checked_nodes(Some(n))?;
    let edges: Vec<_> = (1..n).map(|v| (v - 1, v)).collect();
    Graph::from_edges(n, &edges)
}

/// The cycle `C_n` on `0..n` (for `n < 3` this is the path on `n` vertices).
pub fn cycle(n: usize) -> Result<Graph, GraphError> {
    let n = checked_nodes(Some(n))?;
    let mut edges: Vec<_> = (1..n).map(|v| (v - 1, v)).collect();
    if n >= 3 {
        edges.push((n - 1, 0));
    }
    Graph::from_edges(n, &edges)
}

/// The complete graph `K_n`.
pub fn complete(n: usize) -> Result<Graph, GraphError> {
    let n = checked_nodes(Some(n))?;
    let edges: Vec<_> = (0..n)
        .flat_map(|u| (u + 1..n).map(move |v| (u, v)))
        .collect();
    Graph::from_edges(n, &edges)
}

/// The `rows × cols` grid graph; vertex `r * cols + c` sits at row `r`, column `c`.
pub fn grid(rows: usize, cols: usize) -> Result<Graph, GraphError> {
    let n = checked_nodes(rows.checked_mul(cols))?;
    let mut edges = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let v = r * cols + c;
            if c + 1 < cols {
                edges.push((v, v + 1));
            }
            if r + 1 < rows {
                edges.push((v, v + cols));
            }
        }
    }
    Graph::from_edges(n, &edges)
}

/// The complete `arity`-ary tree of the given `height` (a single root has height 0), numbered
/// breadth first: the children of `v` are `arity*v + 1 ..= arity*v + arity`.
///
/// `tree(2, 3)` has 15 vertices, like `data/graphs/tree_balanced_2_3.edges`.
pub fn tree(arity: usize, height: u32) -> Result<Graph, GraphError> {
    // 1 + a + a^2 + ... + a^h vertices.
    let mut n = Some(1usize);
    let mut level = Some(1usize);
    for _ in 0..height {
        level = level.and_then(|l| l.checked_mul(arity));
        n = n.and_then(|total| level.and_then(|l| total.checked_add(l)));
    }
    let n = checked_nodes(n)?;
    let edges: Vec<_> = (1..n).map(|v| ((v - 1) / arity, v)).collect();
    Graph::from_edges(n, &edges)
}

/// The hypercube `Q_d` on `2^d` vertices; vertices are adjacent when their ids differ in one bit.
pub fn hypercube(dimension: u32) -> Result<Graph, GraphError> {
    let n = checked_nodes(1usize.checked_shl(dimension))?;
    let mut edges = Vec::new();
    for v in 0..n {
        for bit in 0..dimension {
            let w = v ^ (1 << bit);
            if v < w {
                edges.push((v, w));
            }
        }
    }
    Graph::from_edges(n, &edges)
}

/// The Petersen graph (10 vertices, 15 edges, girth 5): outer cycle `0..5`, inner pentagram
/// `5..10`, spokes `i - (i + 5)`.
pub fn petersen() -> Graph {
    let mut edges = Vec::new();
    for i in 0..5 {
        edges.push((i, (i + 1) % 5));
        edges.push((i, i + 5));
        edges.push((5 + i, 5 + (i + 2) % 5));
    }
    generalized_petersen(10, &edges)
}

/// The dodecahedron (20 vertices, 30 edges, 3-regular, girth 5): the generalized Petersen
/// graph `GP(10, 2)`.
pub fn dodecahedron() -> Graph {
    let mut edges = Vec::new();
    for i in 0..10 {
        edges.push((i, (i + 1) % 10));
        edges.push((i, i + 10));
        edges.push((10 + i, 10 + (i + 2) % 10));
    }
    generalized_petersen(20, &edges)
}

fn generalized_petersen(n: usize, edges: &[(NodeId, NodeId)]) -> Graph {
    // Every id is below `n` by construction, so `from_edges` cannot fail; fall back to the
    // empty graph rather than panic if that invariant were ever broken.
    Graph::from_edges(n, edges).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_reports_line_and_column() {
        let err = Graph::parse_edge_list("0 1\n\n  1 x2\n").unwrap_err();
        match err {
            GraphError::Parse { line, column, .. } => assert_eq!((line, column), (3, 5)),
            other => panic!("unexpected {other:?}"),
        }
        let err = Graph::parse_edge_list("0 1 2\n").unwrap_err();
        assert!(matches!(
            err,
            GraphError::Parse {
                line: 1,
                column: 5,
                ..
            }
        ));
    }

    #[test]
    fn parse_handles_comments_isolated_vertices_and_loops() {
        let g = Graph::parse_edge_list("# header\n0 1 # trailing\n1 1\n4\n1 0\n").unwrap();
        assert_eq!(g.node_count(), 5);
        assert_eq!(g.edge_count(), 1);
        assert_eq!(g.components().len(), 4);
        let again = Graph::parse_edge_list(&g.to_edge_list()).unwrap();
        assert_eq!(again, g);
    }

    #[test]
    fn generators_have_the_expected_sizes() {
        let sizes = |g: Graph| (g.node_count(), g.edge_count());
        assert_eq!(sizes(path(6).unwrap()), (6, 5));
        assert_eq!(sizes(cycle(8).unwrap()), (8, 8));
        assert_eq!(sizes(cycle(2).unwrap()), (2, 1));
        assert_eq!(sizes(complete(6).unwrap()), (6, 15));
        assert_eq!(sizes(grid(4, 4).unwrap()), (16, 24));
        assert_eq!(sizes(tree(2, 3).unwrap()), (15, 14));
        assert_eq!(sizes(hypercube(4).unwrap()), (16, 32));
        assert_eq!(sizes(petersen()), (10, 15));
        assert_eq!(sizes(dodecahedron()), (20, 30));
        assert!(matches!(hypercube(80), Err(GraphError::TooLarge { .. })));
        assert!(matches!(
            grid(usize::MAX, 2),
            Err(GraphError::TooLarge { .. })
        ));
    }

    #[test]
    fn regular_graphs_are_regular() {
        for g in [petersen(), dodecahedron(), hypercube(3).unwrap()] {
            for v in 0..g.node_count() {
                assert_eq!(g.neighbors(v).len(), 3);
            }
            assert_eq!(g.components().len(), 1);
        }
    }

    #[test]
    fn induced_subgraph_and_distances() {
        let g = cycle(6).unwrap();
        let sub = g.induced_subgraph(&[4, 5, 0]).unwrap();
        assert_eq!(sub.edges().collect::<Vec<_>>(), vec![(0, 1), (1, 2)]);
        let d = g.distances_from(0);
        assert_eq!(d[3], Some(3));
        let two = Graph::from_edges(3, &[(0, 1)]).unwrap();
        assert_eq!(two.distances_from(0)[2], None);
    }
}
