//! The run list: the full factorial of the varied levels (with an optional Latin-hypercube
//! sample as its last factor) times the replicates, in a fixed order, with one seed per run.
//!
//! Run `k` is always the same run: its levels come from `k` by mixed-radix counting (first
//! parameter slowest, replicates fastest) and its seed from the base seed and `k` alone
//! ([`seed_of`]), so neither the job count nor the shard changes what a run does.
//!
//! ```
//! use vitro_batch::design::{Design, Factor, Origin};
//! use vitro_batch::Value;
//! let loss = Factor { path: "channel.loss".into(), origin: Origin::List,
//!                     levels: vec![Value::Float(0.0), Value::Float(0.5)] };
//! let cars = Factor { path: "cars.count".into(), origin: Origin::Range,
//!                     levels: vec![Value::Int(2), Value::Int(4), Value::Int(6)] };
//! let d = Design::new(vec![loss, cars], None, 2, 7, false);
//! assert_eq!(d.runs(), Some(12));
//! let r = d.run(3).unwrap();   // point 1 (loss 0.0, 4 cars), replicate 1
//! assert_eq!((r.point, r.replicate), (1, 1));
//! assert_eq!(r.params[1], ("cars.count".to_string(), Value::Int(4)));
//! assert_eq!(r.seed, vitro_batch::design::seed_of(7, 3));
//! ```

use crate::value::Value;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Where a parameter's levels came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Origin {
    /// An explicit list.
    List,
    /// A range `{ start, stop, step }`.
    Range,
    /// A Latin-hypercube sample.
    LatinHypercube,
    /// Searched (`vitro search`): the levels are the range's ends, or its choices.
    Search,
}

/// One varied parameter and its levels.
#[derive(Clone, Debug, PartialEq)]
pub struct Factor {
    /// Dotted scenario key.
    pub path: String,
    /// Where the levels came from.
    pub origin: Origin,
    /// The levels, in order.
    pub levels: Vec<Value>,
}

/// An interval a Latin-hypercube samples a parameter over.
#[derive(Clone, Debug, PartialEq)]
pub struct Interval {
    /// Dotted scenario key.
    pub path: String,
    /// Lower bound.
    pub low: f64,
    /// Upper bound.
    pub high: f64,
    /// Round samples to integers (the scenario's value is an integer).
    pub integer: bool,
}

/// A Latin-hypercube sample: the sampled keys and one row of values per point.
#[derive(Clone, Debug, PartialEq)]
pub struct Hypercube {
    /// Dotted scenario keys.
    pub paths: Vec<String>,
    /// One row per point, one value per key.
    pub points: Vec<Vec<Value>>,
}

/// The runs of an experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// Factorial parameters, first varying slowest.
    pub factors: Vec<Factor>,
    /// The Latin-hypercube factor (varying fastest among the parameters), if any.
    pub hypercube: Option<Hypercube>,
    /// Runs per point.
    pub replicates: u32,
    /// Base seed.
    pub base_seed: u64,
    /// Seeds per replicate (common random numbers) instead of per run.
    pub common_random_numbers: bool,
}

/// One run: its number, point, replicate, seed and parameter levels.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Run number `k` (0-based).
    pub run: u64,
    /// The combination of levels (0-based), shared by its replicates.
    pub point: u64,
    /// Replicate number within the point (0-based).
    pub replicate: u32,
    /// The run's seed.
    pub seed: u64,
    /// (dotted key, level) of every varied parameter, factors first.
    pub params: Vec<(String, Value)>,
}

impl Design {
    /// A design from its factors and an optional hypercube of `samples` points over
    /// intervals, sampled from the base seed.
    pub fn new(
        factors: Vec<Factor>,
        hypercube: Option<(u32, Vec<Interval>)>,
        replicates: u32,
        base_seed: u64,
        common_random_numbers: bool,
    ) -> Self {
        let hypercube = hypercube.map(|(n, dims)| {
            let unit = latin_hypercube(n as usize, dims.len(), mix(base_seed ^ LHS_SALT));
            Hypercube {
                paths: dims.iter().map(|d| d.path.clone()).collect(),
                points: unit
                    .iter()
                    .map(|row| {
                        row.iter()
                            .zip(&dims)
                            .map(|(u, d)| {
                                let x = d.low + u * (d.high - d.low);
                                if d.integer {
                                    Value::Int(x.round() as i64)
                                } else {
                                    Value::Float(x)
                                }
                            })
                            .collect()
                    })
                    .collect(),
            }
        });
        Design {
            factors,
            hypercube,
            replicates,
            base_seed,
            common_random_numbers,
        }
    }

