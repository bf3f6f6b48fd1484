//! A scatter of paired values (one dot per pair, one colour per group) with the diagonal
//! `y = x`: predicted against measured, for instance.

use super::draw::{self, Chart, Line, XyChart};
use super::error::PlotError;
use crate::stats::MeanCi;
use std::path::{Path, PathBuf};

/// Groups of (x, y) pairs to draw.
#[derive(Clone, Debug, Default)]
pub struct Scatter {
    /// Title of the chart.
    pub title: String,
    /// The line under the title.
    pub note: String,
    /// What the x axis measures.
    pub x_desc: String,
    /// What the y axis measures.
    pub y_desc: String,
    /// Each group's label and its pairs.
    pub groups: Vec<(String, Vec<(f64, f64)>)>,
}

/// Draws `scatter` to `STEM.png` and `STEM.svg`, with the diagonal `y = x` over the range of
/// the data.
pub fn plot_scatter(scatter: &Scatter, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let all = scatter.groups.iter().flat_map(|(_, p)| p.iter());
    let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(x, y)| {
        (lo.min(x).min(y), hi.max(x).max(y))
    });
    let mut lines = group_lines(scatter);
    if lo.is_finite() && hi > lo {
        lines.push(Line {
            label: Some("y = x".into()),
            connect: true,
            points: vec![dot(lo, lo), dot(hi, hi)],
        });
    }
    save(scatter, lines, stem)
}

/// Draws `scatter` to `STEM.png` and `STEM.svg` as residuals: its y values are errors
/// (e.g. relative errors in %), drawn over the line `y = 0` shaded from `-band` to `band`
/// across the range of the data.
pub fn plot_residuals(
    scatter: &Scatter,
    band: f64,
    stem: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let all = scatter.groups.iter().flat_map(|(_, p)| p.iter());
    let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(x, _)| {
        (lo.min(x), hi.max(x))
    });
    let mut lines = group_lines(scatter);
    if lo.is_finite() && hi > lo {
        // y = 0, shaded from -band to +band.
        let edge = |x: f64| {
            (
                x,
                MeanCi {
                    n: 1,
                    mean: 0.0,
                    lo: -band,
                    hi: band,
                },
            )
        };
        // Drawn first, under the dots.
        lines.insert(
            0,
            Line {
                label: Some(format!("no error, band ±{band}")),
                connect: true,
                points: vec![edge(lo), edge(hi)],
            },
        );
    }
    save(scatter, lines, stem)
}

/// One point, drawn as a dot (no interval).
fn dot(x: f64, y: f64) -> (f64, MeanCi) {
    (
        x,
        MeanCi {
            n: 1,
            mean: y,
            lo: y,
            hi: y,
        },
    )
}

/// Each group of `scatter` as unconnected dots, labelled with its size.
fn group_lines(scatter: &Scatter) -> Vec<Line> {
    scatter
        .groups
        .iter()
        .map(|(label, pts)| Line {
            label: Some(format!("{label} (n = {})", pts.len())),
            connect: false,
            points: pts.iter().map(|&(x, y)| dot(x, y)).collect(),
        })
        .collect()
}

/// Draws `lines` with `scatter`'s titles to `STEM.png` and `STEM.svg`.
fn save(scatter: &Scatter, lines: Vec<Line>, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let chart = Chart::Xy(XyChart {
        title: scatter.title.clone(),
        x_desc: scatter.x_desc.clone(),
        y_desc: scatter.y_desc.clone(),
        note: scatter.note.clone(),
        lines,
    });
    draw::save(&chart, stem)
}
