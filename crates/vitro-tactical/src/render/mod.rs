//! Map views: the town on its terrain as a PNG.
//!
//! Layers, bottom up: terrain (elevation tint, hillshade, 10 m contours), water, forbidden
//! zones (the buffer around buildings and water, translucent red), walking-only paths
//! (dashed), bridge decks, driving streets (cased, major classes in yellow), buildings (darker
//! when taller), driving-graph junctions; then a legend, a scale bar, a north arrow and the
//! attribution.

mod text;

use crate::geo::{P2, Polygon};
use crate::map::{Mode, TownMap};
use crate::site::{Site, SiteConfig, SiteError};
use crate::terrain::Terrain;
use std::path::Path;
use tiny_skia::{
    FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Rect, Stroke, StrokeDash, Transform,
};

/// Why a map could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The town could not be set on the terrain.
    #[error(transparent)]
    Site(#[from] SiteError),
    /// The requested image is empty or too large.
    #[error("bad image size {0} x {1}")]
    Size(u32, u32),
    /// The embedded font is unreadable.
    #[error("the embedded font cannot be read")]
    Font,
    /// Encoding or writing the PNG failed.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The output file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// What to draw and how big.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width, pixels (the height follows the town's aspect).
    pub width: u32,
    /// Margin around the town's extent, metres.
    pub margin: f64,
    /// World rectangle `[min_x, min_y, max_x, max_y]` to draw instead of the town's extent
    /// plus margin (a close-up).
    pub window: Option<[f64; 4]>,
    /// Title line of the legend.
    pub title: String,
    /// Attribution lines, bottom right (the OpenStreetMap line is always added).
    pub attribution: Vec<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1600,
            margin: 60.0,
            window: None,
            title: "Town on terrain".into(),
            attribution: Vec::new(),
        }
    }
}

/// Size of a rendered image.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct RenderSummary {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

/// The attribution the map data requires.
pub const OSM_ATTRIBUTION: &str = "Map data \u{a9} OpenStreetMap contributors, ODbL 1.0";

/// Renders `map` set on `terrain` at `offset` (world position of the town's centre; `None`
/// centres it) to the PNG file `out`, with default options.
pub fn render_map(
    map: &TownMap,
    terrain: &Terrain,
    offset: Option<[f64; 2]>,
    out: impl AsRef<Path>,
) -> Result<RenderSummary, RenderError> {
    let config = SiteConfig {
        offset,
        ..SiteConfig::default()
    };
    let site = Site::new(map.clone(), terrain.clone(), &config)?;
    render_site(&site, &RenderOptions::default(), out)
}

/// World to pixel mapping.
struct View {
    x0: f64,
    y1: f64,
    scale: f64,
}

impl View {
    fn px(&self, p: P2) -> (f32, f32) {
        (
            ((p[0] - self.x0) * self.scale) as f32,
            ((self.y1 - p[1]) * self.scale) as f32,
        )
    }
    fn world(&self, px: f64, py: f64) -> P2 {
        [self.x0 + px / self.scale, self.y1 - py / self.scale]
    }
}

fn paint(rgba: [u8; 4]) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
    p.anti_alias = true;
    p
}

fn stroke(width: f32, dash: Option<Vec<f32>>) -> Stroke {
    Stroke {
        width,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        dash: dash.and_then(|d| StrokeDash::new(d, 0.0)),
        ..Stroke::default()
    }
}

