//! The samplers of a search: uniform (the baseline) and the cross-entropy method (CEM,
//! Rubinstein 1999; de Boer et al. 2005), generation by generation.
//!
//! Every coordinate lives on its own scale: an ordered parameter (float or integer) as a
//! number in `[0, 1)` mapped linearly onto its range, a choice or a seed as an index. The
//! adaptive sampler keeps one independent model per coordinate: a normal law (truncated to
//! `[0, 1]`) for ordered ones, a categorical law for choices and seeds. After each
//! generation it ranks every evaluation so far (failures first, then by the guide metric),
//! takes the best `elite` share and moves each model toward them: the normal's mean and
//! spread toward the elites' (smoothed, with a floor on the spread so it keeps exploring),
//! the categorical's weights toward the elites' frequencies (smoothed, keeping a tenth of
//! the mass uniform, so new seeds keep coming). Generation 0 is uniform for both strategies,
//! drawn from the same stream: the two start from the same runs.
//!
//! Proposals depend only on the search seed, the generation and the results of earlier
//! generations, never on timing or thread count. A point already evaluated (same values) is
//! drawn again, so no evaluation repeats another.

use super::spec::Range;
use crate::design::{SplitMix, mix};
use crate::value::Value;
use std::cmp::Ordering;
use std::collections::{BTreeMap, BTreeSet};

/// Weight of the elites' statistics against the previous model's.
const SMOOTHING: f64 = 0.7;
/// Least spread of a normal model, in units of the range.
const SIGMA_MIN: f64 = 0.05;
/// Least mass a categorical model keeps on uniform draws.
const EXPLORE_MIN: f64 = 0.1;
/// Standard deviation of the uniform law on `[0, 1]`.
const SIGMA_UNIFORM: f64 = 0.288_675_134_594_812_9;
/// Salt of the proposal streams.
const SALT: u64 = 0x5345_4152_4348_5f31;

/// How proposals are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// The cross-entropy method.
    Adaptive,
    /// Uniform over the ranges, whatever came before.
    Random,
}

impl Strategy {
    /// `adaptive` or `random`.
    pub fn as_str(self) -> &'static str {
        match self {
            Strategy::Adaptive => "adaptive",
            Strategy::Random => "random",
        }
    }
}

impl std::str::FromStr for Strategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "adaptive" | "cem" => Ok(Strategy::Adaptive),
            "random" => Ok(Strategy::Random),
            _ => Err(format!(
                "unknown strategy `{s}`, expected adaptive or random"
            )),
        }
    }
}

/// One coordinate of a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coord {
    /// An ordered parameter, in `[0, 1]`.
    Unit(f64),
    /// A choice (index into the values) or a seed (offset from the range's low end).
    Index(u64),
}

/// The value of coordinate `c` of a parameter with range `r`.
pub fn value_of(r: &Range, c: Coord) -> Value {
    match (r, c) {
        (Range::Float { low, high }, Coord::Unit(u)) => Value::Float(low + u * (high - low)),
        (Range::Int { low, high }, Coord::Unit(u)) => {
            let n = (high - low + 1) as f64;
            Value::Int((low + (u * n).floor() as i64).min(*high))
        }
        (Range::Seed { low, high }, Coord::Index(i)) => {
            Value::Int(i64::try_from(low + i.min(high - low)).unwrap_or(i64::MAX))
        }
        (Range::Choice(v), Coord::Index(i)) => v[(i as usize).min(v.len() - 1)].clone(),
        // A coordinate of the other kind never comes from a sampler; map it to the low end.
        (Range::Float { low, .. }, _) => Value::Float(*low),
        (Range::Int { low, .. }, _) => Value::Int(*low),
        (Range::Seed { low, .. }, _) => Value::Int(i64::try_from(*low).unwrap_or(i64::MAX)),
        (Range::Choice(v), _) => v[0].clone(),
    }
}