    /// Number of points (combinations of levels); `None` on overflow.
    pub fn points(&self) -> Option<u64> {
        let lhs = self.hypercube.as_ref().map_or(1, |h| h.points.len() as u64);
        self.factors
            .iter()
            .try_fold(lhs, |acc, f| acc.checked_mul(f.levels.len() as u64))
    }

    /// Number of runs; `None` on overflow.
    pub fn runs(&self) -> Option<u64> {
        self.points()?.checked_mul(u64::from(self.replicates))
    }

    /// The varied parameters' keys: factors, then sampled keys.
    pub fn parameter_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.factors.iter().map(|f| f.path.clone()).collect();
        if let Some(h) = &self.hypercube {
            names.extend(h.paths.iter().cloned());
        }
        names
    }

    /// Where each parameter's levels came from, in [`Design::parameter_names`] order.
    pub fn origins(&self) -> Vec<Origin> {
        let mut o: Vec<Origin> = self.factors.iter().map(|f| f.origin).collect();
        if let Some(h) = &self.hypercube {
            o.extend(h.paths.iter().map(|_| Origin::LatinHypercube));
        }
        o
    }

    /// The seed of run `k` with replicate `replicate`.
    pub fn seed(&self, k: u64, replicate: u32) -> u64 {
        if self.common_random_numbers {
            seed_of(self.base_seed, u64::from(replicate))
        } else {
            seed_of(self.base_seed, k)
        }
    }

    /// Run `k`, or `None` past the last run.
    pub fn run(&self, k: u64) -> Option<RunSpec> {
        if k >= self.runs()? {
            return None;
        }
        let reps = u64::from(self.replicates);
        let (point, replicate) = (k / reps, (k % reps) as u32);
        let mut rest = point;
        let mut params = Vec::new();
        if let Some(h) = &self.hypercube {
            let n = h.points.len() as u64;
            let row = &h.points[(rest % n) as usize];
            params.extend(h.paths.iter().cloned().zip(row.iter().cloned()));
            rest /= n;
        }
        for f in self.factors.iter().rev() {
            let n = f.levels.len() as u64;
            params.push((f.path.clone(), f.levels[(rest % n) as usize].clone()));
            rest /= n;
        }
        // Built fastest-first: put factors first (slowest first), then the sampled keys.
        let sampled = self.hypercube.as_ref().map_or(0, |h| h.paths.len());
        let mut ordered: Vec<(String, Value)> = params.split_off(sampled);
        ordered.reverse();
        ordered.extend(params);
        Some(RunSpec {
            run: k,
            point,
            replicate,
            seed: self.seed(k, replicate),
            params: ordered,
        })
    }
}

/// Salt separating the hypercube's random stream from the run seeds.
const LHS_SALT: u64 = 0x4c48_535f_7361_6d70;
const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output function: a stable 64-bit mix.
pub fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of run `k` of an experiment with base seed `base`: output `k` of SplitMix64
/// seeded with `base`. Stable across versions, machines, job counts and shards.
///
/// ```
/// use vitro_batch::design::seed_of;
/// assert_eq!(seed_of(0, 0), 0xe220a8397b1dcdaf); // SplitMix64's first output from 0
/// assert_ne!(seed_of(1, 0), seed_of(1, 1));
/// ```
pub fn seed_of(base: u64, k: u64) -> u64 {
    mix(base.wrapping_add(GOLDEN.wrapping_mul(k.wrapping_add(1))))
}

/// A SplitMix64 generator (for the hypercube and the search).
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(GOLDEN);
        mix(self.0)
    }
    /// Uniform in `[0, 1)` with 53 random bits.
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `0..n` (n > 0), without modulo bias.
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        let zone = u64::MAX - u64::MAX % n;
        loop {
            let x = self.next();
            if x < zone {
                return x % n;
            }
        }
    }
}

/// `n` points of a Latin hypercube in `[0, 1)^dims`: in every dimension each of the `n`
/// strata `[i/n, (i+1)/n)` holds exactly one point, at a uniform place within it.
pub fn latin_hypercube(n: usize, dims: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix(seed);
    let mut points = vec![vec![0.0; dims]; n];
    for d in 0..dims {
        let mut strata: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            let j = rng.below(i as u64 + 1) as usize;
            strata.swap(i, j);
        }
        for (p, s) in points.iter_mut().zip(strata) {
            p[d] = (s as f64 + rng.unit()) / n as f64;
        }
    }
    points
}

