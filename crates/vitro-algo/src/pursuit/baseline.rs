//! Baseline players: random walks, a greedy pursuer team and a fleeing evader.

use super::sim::{chase_step, flee_step, random_step};
use super::{EvaderStrategy, EvaderView, PursuerStrategy, PursuerView};
use crate::graph::NodeId;
use rand_chacha::ChaCha8Rng;

/// Every pursuer takes a uniformly random move (staying included).
#[derive(Clone, Copy, Debug, Default)]
pub struct RandomPursuers;

impl PursuerStrategy for RandomPursuers {
    fn choose(&mut self, view: &PursuerView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
        view.positions
            .iter()
            .map(|&p| random_step(view.arena, p, rng))
            .collect()
    }
}

/// Every pursuer steps along a shortest path towards the evader's most likely vertex (its
/// position when seen; otherwise the belief's mode). Ties are broken at random.
#[derive(Clone, Copy, Debug, Default)]
pub struct GreedyPursuers;

impl PursuerStrategy for GreedyPursuers {
    fn choose(&mut self, view: &PursuerView<'_>, rng: &mut ChaCha8Rng) -> Vec<NodeId> {
        let target = view.belief.most_likely();
        view.positions
            .iter()
            .map(|&p| match target {
                Some(t) => chase_step(view.arena, p, t, rng),
                None => p,
            })
            .collect()
    }
}

/// The evader takes a uniformly random move (staying included).
#[derive(Clone, Copy, Debug, Default)]
pub struct RandomEvader;

impl EvaderStrategy for RandomEvader {
    fn choose(&mut self, view: &EvaderView<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        random_step(view.arena, view.position, rng)
    }
}

/// The evader maximises its distance to the pursuers whose position it knows (seen, belief of
/// one vertex); with none known it walks at random.
#[derive(Clone, Copy, Debug, Default)]
pub struct FleeingEvader;

impl EvaderStrategy for FleeingEvader {
    fn choose(&mut self, view: &EvaderView<'_>, rng: &mut ChaCha8Rng) -> NodeId {
        let known: Vec<NodeId> = view
            .beliefs
            .iter()
            .filter(|b| b.size() == 1)
            .filter_map(|b| b.most_likely())
            .collect();
        flee_step(view.arena, view.position, &known, rng)
    }
}
