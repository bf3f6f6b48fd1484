//! Drawing the charts with plotters, once as PNG and once as SVG, labelled with the
//! embedded DejaVu Sans (no system font library needed).

use super::error::PlotError;
use crate::stats::MeanCi;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// DejaVu Sans (see `assets/fonts/README.md`).
static FONT: &[u8] = include_bytes!("../../../../assets/fonts/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";
const SIZE: (u32, u32) = (960, 600);
/// Okabe–Ito colours: distinguishable with colour-vision deficiencies.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(213, 94, 0),
    RGBColor(120, 120, 120),
    RGBColor(0, 0, 0),
];
const GREY: RGBColor = RGBColor(90, 90, 90);

/// A chart to draw.
pub(crate) enum Chart {
    Xy(XyChart),
    Category(CategoryChart),
    Hist(HistChart),
}

/// Lines (or dots) of means with confidence intervals over a numeric axis.
pub(crate) struct XyChart {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub note: String,
    pub lines: Vec<Line>,
}

/// One line of an [`XyChart`].
pub(crate) struct Line {
    /// Legend entry.
    pub label: Option<String>,
    /// Join the points (a swept parameter) or not (sampled points).
    pub connect: bool,
    /// (x, mean and CI), in x order for lines.
    pub points: Vec<(f64, MeanCi)>,
}

/// Means (dots) or rates (bars) with intervals per category.
pub(crate) struct CategoryChart {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub note: String,
    pub categories: Vec<String>,
    pub items: Vec<Option<MeanCi>>,
    /// Bars from 0 (rates in [0, 1]) instead of dots.
    pub bars: bool,
}

/// A histogram.
pub(crate) struct HistChart {
    pub title: String,
    pub x_desc: String,
    pub note: String,
    pub edges: Vec<f64>,
    pub counts: Vec<usize>,
    pub mean: Option<f64>,
}

/// Registers the embedded font once; false if it could not be read.
fn font_ready() -> bool {
    static READY: OnceLock<bool> = OnceLock::new();
    *READY.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT).is_ok())
}

/// Draws `chart` to `STEM.png` and `STEM.svg`.
pub(crate) fn save(chart: &Chart, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let png = PathBuf::from(format!("{}.png", stem.display()));
    let svg = PathBuf::from(format!("{}.svg", stem.display()));
    let fail = |path: &Path| {
        let path = path.to_owned();
        move |message: String| PlotError::Draw { path, message }
    };
    if !font_ready() {
        return Err(fail(&png)("the embedded font could not be loaded".into()));
    }
    {
        // Drawn into memory and encoded by `png` (already built for the maps): plotters' own
        // file encoder would bring the whole `image` crate for one format.
        let mut rgb = vec![0u8; SIZE.0 as usize * SIZE.1 as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
            draw(&root, chart).map_err(fail(&png))?;
            root.present().map_err(|e| fail(&png)(e.to_string()))?;
        }
        write_png(&png, &rgb, SIZE).map_err(fail(&png))?;
    }
    {
        let root = SVGBackend::new(&svg, SIZE).into_drawing_area();
        draw(&root, chart).map_err(fail(&svg))?;
        root.present().map_err(|e| fail(&svg)(e.to_string()))?;
    }
    Ok(vec![png, svg])
}

/// Writes 8-bit RGB pixels as a PNG file.
fn write_png(path: &Path, rgb: &[u8], (width, height): (u32, u32)) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(s)?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(s)?;
    writer.write_image_data(rgb).map_err(s)?;
    writer.finish().map_err(s)
}

fn s<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Title and note in a header band; returns the area left for the chart.
fn header<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    note: &str,
) -> Result<DrawingArea<DB, Shift>, String> {
    root.fill(&WHITE).map_err(s)?;
    let (head, body) = root.split_vertically(70);
    head.draw_text(title, &(FAMILY, 24).into_font().color(&BLACK), (24, 12))
        .map_err(s)?;
    head.draw_text(note, &(FAMILY, 15).into_font().color(&GREY), (24, 44))
        .map_err(s)?;
    Ok(body)
}

/// A range around `[lo, hi]` with 5% room on each side (some room if it is a point).
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        span * 0.05
    } else if lo == 0.0 {
        0.5
    } else {
        lo.abs() * 0.1
    };
    (lo - pad, hi + pad)
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, chart: &Chart) -> Result<(), String> {
    match chart {
        Chart::Xy(c) => draw_xy(root, c),
        Chart::Category(c) => draw_category(root, c),
        Chart::Hist(c) => draw_hist(root, c),
    }
}

