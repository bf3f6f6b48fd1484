//! Decorations: legend, scale bar, north arrow, attribution.

use super::canvas::{View, paint, stroke};
use super::options::{OSM_ATTRIBUTION, RenderError, RenderOptions};
use super::text;
use crate::site::Site;
use tiny_skia::{FillRule, PathBuilder, Pixmap, Rect, Transform};

/// Legend, scale bar, north arrow, attribution.
pub(super) fn decorate(
    pix: &mut Pixmap,
    view: &View,
    site: &Site,
    opts: &RenderOptions,
) -> Result<(), RenderError> {
    let font = text::font().ok_or(RenderError::Font)?;
    let id = Transform::identity();
    let k = (pix.width() as f32 / 1800.0).max(0.5);
    let fs = 22.0 * k;
    let zc = site.zones_config();
    let items: Vec<(&str, String)> = vec![
        (
            "drive",
            format!(
                "street (vehicles), {} junctions",
                site.map.drive.node_count()
            ),
        ),
        ("major", "main street (secondary, tertiary)".into()),
        ("walk", "footway / path (troops only)".into()),
        ("bridge", "bridge deck".into()),
        (
            "building",
            format!("building ({} footprints)", site.map.buildings.len()),
        ),
        (
            "zone",
            format!("forbidden: building + {} m buffer", zc.building_buffer),
        ),
        ("water", "water".into()),
        ("contour", "contours every 10 m (50 m bold)".into()),
    ];
    let line_h = fs * 1.45;
    let text_w = items
        .iter()
        .map(|(_, t)| text::width(&font, t, fs))
        .fold(text::width(&font, &opts.title, fs * 1.15), f32::max);
    let (bx, by) = (14.0 * k, 14.0 * k);
    let bw = text_w + 90.0 * k;
    let bh = line_h * (items.len() as f32 + 1.6);
    if let Some(r) = Rect::from_xywh(bx, by, bw, bh) {
        pix.fill_rect(r, &paint([255, 255, 255, 225]), id, None);
        let p = PathBuilder::from_rect(r);
        pix.stroke_path(&p, &paint([60, 60, 60, 255]), &stroke(1.5, None), id, None);
    }
    text::draw(
        pix,
        &font,
        &opts.title,
        bx + 14.0 * k,
        by + line_h,
        fs * 1.15,
        [20, 20, 20],
    );
    for (i, (kind, label)) in items.iter().enumerate() {
        let y = by + line_h * (i as f32 + 2.2);
        let (sx0, sx1, sy) = (bx + 14.0 * k, bx + 64.0 * k, y - fs * 0.35);
        let mut pb = PathBuilder::new();
        pb.move_to(sx0, sy);
        pb.line_to(sx1, sy);
        let seg = pb.finish();
        let swatch = Rect::from_xywh(sx0 + 8.0 * k, sy - 9.0 * k, 34.0 * k, 18.0 * k);
        match (*kind, seg, swatch) {
            ("drive", Some(p), _) => {
                pix.stroke_path(
                    &p,
                    &paint([70, 70, 70, 255]),
                    &stroke(9.0 * k, None),
                    id,
                    None,
                );
                pix.stroke_path(
                    &p,
                    &paint([255, 255, 255, 255]),
                    &stroke(6.0 * k, None),
                    id,
                    None,
                );
            }
            ("major", Some(p), _) => {
                pix.stroke_path(
                    &p,
                    &paint([70, 70, 70, 255]),
                    &stroke(12.0 * k, None),
                    id,
                    None,
                );
                pix.stroke_path(
                    &p,
                    &paint([247, 211, 106, 255]),
                    &stroke(9.0 * k, None),
                    id,
                    None,
                );
            }
            ("walk", Some(p), _) => {
                pix.stroke_path(
                    &p,
                    &paint([110, 70, 40, 255]),
                    &stroke(2.0 * k, Some(vec![5.0, 3.5])),
                    id,
                    None,
                );
            }
            ("bridge", Some(p), _) => {
                pix.stroke_path(
                    &p,
                    &paint([20, 20, 20, 255]),
                    &stroke(12.0 * k, None),
                    id,
                    None,
                );
                pix.stroke_path(
                    &p,
                    &paint([200, 200, 205, 255]),
                    &stroke(9.0 * k, None),
                    id,
                    None,
                );
            }
            ("contour", Some(p), _) => {
                pix.stroke_path(
                    &p,
                    &paint([120, 100, 70, 255]),
                    &stroke(1.5 * k, None),
                    id,
                    None,
                );
            }
            ("building", _, Some(r)) => pix.fill_rect(r, &paint([175, 115, 90, 255]), id, None),
            ("zone", _, Some(r)) => pix.fill_rect(r, &paint([214, 40, 40, 110]), id, None),
            ("water", _, Some(r)) => pix.fill_rect(r, &paint([158, 202, 225, 255]), id, None),
            _ => {}
        }
        text::draw(pix, &font, label, bx + 76.0 * k, y, fs, [20, 20, 20]);
    }

    // Scale bar: the largest of 100/200/500/1000 m that fits a fifth of the width.
    let w = pix.width() as f64;
    let metres = [1000.0, 500.0, 200.0, 100.0, 50.0]
        .into_iter()
        .find(|m| m * view.scale <= w / 5.0)
        .unwrap_or(50.0);
    let len = (metres * view.scale) as f32;
    let (sx, sy) = (20.0 * k, pix.height() as f32 - 30.0 * k);
    if let Some(r) = Rect::from_xywh(
        sx - 8.0 * k,
        sy - 40.0 * k,
        len + 16.0 * k + 80.0 * k,
        56.0 * k,
    ) {
        pix.fill_rect(r, &paint([255, 255, 255, 210]), id, None);
    }
    for (i, c) in [[20u8, 20, 20, 255], [255, 255, 255, 255]]
        .iter()
        .cycle()
        .take(4)
        .enumerate()
    {
        let q = len / 4.0;
        if let Some(r) = Rect::from_xywh(sx + q * i as f32, sy - 8.0 * k, q, 8.0 * k) {
            pix.fill_rect(r, &paint(*c), id, None);
        }
    }
    if let Some(r) = Rect::from_xywh(sx, sy - 8.0 * k, len, 8.0 * k) {
        pix.stroke_path(
            &PathBuilder::from_rect(r),
            &paint([20, 20, 20, 255]),
            &stroke(1.0, None),
            id,
            None,
        );
    }
    text::draw(
        pix,
        &font,
        &format!("{metres} m"),
        sx + len + 10.0 * k,
        sy,
        fs,
        [20, 20, 20],
    );
    text::draw(
        pix,
        &font,
        "0",
        sx - 4.0 * k,
        sy - 14.0 * k,
        fs * 0.8,
        [20, 20, 20],
    );

    // North arrow, top right.
    let (nx, ny) = (w as f32 - 50.0 * k, 30.0 * k);
    let mut pb = PathBuilder::new();
    pb.move_to(nx, ny);
    pb.line_to(nx + 16.0 * k, ny + 50.0 * k);
    pb.line_to(nx, ny + 38.0 * k);
    pb.line_to(nx - 16.0 * k, ny + 50.0 * k);
    pb.close();
    if let Some(p) = pb.finish() {
        pix.fill_path(&p, &paint([30, 30, 30, 255]), FillRule::Winding, id, None);
    }
    text::draw(
        pix,
        &font,
        "N",
        nx - 8.0 * k,
        ny + 78.0 * k,
        fs * 1.1,
        [30, 30, 30],
    );

    // Attribution, bottom right.
    let mut lines = vec![OSM_ATTRIBUTION.to_string()];
    lines.extend(opts.attribution.iter().cloned());
    let afs = fs * 0.8;
    let aw = lines
        .iter()
        .map(|l| text::width(&font, l, afs))
        .fold(0.0, f32::max);
    let ah = afs * 1.4 * lines.len() as f32 + 10.0 * k;
    let (ax, ay) = (
        w as f32 - aw - 24.0 * k,
        pix.height() as f32 - ah - 10.0 * k,
    );
    if let Some(r) = Rect::from_xywh(ax - 8.0 * k, ay, aw + 20.0 * k, ah) {
        pix.fill_rect(r, &paint([255, 255, 255, 215]), id, None);
    }
    for (i, l) in lines.iter().enumerate() {
        text::draw(
            pix,
            &font,
            l,
            ax,
            ay + afs * 1.4 * (i as f32 + 1.0),
            afs,
            [30, 30, 30],
        );
    }
    Ok(())
}
