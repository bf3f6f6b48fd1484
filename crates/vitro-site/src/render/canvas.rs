//! The canvas: world to pixel mapping, paints, strokes and paths shared by every layer of a map.

use crate::geo::{P2, Polygon};
use tiny_skia::{LineCap, LineJoin, Paint, PathBuilder, Stroke, StrokeDash};

/// World to pixel mapping.
pub(super) struct View {
    pub(super) x0: f64,
    pub(super) y1: f64,
    pub(super) scale: f64,
}

impl View {
    pub(super) fn px(&self, p: P2) -> (f32, f32) {
        (
            ((p[0] - self.x0) * self.scale) as f32,
            ((self.y1 - p[1]) * self.scale) as f32,
        )
    }
    pub(super) fn world(&self, px: f64, py: f64) -> P2 {
        [self.x0 + px / self.scale, self.y1 - py / self.scale]
    }
}

pub(super) fn paint(rgba: [u8; 4]) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
    p.anti_alias = true;
    p
}

pub(super) fn stroke(width: f32, dash: Option<Vec<f32>>) -> Stroke {
    Stroke {
        width,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        dash: dash.and_then(|d| StrokeDash::new(d, 0.0)),
        ..Stroke::default()
    }
}

pub(super) fn line_path(view: &View, pts: impl IntoIterator<Item = P2>) -> Option<tiny_skia::Path> {
    let mut pb = PathBuilder::new();
    for (i, p) in pts.into_iter().enumerate() {
        let (x, y) = view.px(p);
        if i == 0 {
            pb.move_to(x, y);
        } else {
            pb.line_to(x, y);
        }
    }
    pb.finish()
}

pub(super) fn polygon_path(view: &View, poly: &Polygon, offset: P2) -> Option<tiny_skia::Path> {
    let mut pb = PathBuilder::new();
    for ring in poly.rings() {
        for (i, p) in ring.iter().enumerate() {
            let (x, y) = view.px([p[0] + offset[0], p[1] + offset[1]]);
            if i == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        pb.close();
    }
    pb.finish()
}