fn draw_xy<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &XyChart) -> Result<(), String> {
    let body = header(root, &c.title, &c.note)?;
    let all = c.lines.iter().flat_map(|l| l.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, m) in all {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(m.lo);
        y1 = y1.max(m.hi);
    }
    let (x0, x1) = padded(x0, x1);
    let (y0, y1) = padded(y0, y1);
    let whole_x = c
        .lines
        .iter()
        .flat_map(|l| l.points.iter())
        .all(|(x, _)| x.fract() == 0.0);
    let x_tick = |v: &f64| {
        if whole_x && v.fract() != 0.0 {
            String::new()
        } else {
            tick(*v)
        }
    };
    let mut chart = ChartBuilder::on(&body)
        .margin(20)
        .margin_top(4)
        .x_label_area_size(56)
        .y_label_area_size(86)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(s)?;
    chart
        .configure_mesh()
        .x_label_formatter(&x_tick)
        .y_label_formatter(&|v| tick(*v))
        .x_desc(c.x_desc.as_str())
        .y_desc(c.y_desc.as_str())
        .label_style((FAMILY, 14))
        .axis_desc_style((FAMILY, 17))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(s)?;
    let mut labelled = false;
    for (i, line) in c.lines.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        if line.connect && line.points.len() > 1 {
            let mut band: Vec<(f64, f64)> = line.points.iter().map(|(x, m)| (*x, m.hi)).collect();
            band.extend(line.points.iter().rev().map(|(x, m)| (*x, m.lo)));
            chart
                .draw_series(std::iter::once(Polygon::new(
                    band,
                    color.mix(0.12).filled(),
                )))
                .map_err(s)?;
            chart
                .draw_series(LineSeries::new(
                    line.points.iter().map(|(x, m)| (*x, m.mean)),
                    color.stroke_width(2),
                ))
                .map_err(s)?;
        }
        chart
            .draw_series(line.points.iter().map(|(x, m)| {
                ErrorBar::new_vertical(*x, m.lo, m.mean, m.hi, color.stroke_width(2), 10)
            }))
            .map_err(s)?;
        let dots = chart
            .draw_series(
                line.points
                    .iter()
                    .map(|(x, m)| Circle::new((*x, m.mean), 4, color.filled())),
            )
            .map_err(s)?;
        if let Some(label) = &line.label {
            labelled = true;
            dots.label(label.as_str()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 22, y)], color.stroke_width(3))
            });
        }
    }
    if labelled {
        let (xs, ys) = (x0..x1, y0..y1);
        let corner = legend_corner(c, &xs, &ys);
        chart
            .configure_series_labels()
            .position(corner)
            .label_font((FAMILY, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(190, 190, 190))
            .draw()
            .map_err(s)?;
    }
    Ok(())
}

fn draw_category<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    c: &CategoryChart,
) -> Result<(), String> {
    let body = header(root, &c.title, &c.note)?;
    let n = c.categories.len().max(1) as u32;
    let (y0, y1) = if c.bars {
        (0.0, 1.05)
    } else {
        let lo = c
            .items
            .iter()
            .flatten()
            .map(|m| m.lo)
            .fold(f64::INFINITY, f64::min);
        let hi = c
            .items
            .iter()
            .flatten()
            .map(|m| m.hi)
            .fold(f64::NEG_INFINITY, f64::max);
        padded(lo, hi)
    };
    let labels: Vec<String> = c
        .categories
        .iter()
        .zip(&c.items)
        .map(|(name, m)| format!("{name} (n={})", m.map_or(0, |m| m.n)))
        .collect();
    // Category i sits at x = i; only whole ticks get a label.
    let format = |v: &f64| {
        let i = v.round();
        if (v - i).abs() < 1e-6 && i >= 0.0 {
            labels.get(i as usize).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    };
    let mut chart = ChartBuilder::on(&body)
        .margin(20)
        .margin_top(4)
        .x_label_area_size(56)
        .y_label_area_size(86)
        .build_cartesian_2d(-0.5..f64::from(n) - 0.5, y0..y1)
        .map_err(s)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n as usize + 2)
        .x_label_formatter(&format)
        .y_label_formatter(&|v| tick(*v))
        .x_desc(c.x_desc.as_str())
        .y_desc(c.y_desc.as_str())
        .label_style((FAMILY, 14))
        .axis_desc_style((FAMILY, 17))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(s)?;
    let items: Vec<(f64, MeanCi)> = c
        .items
        .iter()
        .enumerate()
        .filter_map(|(i, m)| Some((i as f64, (*m)?)))
        .collect();
    let color = PALETTE[0];
    if c.bars {
        chart
            .draw_series(items.iter().map(|(x, m)| {
                Rectangle::new(
                    [(x - 0.3, 0.0), (x + 0.3, m.mean)],
                    color.mix(0.55).filled(),
                )
            }))
            .map_err(s)?;
    } else {
        chart
            .draw_series(
                items
                    .iter()
                    .map(|(x, m)| Circle::new((*x, m.mean), 5, color.filled())),
            )
            .map_err(s)?;
    }
    chart
        .draw_series(items.iter().map(|(x, m)| {
            ErrorBar::new_vertical(*x, m.lo, m.mean, m.hi, BLACK.stroke_width(2), 14)
        }))
        .map_err(s)?;
    Ok(())
}

