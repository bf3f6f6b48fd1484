//! Summary statistics for the plots and the conditioned replicates: means with Student-t
//! confidence intervals, Wilson intervals for rates, histogram bins.

/// Mean of a sample with its two-sided 95% confidence interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanCi {
    /// Sample size.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Lower bound (the mean itself when `n < 2`).
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

/// Mean and 95% CI (`mean ± t(0.975, n-1) · s / √n`) of the finite values of `xs`;
/// `None` if there is none.
///
/// ```
/// use vitro_batch::stats::mean_ci;
/// let m = mean_ci(&[1.0, 2.0, 3.0]).unwrap();
/// assert_eq!(m.mean, 2.0);
/// assert!((m.hi - (2.0 + 4.303 / 3f64.sqrt())).abs() < 1e-3);
/// ```
pub fn mean_ci(xs: &[f64]) -> Option<MeanCi> {
    let v: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
    let n = v.len();
    if n == 0 {
        return None;
    }
    let mean = v.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return Some(MeanCi {
            n,
            mean,
            lo: mean,
            hi: mean,
        });
    }
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let half = t975(n - 1) * (var / n as f64).sqrt();
    Some(MeanCi {
        n,
        mean,
        lo: mean - half,
        hi: mean + half,
    })
}

/// The 0.975 quantile of Student's t with `df` degrees of freedom (exact table to 30, then
/// a Cornish–Fisher expansion, good to 1e-4).
pub fn t975(df: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281, 2.2010,
        2.1788, 2.1604, 2.1448, 2.1314, 2.1199, 2.1098, 2.1009, 2.0930, 2.0860, 2.0796, 2.0739,
        2.0687, 2.0639, 2.0595, 2.0555, 2.0518, 2.0484, 2.0452, 2.0423,
    ];
    if (1..=30).contains(&df) {
        return TABLE[df - 1];
    }
    let z: f64 = 1.959_964;
    let v = df.max(1) as f64;
    z + (z.powi(3) + z) / (4.0 * v)
        + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * v * v)
        + (3.0 * z.powi(7) + 19.0 * z.powi(5) + 17.0 * z.powi(3) - 15.0 * z) / (384.0 * v.powi(3))
}

/// A rate `k / n` with its 95% Wilson score interval; `None` if `n == 0`.
///
/// ```
/// use vitro_batch::stats::wilson;
/// let r = wilson(10, 10).unwrap();
/// assert_eq!(r.mean, 1.0);
/// assert!((r.lo - 0.7225).abs() < 1e-3 && r.hi > 0.9999);
/// ```
pub fn wilson(k: usize, n: usize) -> Option<MeanCi> {
    if n == 0 {
        return None;
    }
    let (k, nf) = (k.min(n) as f64, n as f64);
    let z: f64 = 1.959_964;
    let p = k / nf;
    let denom = 1.0 + z * z / nf;
    let centre = (p + z * z / (2.0 * nf)) / denom;
    let half = z / denom * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt();
    Some(MeanCi {
        n,
        mean: p,
        lo: (centre - half).max(0.0),
        hi: (centre + half).min(1.0),
    })
}

/// Equal-width bins over the finite values: `(edges, counts)` with `counts.len() + 1`
/// edges; about √n bins (5 to 30). Empty input gives no bins.
pub fn histogram(xs: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let v: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        let pad = if lo == 0.0 { 0.5 } else { lo.abs() * 0.05 };
        (lo - pad, hi + pad)
    };
    let bins = ((v.len() as f64).sqrt().ceil() as usize).clamp(5, 30);
    let width = (hi - lo) / bins as f64;
    let edges: Vec<f64> = (0..=bins).map(|i| lo + i as f64 * width).collect();
    let mut counts = vec![0; bins];
    for x in v {
        let i = (((x - lo) / width) as usize).min(bins - 1);
        counts[i] += 1;
    }
    (edges, counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles() {
        assert_eq!(t975(1), 12.7062);
        assert!((t975(40) - 2.0211).abs() < 2e-4, "{}", t975(40));
        assert!((t975(120) - 1.9799).abs() < 2e-4, "{}", t975(120));
        assert!((t975(100_000) - 1.96).abs() < 1e-3);
    }

    #[test]
    fn mean_ci_edge_cases() {
        assert_eq!(mean_ci(&[]), None);
        assert_eq!(mean_ci(&[f64::NAN]), None);
        let one = mean_ci(&[4.0, f64::NAN]).unwrap();
        assert_eq!((one.n, one.lo, one.hi), (1, 4.0, 4.0));
        let same = mean_ci(&[2.0; 5]).unwrap();
        assert_eq!((same.lo, same.hi), (2.0, 2.0));
    }

    #[test]
    fn wilson_interval() {
        assert_eq!(wilson(0, 0), None);
        let r = wilson(5, 10).unwrap();
        assert!(
            (r.lo - 0.2366).abs() < 1e-3 && (r.hi - 0.7634).abs() < 1e-3,
            "{r:?}"
        );
    }

    #[test]
    fn histogram_counts_everything() {
        let xs: Vec<f64> = (0..100).map(f64::from).collect();
        let (edges, counts) = histogram(&xs);
        assert_eq!(counts.len(), 10);
        assert_eq!(edges.len(), 11);
        assert_eq!(counts.iter().sum::<usize>(), 100);
        let (_, c) = histogram(&[3.0, 3.0]);
        assert_eq!(c.iter().sum::<usize>(), 2);
    }
}
