//! Monte-Carlo evaluation of a policy: every attack option played many times.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::{Instance, PatrolError, Policy};
use crate::graph::NodeId;

/// Settings for [`monte_carlo`].
#[derive(Clone, Debug, PartialEq)]
pub struct MonteCarloOptions {
    /// Simulated attacks per attack option (target × phase × start vertex). Default 20 000.
    pub trials: u32,
    /// Master seed; attack option `i` draws from stream `i` of a ChaCha8 generator.
    pub seed: u64,
    /// Simultaneous confidence level of all the intervals together. Default 0.99.
    pub confidence: f64,
}

impl Default for MonteCarloOptions {
    fn default() -> Self {
        MonteCarloOptions {
            trials: 20_000,
            seed: 0,
            confidence: 0.99,
        }
    }
}

/// The estimated outcome of one attack option.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AttackEstimate {
    /// Index of the target in [`Instance::targets`](crate::patrol::Instance::targets).
    pub target: usize,
    /// The phase of the schedule period when the attack starts.
    pub phase: usize,
    /// The patroller's vertex when the attack starts.
    pub from: NodeId,
    /// Attacks simulated.
    pub trials: u32,
    /// Attacks caught.
    pub captures: u32,
    /// `captures / trials`.
    pub capture_probability: f64,
    /// Confidence interval for the capture probability.
    pub interval: (f64, f64),
}

/// The result of [`monte_carlo`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MonteCarloReport {
    /// One estimate per attack option, by target, phase, then support vertex.
    pub attacks: Vec<AttackEstimate>,
    /// Estimated policy value: the largest `value_t · (1 − estimate)`.
    pub value: f64,
    /// Confidence interval for the policy value (holds together with the attack intervals).
    pub value_interval: (f64, f64),
}

/// Plays `policy` against every attack option: for each target, phase and support vertex,
/// starts the patroller there and counts how often it stands on the target's (possibly moving)
/// vertex within the deadline.
///
/// The intervals are Hoeffding intervals with a Bonferroni split over the attack options, so
/// with probability at least `confidence` every true capture probability (and hence the true
/// value) lies in its interval at once; they need no normal approximation and stay valid at
/// probabilities 0 and 1.
///
/// # Errors
/// [`PatrolError::InvalidPolicy`] if the policy does not fit the graph or period,
/// [`PatrolError::InvalidInstance`] for bad options.
pub fn monte_carlo(
    instance: &Instance,
    policy: &Policy,
    options: &MonteCarloOptions,
) -> Result<MonteCarloReport, PatrolError> {
    if options.trials == 0 || !(options.confidence > 0.0 && options.confidence < 1.0) {
        return Err(PatrolError::InvalidInstance(
            "Monte-Carlo needs at least one trial and a confidence in (0, 1)".into(),
        ));
    }
    // Validates the policy against the graph and period.
    let exact = policy.attacks(instance)?;
    let options_count = exact.len();
    let delta = (1.0 - options.confidence) / options_count as f64;
    let half_width = libm::sqrt(libm::log(2.0 / delta) / (2.0 * f64::from(options.trials)));
    let mut attacks = Vec::with_capacity(options_count);
    let (mut value, mut value_lo, mut value_hi) = (0.0f64, 0.0f64, 0.0f64);
    for option in &exact {
        let (t, phase, from) = (option.target, option.phase, option.from);
        let target = &instance.targets[t];
        let worth = target.value;
        let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
        rng.set_stream(attacks.len() as u64);
        let mut captures = 0u32;
        for _ in 0..options.trials {
            let mut at = from;
            for s in 1..=target.deadline as usize {
                let u = rng.random::<f64>();
                at = policy.next_at(at, phase + s - 1, u).unwrap_or(at);
                if Some(at) == target.position.at(phase + s) {
                    captures += 1;
                    break;
                }
            }
        }
        let p = f64::from(captures) / f64::from(options.trials);
        let interval = ((p - half_width).max(0.0), (p + half_width).min(1.0));
        value = value.max(worth * (1.0 - p));
        value_lo = value_lo.max(worth * (1.0 - interval.1));
        value_hi = value_hi.max(worth * (1.0 - interval.0));
        attacks.push(AttackEstimate {
            target: t,
            phase,
            from,
            trials: options.trials,
            captures,
            capture_probability: p,
            interval,
        });
    }
    Ok(MonteCarloReport {
        attacks,
        value,
        value_interval: (value_lo, value_hi),
    })
}