/// How an evaluation ranks: failures first, then by score (larger better), then earlier.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rank {
    /// It is a failure.
    pub fails: bool,
    /// The guide metric, signed so that larger is better.
    pub score: f64,
    /// Its run number (ties go to the earlier run).
    pub run: u64,
}

impl Rank {
    /// Best first.
    fn order(&self, other: &Rank) -> Ordering {
        other
            .fails
            .cmp(&self.fails)
            .then(other.score.total_cmp(&self.score))
            .then(self.run.cmp(&other.run))
    }
}

#[derive(Clone, Debug)]
enum Model {
    /// Mean and spread on `[0, 1]`; `None` until the first update (uniform).
    Normal(Option<(f64, f64)>),
    /// Weights of some indices, the rest of the mass spread uniformly over `n` indices.
    Categorical {
        weights: BTreeMap<u64, f64>,
        uniform: f64,
        n: u64,
    },
}

/// Draws the points of a search, generation by generation.
#[derive(Clone, Debug)]
pub struct Sampler {
    strategy: Strategy,
    seed: u64,
    ranges: Vec<Range>,
    elite: f64,
    models: Vec<Model>,
    /// Every evaluated point with its rank.
    history: Vec<(Rank, Vec<Coord>)>,
    /// The values of every point proposed so far.
    seen: BTreeSet<String>,
}

impl Sampler {
    /// A sampler over `ranges` with search seed `seed`, steering by the best `elite` share.
    pub fn new(strategy: Strategy, seed: u64, ranges: Vec<Range>, elite: f64) -> Self {
        let models = ranges
            .iter()
            .map(|r| match r {
                Range::Float { .. } | Range::Int { .. } => Model::Normal(None),
                Range::Seed { low, high } => Model::Categorical {
                    weights: BTreeMap::new(),
                    uniform: 1.0,
                    n: (high - low).saturating_add(1),
                },
                Range::Choice(v) => Model::Categorical {
                    weights: BTreeMap::new(),
                    uniform: 1.0,
                    n: v.len() as u64,
                },
            })
            .collect();
        Sampler {
            strategy,
            seed,
            ranges,
            elite,
            models,
            history: Vec::new(),
            seen: BTreeSet::new(),
        }
    }

    /// The values of a point.
    pub fn values(&self, point: &[Coord]) -> Vec<Value> {
        self.ranges
            .iter()
            .zip(point)
            .map(|(r, &c)| value_of(r, c))
            .collect()
    }

    fn key(&self, point: &[Coord]) -> String {
        let v: Vec<String> = self.values(point).iter().map(Value::to_string).collect();
        v.join("\u{1f}")
    }

    /// The `count` points of generation `generation`.
    pub fn propose(&mut self, generation: u64, count: usize) -> Vec<Vec<Coord>> {
        let mut rng = SplitMix(mix(self.seed ^ SALT ^ mix(generation)));
        let mut out = Vec::with_capacity(count);
        for _ in 0..count {
            let mut point = self.draw(&mut rng);
            // A repeat of an earlier point teaches nothing: draw again (a few times).
            for _ in 0..64 {
                if !self.seen.contains(&self.key(&point)) {
                    break;
                }
                point = self.draw(&mut rng);
            }
            self.seen.insert(self.key(&point));
            out.push(point);
        }
        out
    }

    fn draw(&self, rng: &mut SplitMix) -> Vec<Coord> {
        let adaptive = self.strategy == Strategy::Adaptive;
        self.models
            .iter()
            .map(|m| match m {
                Model::Normal(Some((mu, sigma))) if adaptive => {
                    Coord::Unit(truncated_normal(rng, *mu, *sigma))
                }
                Model::Normal(_) => Coord::Unit(rng.unit()),
                Model::Categorical {
                    weights,
                    uniform,
                    n,
                } => {
                    let u = rng.unit();
                    if !adaptive || u < *uniform || weights.is_empty() {
                        return Coord::Index(rng.below((*n).max(1)));
                    }
                    let mut left = u - uniform;
                    for (&i, &w) in weights {
                        if left < w {
                            return Coord::Index(i);
                        }
                        left -= w;
                    }
                    // Rounding left a sliver: the last weighted index.
                    Coord::Index(weights.keys().next_back().copied().unwrap_or(0))
                }
            })
            .collect()
    }