/// A share of the runs: shard `index` of `count` takes the runs with `k % count == index`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard (0-based).
    pub index: u64,
    /// Number of shards.
    pub count: u64,
}

impl Shard {
    /// The whole experiment.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Whether run `k` belongs to this shard.
    pub fn contains(self, k: u64) -> bool {
        k % self.count == self.index
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    /// `i/N` with `0 <= i < N`.
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("invalid shard `{s}`, expected i/N with 0 <= i < N (e.g. 0/4)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: u64 = i.trim().parse().map_err(|_| bad())?;
        let count: u64 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn factor(path: &str, levels: Vec<Value>) -> Factor {
        Factor {
            path: path.into(),
            origin: Origin::List,
            levels,
        }
    }

    #[test]
    fn factorial_order_first_slowest_replicates_fastest() {
        let a = factor("a", vec![Value::Int(1), Value::Int(2)]);
        let b = factor("b", vec!["x".into(), "y".into(), "z".into()]);
        let d = Design::new(vec![a, b], None, 2, 0, false);
        let seen: Vec<(i64, String, u32)> = (0..12)
            .map(|k| {
                let r = d.run(k).unwrap();
                let Value::Int(a) = r.params[0].1 else {
                    panic!()
                };
                (a, r.params[1].1.to_string(), r.replicate)
            })
            .collect();
        assert_eq!(seen[0], (1, "x".into(), 0));
        assert_eq!(seen[1], (1, "x".into(), 1));
        assert_eq!(seen[2], (1, "y".into(), 0));
        assert_eq!(seen[6], (2, "x".into(), 0));
        assert_eq!(seen[11], (2, "z".into(), 1));
        assert_eq!(d.run(12), None);
    }

    #[test]
    fn seeds_depend_on_base_and_run_only() {
        let d = Design::new(
            vec![factor("a", vec![Value::Int(1), Value::Int(2)])],
            None,
            3,
            9,
            false,
        );
        let seeds: Vec<u64> = (0..6).map(|k| d.run(k).unwrap().seed).collect();
        let mut unique = seeds.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), 6);
        assert_eq!(seeds[4], seed_of(9, 4));
        // Common random numbers: replicate r has the same seed at every point.
        let crn = Design {
            common_random_numbers: true,
            ..d
        };
        assert_eq!(crn.run(1).unwrap().seed, crn.run(4).unwrap().seed);
        assert_ne!(crn.run(0).unwrap().seed, crn.run(1).unwrap().seed);
    }

    #[test]
    fn hypercube_fills_every_stratum_once() {
        let n = 17;
        let pts = latin_hypercube(n, 3, 5);
        for d in 0..3 {
            let mut strata: Vec<usize> = pts.iter().map(|p| (p[d] * n as f64) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..n).collect::<Vec<_>>());
        }
        assert_eq!(pts, latin_hypercube(n, 3, 5));
        assert_ne!(pts, latin_hypercube(n, 3, 6));
    }

    #[test]
    fn hypercube_is_the_fastest_factor() {
        let a = factor("a", vec![Value::Int(1), Value::Int(2)]);
        let d = Design::new(
            vec![a],
            Some((
                3,
                vec![
                    Interval {
                        path: "x".into(),
                        low: 10.0,
                        high: 20.0,
                        integer: false,
                    },
                    Interval {
                        path: "n".into(),
                        low: 1.0,
                        high: 9.0,
                        integer: true,
                    },
                ],
            )),
            1,
            4,
            false,
        );
        assert_eq!(d.runs(), Some(6));
        assert_eq!(d.parameter_names(), ["a", "x", "n"]);
        let r0 = d.run(0).unwrap();
        let r1 = d.run(1).unwrap();
        let r3 = d.run(3).unwrap();
        assert_eq!(r0.params[0].1, Value::Int(1));
        assert_eq!(r1.params[0].1, Value::Int(1));
        assert_eq!(r3.params[0].1, Value::Int(2));
        assert_ne!(r0.params[1], r1.params[1]);
        assert_eq!(r0.params[1..], r3.params[1..]);
        let x = r0.params[1].1.as_f64().unwrap();
        assert!((10.0..20.0).contains(&x));
        assert!(matches!(r0.params[2].1, Value::Int(1..=9)));
    }

    #[test]
    fn shards_partition_the_runs() {
        let s: Shard = "1/3".parse().unwrap();
        assert_eq!(s, Shard { index: 1, count: 3 });
        assert!(s.contains(4) && !s.contains(3));
        for bad in ["3/3", "1", "a/2", "0/0", "-1/2"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
