//! Plots of a result directory (feature `plot`), each as PNG and SVG:
//!
//! - `METRIC-vs-PARAM`: every kept numeric (or boolean, as 0/1) metric against every varied
//!   parameter: the mean over the runs at each level with its 95% confidence interval
//!   (Student t). With exactly two swept parameters, one line per level of the other;
//!   otherwise the other parameters are pooled. A Latin-hypercube parameter gets one dot per
//!   design point (mean over its replicates) instead of a line.
//! - `hist-METRIC`: the distribution of a metric over all successful runs.
//! - `success-rate-vs-PARAM`: for each categorical (string or boolean) parameter, the share of
//!   successful runs per level with its 95% Wilson interval. Success is a boolean metric
//!   (`success` if kept, or the one named) or else the run's status.
//!
//! Failed runs are left out of the metric plots (the note under each title says how many).

mod draw;
mod error;
mod scatter;
mod search;
pub use crate::stats;
pub use scatter::{Scatter, plot_residuals, plot_scatter};
pub use search::{SearchCurves, plot_search_curves};

use crate::design::Origin;
use crate::journal::{self, RunRecord, Status};
use crate::manifest::{Manifest, ParamInfo};
use crate::value::Value;
use draw::{CategoryChart, Chart, HistChart, Line, XyChart};
pub use error::PlotError;
use stats::{MeanCi, mean_ci, wilson};
use std::path::{Path, PathBuf};

/// What to plot.
#[derive(Clone, Debug, Default)]
pub struct PlotOptions {
    /// Metrics to plot against the parameters (empty: every numeric kept metric).
    pub metrics: Vec<String>,
    /// Metrics to draw histograms of (empty: the same as `metrics`).
    pub histograms: Vec<String>,
    /// Boolean metric that says whether a run succeeded (default: `success` if kept, else
    /// the run's status).
    pub success: Option<String>,
}

/// Plots the results in `dir` into `out` (created); returns the files written.
pub fn plot_dir(dir: &Path, out: &Path, opts: &PlotOptions) -> Result<Vec<PathBuf>, PlotError> {
    let manifest = Manifest::load(dir)?.ok_or_else(|| PlotError::NotResults(dir.to_owned()))?;
    let mut records = journal::read(dir)?.records;
    records.sort_by_key(|r| r.run);
    let charts = charts(&manifest, &records, opts)?;
    std::fs::create_dir_all(out).map_err(|e| PlotError::Draw {
        path: out.to_owned(),
        message: e.to_string(),
    })?;
    let mut files = Vec::new();
    for (name, chart) in charts {
        files.extend(draw::save(&chart, &out.join(sanitize(&name)))?);
    }
    Ok(files)
}