    /// Takes in the evaluations of one generation: each point with its rank (`None`: the run
    /// failed to run, and steers nothing); then refits the models.
    pub fn observe(&mut self, evaluated: Vec<(Vec<Coord>, Option<Rank>)>) {
        for (point, rank) in evaluated {
            if let Some(rank) = rank {
                self.history.push((rank, point));
            }
        }
        if self.strategy == Strategy::Random || self.history.is_empty() {
            return;
        }
        self.history.sort_by(|a, b| a.0.order(&b.0));
        let k = ((self.elite * self.history.len() as f64).ceil() as usize)
            .clamp(2.min(self.history.len()), self.history.len());
        let elites: Vec<&Vec<Coord>> = self.history[..k].iter().map(|(_, p)| p).collect();
        for (d, model) in self.models.iter_mut().enumerate() {
            match model {
                Model::Normal(fit) => {
                    let xs: Vec<f64> = elites
                        .iter()
                        .filter_map(|p| match p[d] {
                            Coord::Unit(u) => Some(u),
                            Coord::Index(_) => None,
                        })
                        .collect();
                    let n = xs.len().max(1) as f64;
                    let mean = xs.iter().sum::<f64>() / n;
                    let sd =
                        libm::sqrt(xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n);
                    let (mu0, s0) = fit.unwrap_or((0.5, SIGMA_UNIFORM));
                    let mu = SMOOTHING * mean + (1.0 - SMOOTHING) * mu0;
                    let sigma = (SMOOTHING * sd + (1.0 - SMOOTHING) * s0).max(SIGMA_MIN);
                    *fit = Some((mu, sigma));
                }
                Model::Categorical {
                    weights, uniform, ..
                } => {
                    for w in weights.values_mut() {
                        *w *= 1.0 - SMOOTHING;
                    }
                    *uniform *= 1.0 - SMOOTHING;
                    let share = SMOOTHING / elites.len() as f64;
                    for p in &elites {
                        if let Coord::Index(i) = p[d] {
                            *weights.entry(i).or_insert(0.0) += share;
                        }
                    }
                    weights.retain(|_, w| *w >= 1e-4);
                    let total: f64 = weights.values().sum();
                    let keep = (1.0 - EXPLORE_MIN).min(total);
                    if total > 0.0 {
                        for w in weights.values_mut() {
                            *w *= keep / total;
                        }
                    }
                    *uniform = 1.0 - keep;
                }
            }
        }
    }

    /// The mean and spread of each ordered coordinate's model (`None` for choices and seeds,
    /// or before the first update): for reports and tests.
    pub fn normals(&self) -> Vec<Option<(f64, f64)>> {
        self.models
            .iter()
            .map(|m| match m {
                Model::Normal(fit) => *fit,
                Model::Categorical { .. } => None,
            })
            .collect()
    }
}

/// A normal draw truncated to `[0, 1]` (rejection, then clamping after 32 tries).
fn truncated_normal(rng: &mut SplitMix, mu: f64, sigma: f64) -> f64 {
    for _ in 0..32 {
        // Box–Muller with libm, so the draws are the same on every machine.
        let u1 = 1.0 - rng.unit();
        let u2 = rng.unit();
        let z = libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(std::f64::consts::TAU * u2);
        let x = mu + sigma * z;
        if (0.0..=1.0).contains(&x) {
            return x;
        }
    }
    mu.clamp(0.0, 1.0)
}

#[cfg(test)]
#[path = "cem_tests.rs"]
mod tests;
