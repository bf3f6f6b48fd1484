//! Map views: the town on its terrain as a PNG.
//!
//! Layers, bottom up: terrain (elevation tint, hillshade, 10 m contours), water, forbidden
//! zones (the buffer around buildings and water, translucent red), walking-only paths
//! (dashed), bridge decks, driving streets (cased, major classes in yellow), buildings (darker
//! when taller), driving-graph junctions; then a legend, a scale bar, a north arrow and the
//! attribution.

mod canvas;
mod ground;
mod legend;
mod options;
mod overlay;
mod text;

pub use options::{OSM_ATTRIBUTION, RenderError, RenderOptions};
pub use overlay::Overlay;

use canvas::{View, line_path, paint, polygon_path, stroke};

use crate::map::{Mode, TownMap};
use crate::site::{Site, SiteConfig};
use crate::terrain::Terrain;
use std::path::Path;
use tiny_skia::{FillRule, PathBuilder, Pixmap, Transform};

/// Size of a rendered image.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct RenderSummary {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

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

/// Renders a site to the PNG file `out`.
pub fn render_site(
    site: &Site,
    opts: &RenderOptions,
    out: impl AsRef<Path>,
) -> Result<RenderSummary, RenderError> {
    render_site_with(site, opts, &[], out)
}

/// Renders a site with `overlays` (trajectories, routes) drawn over it and listed in a
/// legend of their own, to the PNG file `out`.
pub fn render_site_with(
    site: &Site,
    opts: &RenderOptions,
    overlays: &[Overlay],
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

    ground::draw_terrain(&mut pix, &view, &site.terrain);

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

    overlay::draw(&mut pix, &view, overlays);
    legend::decorate(&mut pix, &view, site, opts)?;
    overlay::legend(&mut pix, overlays)?;
    pix.save_png(out).map_err(|e| RenderError::Write {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(RenderSummary {
        width: opts.width,
        height,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tint_is_continuous_and_font_loads() {
        for i in 0..100 {
            let (a, b) = (
                ground::tint(i as f64 / 100.0),
                ground::tint((i + 1) as f64 / 100.0),
            );
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 10.0));
        }
        let f = text::font().unwrap();
        assert!(text::width(&f, "Kotka", 20.0) > 40.0);
    }
}