/// Every chart of a result set, with its file stem.
fn charts(
    m: &Manifest,
    records: &[RunRecord],
    opts: &PlotOptions,
) -> Result<Vec<(String, Chart)>, PlotError> {
    let kept = &m.keep.metrics;
    for name in opts.metrics.iter().chain(&opts.histograms) {
        if !kept.contains(name) {
            return Err(PlotError::UnknownMetric {
                name: name.clone(),
                kept: kept.join(", "),
            });
        }
    }
    let ok: Vec<&RunRecord> = records.iter().filter(|r| r.status == Status::Ok).collect();
    let failed = records.len() - ok.len();
    let numeric = |name: &String| {
        ok.iter()
            .any(|r| r.metrics.get(name).and_then(number).is_some())
    };
    let metrics: Vec<&String> = if opts.metrics.is_empty() {
        kept.iter().filter(|n| numeric(n)).collect()
    } else {
        opts.metrics.iter().collect()
    };
    let hists: Vec<&String> = if opts.histograms.is_empty() {
        metrics.clone()
    } else {
        opts.histograms.iter().collect()
    };
    let left_out = if failed > 0 {
        format!(
            "; {failed} failed run{} left out",
            if failed == 1 { "" } else { "s" }
        )
    } else {
        String::new()
    };

    let mut out = Vec::new();
    for metric in &metrics {
        for p in &m.parameters {
            let chart = if categorical(p) {
                category_means(m, p, metric, &ok, &left_out)
            } else if matches!(p.origin, Origin::LatinHypercube | Origin::Search) {
                Chart::Xy(hypercube_dots(m, p, metric, &ok, &left_out))
            } else {
                Chart::Xy(level_lines(m, p, metric, &ok, &left_out))
            };
            out.push((format!("{metric}-vs-{}", p.path), chart));
        }
    }
    for metric in hists {
        let xs: Vec<f64> = ok
            .iter()
            .filter_map(|r| r.metrics.get(metric).and_then(number))
            .collect();
        let (edges, counts) = stats::histogram(&xs);
        out.push((
            format!("hist-{metric}"),
            Chart::Hist(HistChart {
                title: format!("Distribution of {metric}"),
                x_desc: metric.to_string(),
                note: format!("{} runs{left_out}", xs.len()),
                mean: mean_ci(&xs).map(|s| s.mean),
                edges,
                counts,
            }),
        ));
    }
    let success = success_of(m, records, opts)?;
    for p in m.parameters.iter().filter(|p| categorical(p)) {
        let items = p
            .levels
            .iter()
            .map(|level| {
                let at: Vec<bool> = records
                    .iter()
                    .zip(&success)
                    .filter(|(r, _)| r.params.get(&p.path) == Some(level))
                    .map(|(_, s)| *s)
                    .collect();
                wilson(at.iter().filter(|s| **s).count(), at.len())
            })
            .collect();
        out.push((
            format!("success-rate-vs-{}", p.path),
            Chart::Category(CategoryChart {
                title: format!("Success rate by {}", p.path),
                x_desc: p.path.clone(),
                y_desc: "success rate".into(),
                note: match success_name(m, records, opts) {
                    Some(name) => {
                        format!("share of runs whose `{name}` is true, 95% Wilson interval")
                    }
                    None => "share of runs that ended without error, 95% Wilson interval".into(),
                },
                categories: p.levels.iter().map(Value::to_string).collect(),
                items,
                bars: true,
            }),
        ));
    }
    Ok(out)
}

/// A metric value as a number (booleans as 0 and 1).
fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Bool(b) => Some(f64::from(u8::from(*b))),
        v => v.as_f64(),
    }
}

/// Whether a parameter's levels are strings or booleans.
fn categorical(p: &ParamInfo) -> bool {
    p.levels
        .iter()
        .any(|v| matches!(v, Value::Text(_) | Value::Bool(_)))
}

/// Values of `metric` in the runs matching `filter`.
fn values(ok: &[&RunRecord], metric: &str, filter: impl Fn(&RunRecord) -> bool) -> Vec<f64> {
    ok.iter()
        .filter(|r| filter(r))
        .filter_map(|r| r.metrics.get(metric).and_then(number))
        .collect()
}

