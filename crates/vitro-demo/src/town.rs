//! The street graph: a town-like grid of junctions with some diagonal streets and a few
//! missing blocks, generated deterministically from the scenario and a random stream.

use crate::config::TownConfig;
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use vitro::env::{GraphStorage, NodeId};

/// A junction: a node of the street graph, at (x, y) metres east and north of the south-west
/// corner.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Junction {
    /// Metres east.
    pub x: f64,
    /// Metres north.
    pub y: f64,
}

/// A street between two junctions (stored once per direction).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Street {
    /// True for a diagonal street across a block.
    pub diagonal: bool,
}

/// The street graph storage.
pub type Streets = GraphStorage<Junction, Street>;

/// Generates the town of `cfg`, drawing from `rng` (use a named stream of the simulation).
///
/// Junctions sit on a `columns × rows` grid, `block_m` apart, numbered row by row from the
/// south-west. `missing_blocks` junctions at odd (column, row) are left out with their streets
/// (none of them touch, so the town stays connected), and a share `diagonal_share` of the
/// blocks whose four corners remain gets one diagonal street, in a random direction.
///
/// ```
/// use rand::SeedableRng;
/// use vitro_demo::config::TownConfig;
/// use vitro_demo::town::generate;
/// let cfg = TownConfig { columns: 5, rows: 4, block_m: 100.0, diagonal_share: 0.0, missing_blocks: 2 };
/// let town = generate(&cfg, &mut rand_chacha::ChaCha8Rng::seed_from_u64(1));
/// assert_eq!(town.node_count(), 5 * 4 - 2);
/// ```
pub fn generate(cfg: &TownConfig, rng: &mut impl Rng) -> Streets {
    let (cols, rows) = (cfg.columns as usize, cfg.rows as usize);
    let mut present = vec![true; cols * rows];
    // Candidates for missing blocks: inner junctions at odd (column, row), shuffled.
    let mut candidates: Vec<(usize, usize)> = (1..cols.saturating_sub(1))
        .step_by(2)
        .flat_map(|c| (1..rows.saturating_sub(1)).step_by(2).map(move |r| (c, r)))
        .collect();
    for i in (1..candidates.len()).rev() {
        let j = rng.random_range(0..=i);
        candidates.swap(i, j);
    }
    for &(c, r) in candidates.iter().take(cfg.missing_blocks as usize) {
        present[r * cols + c] = false;
    }

    let mut town = Streets::default();
    let mut ids: Vec<Option<NodeId>> = vec![None; cols * rows];
    for r in 0..rows {
        for c in 0..cols {
            if present[r * cols + c] {
                ids[r * cols + c] = Some(town.add_node(Junction {
                    x: c as f64 * cfg.block_m,
                    y: r as f64 * cfg.block_m,
                }));
            }
        }
    }
    let at = |c: usize, r: usize| ids[r * cols + c];
    let straight = Street { diagonal: false };
    for r in 0..rows {
        for c in 0..cols {
            let Some(a) = at(c, r) else { continue };
            if let Some(b) = (c + 1 < cols).then(|| at(c + 1, r)).flatten() {
                town.add_undirected_edge(a, b, cfg.block_m, straight);
            }
            if let Some(b) = (r + 1 < rows).then(|| at(c, r + 1)).flatten() {
                town.add_undirected_edge(a, b, cfg.block_m, straight);
            }
        }
    }
    let diagonal_m = cfg.block_m * std::f64::consts::SQRT_2;
    for r in 0..rows.saturating_sub(1) {
        for c in 0..cols.saturating_sub(1) {
            // Two draws per block whatever happens, so one block's outcome never shifts the
            // numbers the next one sees.
            let u: f64 = rng.random();
            let rising: bool = rng.random();
            let corners = (at(c, r), at(c + 1, r), at(c, r + 1), at(c + 1, r + 1));
            let (Some(sw), Some(se), Some(nw), Some(ne)) = corners else {
                continue;
            };
            if u < cfg.diagonal_share {
                let (a, b) = if rising { (sw, ne) } else { (se, nw) };
                town.add_undirected_edge(a, b, diagonal_m, Street { diagonal: true });
            }
        }
    }
    town
}

