//! Shared move rules for the baselines and the searches' simulations.

use super::Arena;
use crate::graph::NodeId;
use rand::Rng;

/// A uniformly random move from `from` (staying included).
pub(crate) fn random_step(arena: &Arena, from: NodeId, rng: &mut impl Rng) -> NodeId {
    let moves = arena.moves(from);
    moves[rng.random_range(0..moves.len())]
}

/// The move from `from` that best satisfies `key` (largest wins); ties broken uniformly at
/// random by reservoir sampling, so the choice depends only on the RNG and the ascending move
/// order.
fn best_step(
    arena: &Arena,
    from: NodeId,
    rng: &mut impl Rng,
    mut key: impl FnMut(NodeId) -> i64,
) -> NodeId {
    let mut best = from;
    let mut best_key = i64::MIN;
    let mut ties = 0u32;
    for &v in arena.moves(from) {
        let k = key(v);
        if k > best_key {
            best = v;
            best_key = k;
            ties = 1;
        } else if k == best_key {
            ties += 1;
            if rng.random_range(0..ties) == 0 {
                best = v;
            }
        }
    }
    best
}

/// A step along a shortest path towards `target` (staying if already there).
pub(crate) fn chase_step(
    arena: &Arena,
    from: NodeId,
    target: NodeId,
    rng: &mut impl Rng,
) -> NodeId {
    let bits = arena.toward(from, target);
    if bits == 0 {
        return best_step(arena, from, rng, |v| -i64::from(arena.dist(target, v)));
    }
    // Uniform among the shortest-path moves (as `best_step` breaks ties).
    let mut k = rng.random_range(0..bits.count_ones());
    let mut rest = bits;
    loop {
        let i = rest.trailing_zeros();
        if k == 0 {
            return arena.moves(from)[i as usize];
        }
        k -= 1;
        rest &= rest - 1;
    }
}

/// A step that maximises the distance to the nearest threat, then the total distance.
pub(crate) fn flee_step(
    arena: &Arena,
    from: NodeId,
    threats: &[NodeId],
    rng: &mut impl Rng,
) -> NodeId {
    if threats.is_empty() {
        return random_step(arena, from, rng);
    }
    best_step(arena, from, rng, |v| {
        let mut nearest = i64::MAX;
        let mut total = 0i64;
        for &t in threats {
            let d = i64::from(arena.dist(t, v));
            nearest = nearest.min(d);
            total += d;
        }
        // Adjacent to a pursuer is nearly as bad as sharing its vertex.
        nearest * 1024 + total.min(1023)
    })
}

/// The pursuers' heuristic value of a non-terminal position, in `[0, 1]`: 1 when a pursuer
/// is next to the evader, falling linearly with the nearest pursuer's distance (to 0 at
/// `scale` hops), with a smaller share for the mean distance.
pub(crate) fn closeness(arena: &Arena, pursuers: &[NodeId], evader: NodeId, scale: f64) -> f64 {
    let mut nearest = f64::MAX;
    let mut total = 0.0;
    for &p in pursuers {
        let d = f64::from(arena.dist(p, evader)).min(scale);
        nearest = nearest.min(d);
        total += d;
    }
    let mean = total / pursuers.len().max(1) as f64;
    let near = 1.0 - (nearest - 1.0).max(0.0) / scale;
    let all = 1.0 - mean / scale;
    (0.75 * near + 0.25 * all).clamp(0.0, 1.0)
}