fn draw_hist<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    c: &HistChart,
) -> Result<(), String> {
    let body = header(root, &c.title, &c.note)?;
    let (Some(&x0), Some(&x1)) = (c.edges.first(), c.edges.last()) else {
        body.draw_text(
            "no successful run",
            &(FAMILY, 20).into_font().color(&GREY),
            (40, 40),
        )
        .map_err(s)?;
        return Ok(());
    };
    let top = c.counts.iter().copied().max().unwrap_or(0).max(1) as f64 * 1.1;
    let mut chart = ChartBuilder::on(&body)
        .margin(20)
        .margin_top(4)
        .x_label_area_size(56)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, 0.0..top)
        .map_err(s)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_label_formatter(&|v| tick(*v))
        .x_desc(c.x_desc.as_str())
        .y_desc("runs")
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style((FAMILY, 14))
        .axis_desc_style((FAMILY, 17))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(s)?;
    let color = PALETTE[0];
    let bins = c.edges.windows(2).zip(&c.counts);
    chart
        .draw_series(bins.clone().map(|(e, &n)| {
            Rectangle::new([(e[0], 0.0), (e[1], n as f64)], color.mix(0.6).filled())
        }))
        .map_err(s)?;
    chart
        .draw_series(
            bins.map(|(e, &n)| {
                Rectangle::new([(e[0], 0.0), (e[1], n as f64)], WHITE.stroke_width(1))
            }),
        )
        .map_err(s)?;
    if let Some(mean) = c.mean {
        let accent = PALETTE[5];
        chart
            .draw_series(LineSeries::new(
                [(mean, 0.0), (mean, top)],
                accent.stroke_width(2),
            ))
            .map_err(s)?
            .label(format!("mean {}", short(mean)))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 22, y)], accent.stroke_width(3))
            });
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FAMILY, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(190, 190, 190))
            .draw()
            .map_err(s)?;
    }
    Ok(())
}

/// A number with about four significant digits, for labels.
fn short(x: f64) -> String {
    let a = x.abs();
    if a >= 1000.0 || a == 0.0 {
        format!("{x:.0}")
    } else if a >= 1.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.4}")
    }
}

/// An axis tick: at most six decimals, trailing zeros dropped (`300`, `0.3`, `2.5`).
fn tick(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// The corner of the plot where the legend of `c` hides the fewest points of its lines
/// (means, interval ends and the segments between them).
fn legend_corner(
    c: &XyChart,
    xs: &std::ops::Range<f64>,
    ys: &std::ops::Range<f64>,
) -> SeriesLabelPosition {
    let entries = c.lines.iter().filter(|l| l.label.is_some()).count() as f64;
    let (w, h) = (0.3, (0.06 + 0.045 * entries).min(0.9));
    let unit = |x: f64, y: f64| {
        (
            (x - xs.start) / (xs.end - xs.start),
            (y - ys.start) / (ys.end - ys.start),
        )
    };
    let mut pts = Vec::new();
    for line in &c.lines {
        for (x, m) in &line.points {
            pts.extend([unit(*x, m.mean), unit(*x, m.lo), unit(*x, m.hi)]);
        }
        if line.connect {
            for pair in line.points.windows(2) {
                let ((xa, a), (xb, b)) = (pair[0], pair[1]);
                for i in 1..10 {
                    let t = f64::from(i) / 10.0;
                    pts.push(unit(xa + t * (xb - xa), a.mean + t * (b.mean - a.mean)));
                }
            }
        }
    }
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let hidden = |right: bool, top: bool| {
        pts.iter()
            .filter(|(x, y)| {
                (if right { *x > 1.0 - w } else { *x < w })
                    && (if top { *y > 1.0 - h } else { *y < h })
            })
            .count()
    };
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (pos, right, top) in corners {
        let n = hidden(right, top);
        if n < best.1 {
            best = (pos, n);
        }
    }
    best.0
}