/// Mean ± CI of `metric` per level of swept parameter `p`; one line per level of the other
/// swept parameter when there are exactly two (and no hypercube), else pooled.
fn level_lines(
    m: &Manifest,
    p: &ParamInfo,
    metric: &str,
    ok: &[&RunRecord],
    left_out: &str,
) -> XyChart {
    let others: Vec<&ParamInfo> = m.parameters.iter().filter(|q| q.path != p.path).collect();
    let group = match others.as_slice() {
        [g] if matches!(g.origin, Origin::List | Origin::Range) && g.levels.len() <= 8 => Some(*g),
        _ => None,
    };
    let line = |label: Option<String>, filter: &dyn Fn(&RunRecord) -> bool| Line {
        label,
        connect: true,
        points: p
            .levels
            .iter()
            .filter_map(|level| {
                let x = level.as_f64()?;
                let xs = values(ok, metric, |r| {
                    r.params.get(&p.path) == Some(level) && filter(r)
                });
                Some((x, mean_ci(&xs)?))
            })
            .collect(),
    };
    let (lines, how) = match group {
        Some(g) => (
            g.levels
                .iter()
                .map(|gl| {
                    line(Some(format!("{} = {gl}", g.path)), &|r: &RunRecord| {
                        r.params.get(&g.path) == Some(gl)
                    })
                })
                .collect(),
            format!("{} replicates per point", m.replicates),
        ),
        None if others.is_empty() => (
            vec![line(None, &|_| true)],
            format!("{} replicates per point", m.replicates),
        ),
        None => (
            vec![line(None, &|_| true)],
            format!(
                "pooled over {}",
                others
                    .iter()
                    .map(|q| q.path.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ),
    };
    XyChart {
        title: format!("{metric} vs {}", p.path),
        x_desc: p.path.clone(),
        y_desc: metric.to_owned(),
        note: format!("mean and 95% CI, {how}{left_out}"),
        lines,
    }
}

/// One dot per design point (mean over its replicates, with CI) against a sampled parameter.
fn hypercube_dots(
    m: &Manifest,
    p: &ParamInfo,
    metric: &str,
    ok: &[&RunRecord],
    left_out: &str,
) -> XyChart {
    let mut points: Vec<u64> = ok.iter().map(|r| r.point).collect();
    points.dedup();
    let dots = points
        .iter()
        .filter_map(|&pt| {
            let at: Vec<&RunRecord> = ok.iter().copied().filter(|r| r.point == pt).collect();
            let x = at.first()?.params.get(&p.path)?.as_f64()?;
            Some((x, mean_ci(&values(&at, metric, |_| true))?))
        })
        .collect();
    XyChart {
        title: format!("{metric} vs {}", p.path),
        x_desc: p.path.clone(),
        y_desc: metric.to_owned(),
        note: format!(
            "one dot per design point: mean and 95% CI over {} replicates{left_out}",
            m.replicates
        ),
        lines: vec![Line {
            label: None,
            connect: false,
            points: dots,
        }],
    }
}

/// Mean ± CI of `metric` per level of a categorical parameter (others pooled).
fn category_means(
    _m: &Manifest,
    p: &ParamInfo,
    metric: &str,
    ok: &[&RunRecord],
    left_out: &str,
) -> Chart {
    Chart::Category(CategoryChart {
        title: format!("{metric} by {}", p.path),
        x_desc: p.path.clone(),
        y_desc: metric.to_owned(),
        note: format!("mean and 95% CI, other parameters pooled{left_out}"),
        categories: p.levels.iter().map(Value::to_string).collect(),
        items: p
            .levels
            .iter()
            .map(|level| {
                mean_ci(&values(ok, metric, |r| {
                    r.params.get(&p.path) == Some(level)
                }))
            })
            .collect::<Vec<Option<MeanCi>>>(),
        bars: false,
    })
}

/// The metric that says success, if any: the one named, or a kept boolean `success`.
fn success_name<'a>(
    m: &'a Manifest,
    records: &[RunRecord],
    opts: &'a PlotOptions,
) -> Option<&'a str> {
    opts.success.as_deref().or_else(|| {
        let boolean = records
            .iter()
            .any(|r| matches!(r.metrics.get("success"), Some(Value::Bool(_))));
        let kept = m.keep.metrics.iter().find(|n| *n == "success");
        kept.filter(|_| boolean).map(String::as_str)
    })
}

/// Whether each record succeeded.
fn success_of(
    m: &Manifest,
    records: &[RunRecord],
    opts: &PlotOptions,
) -> Result<Vec<bool>, PlotError> {
    let Some(name) = success_name(m, records, opts) else {
        return Ok(records.iter().map(|r| r.status == Status::Ok).collect());
    };
    if !m.keep.metrics.iter().any(|n| n == name) {
        return Err(PlotError::UnknownMetric {
            name: name.to_owned(),
            kept: m.keep.metrics.join(", "),
        });
    }
    records
        .iter()
        .map(|r| match r.metrics.get(name) {
            Some(Value::Bool(b)) => Ok(r.status == Status::Ok && *b),
            None if r.status == Status::Failed => Ok(false),
            _ => Err(PlotError::NotBoolean(name.to_owned())),
        })
        .collect()
}

/// A file stem from a chart name: letters, digits, `.`, `_` and `-` kept.
fn sanitize(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
