//! Many episodes: capture rate with its interval, capture time, time in sight.

use super::super::{Arena, PursuitError};
use super::{GameEvader, TeamStrategy, play_game};
use crate::graph::NodeId;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The Wilson score interval at 95 % for `successes` out of `trials` (`(0, 1)` for none).
pub fn wilson_interval(successes: usize, trials: usize) -> (f64, f64) {
    if trials == 0 {
        return (0.0, 1.0);
    }
    let z = 1.959_963_984_540_054_f64;
    let n = trials as f64;
    let p = successes as f64 / n;
    let denom = 1.0 + z * z / n;
    let centre = (p + z * z / (2.0 * n)) / denom;
    let half = z * libm::sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / denom;
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// What [`evaluate`] measured.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct EvalSummary {
    /// Episodes played.
    pub episodes: usize,
    /// Episodes ending in capture.
    pub captures: usize,
    /// `captures / episodes`.
    pub capture_rate: f64,
    /// Its 95 % Wilson interval.
    pub capture_rate_ci95: (f64, f64),
    /// Mean round of capture over the captures (`None` without one).
    pub mean_capture_round: Option<f64>,
    /// Mean over episodes of the fraction of rounds played with the evader in sight.
    pub mean_in_sight: f64,
    /// True if the pursuers' information set held the truth in every round of every episode.
    pub truth_in_belief: bool,
}

/// Plays `episodes` episodes of at most `rounds` rounds with `pursuers` pursuers. Episode `i`
/// draws its own stream from `seed`: the pursuers start on distinct random vertices (on the
/// same vertex if there are fewer vertices than pursuers), then the evader places itself.
/// `team` and `evader` make fresh players for each episode.
///
/// # Errors
/// As [`play_game`]; [`PursuitError::NoPursuers`] for `pursuers == 0`.
pub fn evaluate(
    arena: &Arena,
    pursuers: usize,
    episodes: usize,
    rounds: u32,
    seed: u64,
    team: &mut dyn FnMut() -> Box<dyn TeamStrategy>,
    evader: &mut dyn FnMut() -> Box<dyn GameEvader>,
) -> Result<EvalSummary, PursuitError> {
    if pursuers == 0 {
        return Err(PursuitError::NoPursuers);
    }
    let n = arena.node_count();
    let (mut captures, mut capture_rounds, mut sight) = (0usize, 0u64, 0.0);
    let mut truth = true;
    for episode in 0..episodes {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(episode as u64);
        let mut starts: Vec<NodeId> = Vec::with_capacity(pursuers);
        while starts.len() < pursuers {
            let v = rng.random_range(0..n);
            if !starts.contains(&v) || n < pursuers {
                starts.push(v);
            }
        }
        let out = play_game(
            arena,
            &starts,
            team().as_mut(),
            evader().as_mut(),
            rounds,
            &mut rng,
        )?;
        if let Some(t) = out.captured_at {
            captures += 1;
            capture_rounds += u64::from(t);
        }
        sight += f64::from(out.rounds_in_sight) / f64::from(out.rounds.max(1));
        truth &= out.truth_in_belief;
    }
    Ok(EvalSummary {
        episodes,
        captures,
        capture_rate: captures as f64 / episodes.max(1) as f64,
        capture_rate_ci95: wilson_interval(captures, episodes),
        mean_capture_round: (captures > 0).then(|| capture_rounds as f64 / captures as f64),
        mean_in_sight: sight / episodes.max(1) as f64,
        truth_in_belief: truth,
    })
}
