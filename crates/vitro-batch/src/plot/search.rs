//! The progress of searches: what they found against the evaluations spent, one line per
//! strategy (the mean over its searches, with the 95% confidence band).

use super::draw::{self, Chart, Line, XyChart};
use super::error::PlotError;
use crate::stats::mean_ci;
use std::path::{Path, PathBuf};

/// Curves of several searches, grouped (e.g. by strategy).
#[derive(Clone, Debug, Default)]
pub struct SearchCurves {
    /// Title of the chart.
    pub title: String,
    /// The line under the title.
    pub note: String,
    /// What the y axis counts.
    pub y_desc: String,
    /// Each group's label and its searches' curves: value after evaluation 1, 2, ...
    pub groups: Vec<(String, Vec<Vec<f64>>)>,
}

/// Draws `curves` to `STEM.png` and `STEM.svg`: per group, the mean over its searches after
/// the first evaluation and every tenth (and the last), with the 95% Student-t band.
pub fn plot_search_curves(curves: &SearchCurves, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let lines = curves
        .groups
        .iter()
        .map(|(label, runs)| {
            let len = runs.iter().map(Vec::len).min().unwrap_or(0);
            let points = (0..len)
                .filter(|i| *i == 0 || (i + 1) % 10 == 0 || i + 1 == len)
                .filter_map(|i| {
                    let at: Vec<f64> = runs.iter().map(|c| c[i]).collect();
                    mean_ci(&at).map(|m| ((i + 1) as f64, m))
                })
                .collect();
            Line {
                label: Some(format!("{label} (n = {})", runs.len())),
                connect: true,
                points,
            }
        })
        .collect();
    let chart = Chart::Xy(XyChart {
        title: curves.title.clone(),
        x_desc: "evaluations (runs)".into(),
        y_desc: curves.y_desc.clone(),
        note: curves.note.clone(),
        lines,
    });
    draw::save(&chart, stem)
}