fn line_path(view: &View, pts: impl IntoIterator<Item = P2>) -> Option<tiny_skia::Path> {
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

fn polygon_path(view: &View, poly: &Polygon, offset: P2) -> Option<tiny_skia::Path> {
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

/// Elevation tint: green lowlands, tan slopes, brown tops (`t` in 0..1).
fn tint(t: f64) -> [f64; 3] {
    let stops = [
        [0.0, 170.0, 200.0, 140.0],
        [0.45, 226.0, 222.0, 170.0],
        [0.8, 206.0, 176.0, 130.0],
        [1.0, 190.0, 160.0, 140.0],
    ];
    let t = t.clamp(0.0, 1.0);
    for w in stops.windows(2) {
        let (a, b) = (w[0], w[1]);
        if t <= b[0] {
            let f = (t - a[0]) / (b[0] - a[0]);
            return [1, 2, 3].map(|i| a[i] + f * (b[i] - a[i]));
        }
    }
    [190.0, 160.0, 140.0]
}

/// Hillshade at every grid cell (Horn's slope, light from the north-west at 45°), 0..1.
fn hillshade(terrain: &Terrain) -> Vec<f64> {
    let g = terrain.grid();
    let (nc, nr) = (g.ncols as isize, g.nrows as isize);
    let at = |c: isize, r: isize, d: f64| {
        g.get(c.clamp(0, nc - 1) as usize, r.clamp(0, nr - 1) as usize)
            .unwrap_or(d)
    };
    let (az, alt) = (315f64.to_radians(), 45f64.to_radians());
    let mut out = vec![0.5; g.values.len()];
    for r in 0..nr {
        for c in 0..nc {
            let Some(h) = g.get(c as usize, r as usize) else {
                continue;
            };
            let z = |dc: isize, dr: isize| at(c + dc, r + dr, h);
            // Rows run south to north, so +r is north.
            let dzdx = ((z(1, 1) + 2.0 * z(1, 0) + z(1, -1))
                - (z(-1, 1) + 2.0 * z(-1, 0) + z(-1, -1)))
                / (8.0 * g.cellsize);
            let dzdy = ((z(-1, 1) + 2.0 * z(0, 1) + z(1, 1))
                - (z(-1, -1) + 2.0 * z(0, -1) + z(1, -1)))
                / (8.0 * g.cellsize);
            // Surface normal (-dzdx, -dzdy, 1), light direction from azimuth (clockwise from
            // north) and altitude.
            let l = [
                libm::cos(alt) * libm::sin(az),
                libm::cos(alt) * libm::cos(az),
                libm::sin(alt),
            ];
            let n = libm::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
            let shade = (-dzdx * l[0] - dzdy * l[1] + l[2]) / n;
            out[(r * nc + c) as usize] = shade.clamp(0.0, 1.0);
        }
    }
    out
}

/// Bilinear interpolation of per-cell values at local (x, y).
fn bilinear(terrain: &Terrain, vals: &[f64], x: f64, y: f64) -> f64 {
    let g = terrain.grid();
    let u = (x / g.cellsize - 0.5).clamp(0.0, (g.ncols - 1) as f64);
    let v = (y / g.cellsize - 0.5).clamp(0.0, (g.nrows - 1) as f64);
    let i = (u.floor() as usize).min(g.ncols - 2);
    let j = (v.floor() as usize).min(g.nrows - 2);
    let (fx, fy) = (u - i as f64, v - j as f64);
    let k = |c: usize, r: usize| vals[r * g.ncols + c];
    k(i, j) * (1.0 - fx) * (1.0 - fy)
        + k(i + 1, j) * fx * (1.0 - fy)
        + k(i, j + 1) * (1.0 - fx) * fy
        + k(i + 1, j + 1) * fx * fy
}

fn draw_terrain(pix: &mut Pixmap, view: &View, terrain: &Terrain) {
    let (w, h) = (pix.width() as usize, pix.height() as usize);
    let shade = hillshade(terrain);
    let heights: Vec<Option<f64>> = (0..w * h)
        .map(|k| {
            let p = view.world((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
            terrain.height(p[0], p[1])
        })
        .collect();
    let (lo, hi) = heights
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = (hi - lo).max(1.0);
    let band = |v: f64, step: f64| libm::floor(v / step) as i64;
    let data = pix.data_mut();
    for k in 0..w * h {
        let (px, py) = (k % w, k / w);
        let rgb = match heights[k] {
            None => [235.0, 235.0, 235.0],
            Some(v) => {
                let p = view.world(px as f64 + 0.5, py as f64 + 0.5);
                let s = bilinear(terrain, &shade, p[0], p[1]);
                let mut c = tint((v - lo) / span).map(|x| x * (0.62 + 0.5 * s));
                // Contours where the 10 m band changes towards the right or down neighbour.
                let next = [
                    (px + 1 < w).then(|| heights[k + 1]).flatten(),
                    (py + 1 < h).then(|| heights[k + w]).flatten(),
                ];
                for n in next.into_iter().flatten() {
                    if band(v, 50.0) != band(n, 50.0) {
                        c = c.map(|x| x * 0.62);
                    } else if band(v, 10.0) != band(n, 10.0) {
                        c = c.map(|x| x * 0.82);
                    }
                }
                c
            }
        };
        for i in 0..3 {
            data[k * 4 + i] = rgb[i].clamp(0.0, 255.0) as u8;
        }
        data[k * 4 + 3] = 255;
    }
}

/// Renders a site to the PNG file `out`.
pub fn render_site(
    site: &Site,
    opts: &RenderOptions,
    out: impl AsRef<Path>,
) -> Result<RenderSummary, RenderError> {
    let out = out.as_ref();
    let map = &site.map;
    let off = site.offset;
    let e = map.extent;
    let [x0, y0, x1, y1] = opts.window.unwrap_or([
        e[0] + off[0] - opts.margin,
        e[1] + off[1] - opts.margin,
        e[2] + off[0] + opts.margin,
        e[3] + off[1] + opts.margin,
    ]);
    if !(x1 > x0 && y1 > y0) {
        return Err(RenderError::Size(opts.width, 0));
    }
    let scale = f64::from(opts.width) / (x1 - x0);
    let height = ((y1 - y0) * scale).round();
    if opts.width == 0 || !(1.0..=20_000.0).contains(&height) || opts.width > 20_000 {
        return Err(RenderError::Size(opts.width, height.max(0.0) as u32));
    }
    let height = height as u32;
    let mut pix = Pixmap::new(opts.width, height).ok_or(RenderError::Size(opts.width, height))?;
    let view = View { x0, y1, scale };
    let s = scale as f32;
    let id = Transform::identity();

    draw_terrain(&mut pix, &view, &site.terrain);

    // Water.
    for w in &map.water {
        if let Some(path) = polygon_path(&view, &w.area, off) {
            pix.fill_path(
                &path,
                &paint([158, 202, 225, 255]),
                FillRule::EvenOdd,
                id,
                None,
            );
            pix.stroke_path(
                &path,
                &paint([74, 144, 194, 255]),
                &stroke(1.0, None),
                id,
                None,
            );
        }
    }
    // Forbidden zones: the buffer drawn as a stroke twice its width around each outline.
    let zc = site.zones_config();
    let zone_paint = paint([214, 40, 40, 110]);
    let outlines = map
        .buildings
        .iter()
        .map(|b| (&b.footprint, zc.building_buffer))
        .chain(map.water.iter().map(|w| (&w.area, zc.water_buffer)));
    for (poly, buf) in outlines {
        if let Some(path) = polygon_path(&view, poly, off) {
            pix.fill_path(&path, &zone_paint, FillRule::EvenOdd, id, None);
            if buf > 0.0 {
                pix.stroke_path(
                    &path,
                    &zone_paint,
                    &stroke(2.0 * buf as f32 * s, None),
                    id,
                    None,
                );
            }
        }
    }
    // Walking-only paths: walk segments whose way is not in the driving network.
    let drive_ways: std::collections::BTreeSet<i64> =
        map.drive.segments.iter().map(|g| g.way).collect();
    let path_paint = paint([110, 70, 40, 255]);
    for seg in map
        .walk
        .segments
        .iter()
        .filter(|g| !drive_ways.contains(&g.way))
    {
        if let Some(p) = line_path(&view, seg.points.iter().map(|&q| site.to_world(q))) {
            pix.stroke_path(
                &p,
                &paint([255, 255, 255, 150]),
                &stroke(3.2, None),
                id,
                None,
            );
            pix.stroke_path(
                &p,
                &path_paint,
                &stroke(1.6, Some(vec![5.0, 3.5])),
                id,
                None,
            );
        }
    }
    // Driving streets: casing, then fill; major classes wider and yellow. Streets on bridges
    // come last, over their deck, so they pass over what runs beneath.
    let major = |c: &str| {
        matches!(
            c.strip_suffix("_link").unwrap_or(c),
            "motorway" | "trunk" | "primary" | "secondary" | "tertiary"
        )
    };
    let streets = &map.streets(Mode::Drive).segments;
    let road_w = (6.0 * s).max(3.0);
    for on_bridge in [false, true] {
        if on_bridge {
            for b in &site.bridges {
                if let Some(p) = line_path(&view, b.deck.iter().map(|q| [q[0], q[1]])) {
                    // Wider than any street so the deck shows around the road it carries.
                    let w = (b.width as f32 * s).max(9.0 * s).max(6.0);
                    pix.stroke_path(
                        &p,
                        &paint([20, 20, 20, 255]),
                        &stroke(w + 8.0, None),
                        id,
                        None,
                    );
                    pix.stroke_path(
                        &p,
                        &paint([200, 200, 205, 255]),
                        &stroke(w + 4.0, None),
                        id,
                        None,
                    );
                }
            }
        }
        let paths: Vec<(bool, tiny_skia::Path)> = streets
            .iter()
            .filter(|g| g.bridge == on_bridge)
            .filter_map(|g| {
                line_path(&view, g.points.iter().map(|&q| site.to_world(q)))
                    .map(|p| (major(&g.class), p))
            })
            .collect();
        for (m, p) in &paths {
            let w = if *m { road_w * 1.5 } else { road_w };
            pix.stroke_path(
                p,
                &paint([70, 70, 70, 255]),
                &stroke(w + 2.5, None),
                id,
                None,
            );
        }
        for (m, p) in &paths {
            let (w, c) = if *m {
                (road_w * 1.5, [247, 211, 106, 255])
            } else {
                (road_w, [255, 255, 255, 255])
            };
            pix.stroke_path(p, &paint(c), &stroke(w, None), id, None);
        }
    }
    // Buildings, darker when taller.
    let outline = paint([90, 45, 30, 255]);
    for (b, placed) in map.buildings.iter().zip(&site.buildings) {
        let t = ((placed.roof - placed.base) / 30.0).clamp(0.0, 1.0);
        let c = [200.0 - 90.0 * t, 140.0 - 70.0 * t, 115.0 - 60.0 * t].map(|v| v as u8);
        if let Some(path) = polygon_path(&view, &b.footprint, off) {
            pix.fill_path(
                &path,
                &paint([c[0], c[1], c[2], 255]),
                FillRule::EvenOdd,
                id,
                None,
            );
            pix.stroke_path(&path, &outline, &stroke(0.7, None), id, None);
        }
    }
    // Junctions of the driving graph.
    let dot = paint([40, 40, 40, 255]);
    for n in 0..map.drive.node_count() {
        if let Some(p) = map.drive.pos(vitro::env::NodeId(n as u32)) {
            let (x, y) = view.px(site.to_world(p));
            if let Some(c) = PathBuilder::from_circle(x, y, (1.4 * s).clamp(1.5, 4.0)) {
                pix.fill_path(&c, &dot, FillRule::Winding, id, None);
            }
        }
    }

    decorate(&mut pix, &view, site, opts)?;
    pix.save_png(out).map_err(|e| RenderError::Write {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(RenderSummary {
        width: opts.width,
        height,
    })
}

/// Legend, scale bar, north arrow, attribution.
fn decorate(
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tint_is_continuous_and_font_loads() {
        for i in 0..100 {
            let (a, b) = (tint(i as f64 / 100.0), tint((i + 1) as f64 / 100.0));
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 10.0));
        }
        let f = text::font().unwrap();
        assert!(text::width(&f, "Kotka", 20.0) > 40.0);
    }
}
