//! Overlays: trajectories drawn over a rendered site, with a legend of their own.
//!
//! ```
//! use vitro_site::map::TownMap;
//! use vitro_site::render::{Overlay, RenderOptions, render_site_with};
//! use vitro_site::site::{Site, SiteConfig};
//! use vitro_site::terrain::Terrain;
//! let ground = Terrain::flat(50, 50, 10.0, 0.0).unwrap();
//! let site = Site::new(TownMap::from_buildings(vec![]), ground, &SiteConfig::default()).unwrap();
//! let track = Overlay::line("patrol", vec![[100.0, 100.0], [400.0, 300.0]], [200, 30, 30, 255]);
//! let opts = RenderOptions { width: 300, window: Some([0.0, 0.0, 500.0, 500.0]), ..Default::default() };
//! let out = std::env::temp_dir().join(format!("overlay-doc-{}.png", std::process::id()));
//! let size = render_site_with(&site, &opts, &[track], &out).unwrap();
//! assert_eq!((size.width, size.height), (300, 300));
//! # std::fs::remove_file(out).unwrap();
//! ```

use super::canvas::{View, line_path, paint, stroke};
use super::options::RenderError;
use super::text;
use crate::geo::P2;
use tiny_skia::{FillRule, PathBuilder, Pixmap, Rect, Transform};

/// One polyline (world metres) to draw over the map.
#[derive(Clone, Debug, PartialEq)]
pub struct Overlay {
    /// Legend text.
    pub label: String,
    /// World points (x, y), metres.
    pub points: Vec<P2>,
    /// Colour, RGBA.
    pub rgba: [u8; 4],
    /// Line width, pixels.
    pub width: f32,
    /// Dash pattern (on, off, ... pixels), if dashed.
    pub dash: Option<Vec<f32>>,
    /// Dot radius at every point, pixels (0: none).
    pub dots: f32,
}

impl Overlay {
    /// A solid line, 3 px wide.
    pub fn line(label: impl Into<String>, points: Vec<P2>, rgba: [u8; 4]) -> Self {
        Overlay {
            label: label.into(),
            points,
            rgba,
            width: 3.0,
            dash: None,
            dots: 0.0,
        }
    }
}

/// Draws the overlays' lines (a thin white casing under each, so they read on any ground).
pub(super) fn draw(pix: &mut Pixmap, view: &View, overlays: &[Overlay]) {
    let id = Transform::identity();
    for o in overlays {
        if let Some(p) = line_path(view, o.points.iter().copied()) {
            pix.stroke_path(
                &p,
                &paint([255, 255, 255, 170]),
                &stroke(o.width + 2.0, o.dash.clone()),
                id,
                None,
            );
            pix.stroke_path(
                &p,
                &paint(o.rgba),
                &stroke(o.width, o.dash.clone()),
                id,
                None,
            );
        }
        if o.dots > 0.0 {
            for &q in &o.points {
                let (x, y) = view.px(q);
                if let Some(c) = PathBuilder::from_circle(x, y, o.dots) {
                    pix.fill_path(&c, &paint(o.rgba), FillRule::Winding, id, None);
                }
            }
        }
    }
}

/// The overlays' legend, top right (left of the north arrow).
pub(super) fn legend(pix: &mut Pixmap, overlays: &[Overlay]) -> Result<(), RenderError> {
    if overlays.is_empty() {
        return Ok(());
    }
    let font = text::font().ok_or(RenderError::Font)?;
    let id = Transform::identity();
    let k = (pix.width() as f32 / 1800.0).max(0.5);
    let fs = 22.0 * k;
    let line_h = fs * 1.45;
    let text_w = overlays
        .iter()
        .map(|o| text::width(&font, &o.label, fs))
        .fold(0.0, f32::max);
    let bw = text_w + 96.0 * k;
    let bh = line_h * (overlays.len() as f32 + 0.6);
    let (bx, by) = (pix.width() as f32 - bw - 110.0 * k, 14.0 * k);
    if let Some(r) = Rect::from_xywh(bx, by, bw, bh) {
        pix.fill_rect(r, &paint([255, 255, 255, 225]), id, None);
        pix.stroke_path(
            &PathBuilder::from_rect(r),
            &paint([60, 60, 60, 255]),
            &stroke(1.5, None),
            id,
            None,
        );
    }
    for (i, o) in overlays.iter().enumerate() {
        let y = by + line_h * (i as f32 + 1.0);
        let sy = y - fs * 0.35;
        let mut pb = PathBuilder::new();
        pb.move_to(bx + 14.0 * k, sy);
        pb.line_to(bx + 70.0 * k, sy);
        if let Some(p) = pb.finish() {
            pix.stroke_path(
                &p,
                &paint(o.rgba),
                &stroke(o.width.max(2.0), o.dash.clone()),
                id,
                None,
            );
        }
        if o.dots > 0.0
            && let Some(c) = PathBuilder::from_circle(bx + 42.0 * k, sy, o.dots)
        {
            pix.fill_path(&c, &paint(o.rgba), FillRule::Winding, id, None);
        }
        text::draw(pix, &font, &o.label, bx + 82.0 * k, y, fs, [20, 20, 20]);
    }
    Ok(())
}