#[derive(PartialEq)]
struct Frontier(f64, u32);
impl Eq for Frontier {}
impl Ord for Frontier {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on distance, ties by node id: deterministic.
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}
impl PartialOrd for Frontier {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Shortest distances from several sources, each with a starting offset (e.g. a car halfway
/// along a street starts at the street's end with the rest of the street as offset).
/// Unreachable junctions get `f64::INFINITY`.
pub fn distances<N, E>(g: &GraphStorage<N, E>, sources: &[(NodeId, f64)]) -> Vec<f64> {
    let mut dist = vec![f64::INFINITY; g.node_count()];
    let mut heap = BinaryHeap::new();
    for &(s, d0) in sources {
        match dist.get_mut(s.0 as usize) {
            Some(d) if d0 < *d => {
                *d = d0;
                heap.push(Frontier(d0, s.0));
            }
            _ => {}
        }
    }
    while let Some(Frontier(d, u)) = heap.pop() {
        if d > dist[u as usize] {
            continue;
        }
        for (v, len, _) in g.neighbors(NodeId(u)) {
            let nd = d + len;
            if nd < dist[v.0 as usize] {
                dist[v.0 as usize] = nd;
                heap.push(Frontier(nd, v.0));
            }
        }
    }
    dist
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn cfg(diagonal_share: f64, missing_blocks: u32) -> TownConfig {
        TownConfig {
            columns: 9,
            rows: 7,
            block_m: 100.0,
            diagonal_share,
            missing_blocks,
        }
    }

    #[test]
    fn same_seed_same_town_other_seed_other_town() {
        let c = cfg(0.3, 5);
        let a = generate(&c, &mut ChaCha8Rng::seed_from_u64(1));
        let b = generate(&c, &mut ChaCha8Rng::seed_from_u64(1));
        let d = generate(&c, &mut ChaCha8Rng::seed_from_u64(2));
        assert_eq!(a.digest(), b.digest());
        assert_ne!(a.digest(), d.digest());
    }

    #[test]
    fn full_grid_has_the_grid_streets() {
        let t = generate(&cfg(0.0, 0), &mut ChaCha8Rng::seed_from_u64(0));
        assert_eq!(t.node_count(), 63);
        // 8*7 horizontal + 9*6 vertical streets, both directions.
        assert_eq!(t.edge_count(), 2 * (8 * 7 + 9 * 6));
        let all = generate(&cfg(1.0, 0), &mut ChaCha8Rng::seed_from_u64(0));
        assert_eq!(all.edge_count(), 2 * (8 * 7 + 9 * 6 + 8 * 6));
    }

    #[test]
    fn missing_blocks_keep_the_town_connected() {
        let c = cfg(0.2, c_max());
        fn c_max() -> u32 {
            cfg(0.0, 0).max_missing_blocks()
        }
        for seed in 0..20 {
            let t = generate(&c, &mut ChaCha8Rng::seed_from_u64(seed));
            assert_eq!(t.node_count(), 63 - 12);
            let d = distances(&t, &[(NodeId(0), 0.0)]);
            assert!(d.iter().all(|x| x.is_finite()), "seed {seed}");
        }
    }

    #[test]
    fn distances_with_offsets() {
        let t = generate(&cfg(0.0, 0), &mut ChaCha8Rng::seed_from_u64(0));
        let d = distances(&t, &[(NodeId(1), 30.0)]);
        assert_eq!(d[1], 30.0);
        assert_eq!(d[0], 130.0);
        assert_eq!(d[10], 130.0); // one row up from junction 1
        assert_eq!(d[62], 30.0 + 100.0 * (7.0 + 6.0));
    }
}
