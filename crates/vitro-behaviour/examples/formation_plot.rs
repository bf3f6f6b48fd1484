//! A squad of four (a leader and three members, directed troopers) ordered across the real
//! town: over the open valley, past a red trooper, into the narrow streets of the
//! south-eastern terraces, then north. Drawn over the map to `docs/formation.png`: each
//! body's trajectory, every change of formation marked and named, and three close-ups
//! (wedge on open ground, line facing the red, column and file in the streets) with the
//! squad's shape every 15 s.
//!
//! `cargo run --release -p vitro-behaviour --example formation_plot [OUT.png]`

// Measurements of the outcome (distances, angles, fits), not model code: platform math is
// allowed here (clippy.toml bans it where it could change a trace hash).
#![allow(clippy::disallowed_methods)]

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use std::time::Instant;
use tiny_skia::{
    Color, FillRule, Paint, PathBuilder, Pixmap, PixmapPaint, Rect, Stroke, Transform,
};
use vitro::prelude::*;
use vitro_behaviour::formation::{
    FormationParams, LEADER_PROGRAM, Leader, Member, Pattern, Script, Switch, TrackPoint,
};
use vitro_site::geo::dist;
use vitro_site::map::Mode;
use vitro_site::render::{Overlay, RenderOptions, render_site_with};
use vitro_tactical::arena::Ev;
use vitro_tactical::entity::Level;
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::{Basic, Command, Signal};
use vitro_tactical::setup::Setup;
use vitro_tactical::types::TroopKind;

type P2 = [f64; 2];
type Error = Box<dyn std::error::Error>;

static FONT: &[u8] = include_bytes!("../../vitro-site/assets/DejaVuSans.ttf");

/// Colours: the leader, then the members.
const BODY: [[u8; 4]; 4] = [
    [20, 20, 20, 255],
    [31, 119, 180, 255],
    [44, 160, 44, 255],
    [148, 103, 189, 255],
];
const RED: [u8; 4] = [214, 39, 40, 255];

fn pattern_colour(p: Pattern) -> [u8; 4] {
    match p {
        Pattern::File => [230, 120, 0, 255],
        Pattern::Column => [255, 200, 0, 255],
        Pattern::Line => [220, 0, 120, 255],
        Pattern::Wedge => [0, 170, 200, 255],
    }
}

fn why(reason: &str) -> &str {
    match reason {
        "narrow" => "narrow street",
        "street" => "street",
        "open" => "open ground",
        other => other,
    }
}

fn node_xy(setup: &Setup, n: NodeId) -> Result<P2, Error> {
    let p = setup
        .arena()
        .node_point(Mode::Walk, n)
        .ok_or("not a walk node")?;
    Ok([p[0], p[1]])
}

/// A walk-graph node 60-100 m off the first leg, in sight from the leg's point 40 % along.
fn hiding_place(setup: &Setup, path: &[NodeId]) -> Result<NodeId, Error> {
    let pts: Vec<P2> = path
        .iter()
        .map(|&n| node_xy(setup, n))
        .collect::<Result<_, _>>()?;
    let at = pts[pts.len() * 2 / 5];
    let site = &setup.site;
    let z = |p: P2, h: f64| [p[0], p[1], site.ground(p).unwrap_or(0.0) + h];
    let walk = &setup.roads.walk;
    (0..walk.graph.node_count() as u32)
        .map(NodeId)
        .filter(|n| walk.main[n.0 as usize])
        .find(|&n| {
            node_xy(setup, n).is_ok_and(|p| {
                (60.0..100.0).contains(&dist(p, at))
                    && pts.iter().all(|&q| dist(p, q) > 50.0)
                    && site.los.visible(z(at, 1.8), z(p, 0.9))
            })
        })
        .ok_or_else(|| "no hiding place by the route".into())
}

/// What the run left for the picture.
struct Run {
    leader: EntityId,
    members: Vec<EntityId>,
    log: Vec<TrackPoint>,
    switches: Vec<Switch>,
    red: P2,
    start: P2,
    goal: P2,
    arrived: f64,
}

fn run(setup: &Setup) -> Result<Run, Error> {
    let (a, b) = setup
        .standard_trip(Mode::Walk)
        .ok_or("the walk graph has no connected part")?;
    let terraces = setup
        .roads
        .walk
        .nearest_connected(setup.site.to_town([3750.0, 2450.0]))
        .ok_or("no walk node")?;
    let first = setup.roads.walk.path(a, terraces)?;
    let red_node = hiding_place(setup, &first)?;
    let params = FormationParams::default();
    let mut sim = Simulation::<Tactical>::new(setup.arena(), 7);
    let leader = EntityId(3);
    let mut members = Vec::new();
    for name in ["alpha", "bravo", "charlie"] {
        let m = Member::new(leader, params.clone());
        members.push(sim.add_agent(name, Box::new(m))?);
    }
    let l = Leader::new(LEADER_PROGRAM, members.clone(), params)?;
    if sim.add_agent("leader", Box::new(l))? != leader {
        return Err("the leader is not entity 3".into());
    }
    for &id in members.iter().chain([&leader]) {
        sim.env_mut()
            .add_trooper(id, TroopKind::Blue, Level::Directed, a, 0.0)?;
    }
    let red = sim.add_entity("red")?;
    sim.env_mut()
        .add_trooper(red, TroopKind::Red, Level::Directed, red_node, 0.0)?;
    let (start, mid, goal) = (
        node_xy(setup, a)?,
        node_xy(setup, terraces)?,
        node_xy(setup, b)?,
    );
    let hq = Script::new(vec![(
        SimTime::from_secs(1),
        leader,
        Basic::from(Command::GoTo(mid)),
    )])
    .then_on_arrival(vec![(leader, Basic::from(Command::GoTo(goal)))]);
    let hq = sim.add_agent("hq", Box::new(hq))?;
    for &id in members.iter().chain([&leader, &hq]) {
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)?;
    }
    let done = Basic::from(Signal::new("arrived", ""));
    let heard = |sim: &Simulation<Tactical>| {
        sim.agent(hq)
            .and_then(|a| a.as_any().downcast_ref::<Script>())
            .map_or(0, |s| s.heard_all(&done).len())
    };
    sim.run(SimTime::from_secs(4 * 3600), |sim| heard(sim) >= 2);
    let l = sim
        .agent(leader)
        .and_then(|a| a.as_any().downcast_ref::<Leader>())
        .ok_or("no leader")?;
    let arrived = l
        .arrivals()
        .last()
        .map(|a| a.t.as_secs_f64())
        .ok_or("the squad did not arrive")?;
    Ok(Run {
        leader,
        members,
        log: l.trajectory().to_vec(),
        switches: l.switches().to_vec(),
        red: node_xy(setup, red_node)?,
        start,
        goal,
        arrived,
    })
}

impl Run {
    fn track(&self, id: EntityId, from: f64, to: f64) -> Vec<P2> {
        self.log
            .iter()
            .filter(|p| p.id == id && (from..=to).contains(&p.t.as_secs_f64()))
            .map(|p| [p.pos[0], p.pos[1]])
            .collect()
    }
    fn at(&self, id: EntityId, t: f64) -> Option<P2> {
        self.log
            .iter()
            .rev()
            .find(|p| p.id == id && p.t.as_secs_f64() <= t)
            .map(|p| [p.pos[0], p.pos[1]])
    }
    fn ids(&self) -> Vec<EntityId> {
        std::iter::once(self.leader)
            .chain(self.members.iter().copied())
            .collect()
    }
}

fn paint(rgba: [u8; 4]) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
    p.anti_alias = true;
    p
}

fn stroke(width: f32) -> Stroke {
    Stroke {
        width,
        line_cap: tiny_skia::LineCap::Round,
        line_join: tiny_skia::LineJoin::Round,
        ..Stroke::default()
    }
}

/// World to pixels for a rendered window.
#[derive(Copy, Clone)]
struct View {
    x0: f64,
    y1: f64,
    scale: f64,
}

impl View {
    fn of(window: [f64; 4], width: u32) -> View {
        View {
            x0: window[0],
            y1: window[3],
            scale: f64::from(width) / (window[2] - window[0]),
        }
    }
    fn px(&self, p: P2) -> (f32, f32) {
        (
            ((p[0] - self.x0) * self.scale) as f32,
            ((self.y1 - p[1]) * self.scale) as f32,
        )
    }
}

fn text_width(font: &FontRef<'_>, s: &str, size: f32) -> f32 {
    let f = font.as_scaled(PxScale::from(size));
    s.chars().map(|c| f.h_advance(f.glyph_id(c))).sum()
}

/// Draws `s` with its baseline at (`x`, `y`) on a white box.
fn label(pix: &mut Pixmap, font: &FontRef<'_>, s: &str, x: f32, y: f32, size: f32, rgb: [u8; 3]) {
    let w = text_width(font, s, size);
    if let Some(r) = Rect::from_xywh(x - 3.0, y - size * 0.85, w + 6.0, size * 1.15) {
        pix.fill_rect(r, &paint([255, 255, 255, 215]), Transform::identity(), None);
    }
    let f = font.as_scaled(PxScale::from(size));
    let (pw, ph) = (pix.width() as i32, pix.height() as i32);
    let data = pix.data_mut();
    let mut caret = x;
    for c in s.chars() {
        let id = f.glyph_id(c);
        let glyph = id.with_scale_and_position(size, point(caret, y));
        caret += f.h_advance(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, cov| {
            let (px, py) = (b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32);
            if px < 0 || py < 0 || px >= pw || py >= ph {
                return;
            }
            let k = ((py * pw + px) * 4) as usize;
            for i in 0..3 {
                let old = f32::from(data[k + i]);
                data[k + i] = (old + (f32::from(rgb[i]) - old) * cov.clamp(0.0, 1.0)).round() as u8;
            }
        });
    }
}

fn dot(pix: &mut Pixmap, x: f32, y: f32, r: f32, rgba: [u8; 4]) {
    if let Some(c) = PathBuilder::from_circle(x, y, r) {
        let id = Transform::identity();
        pix.fill_path(
            &c,
            &paint([255, 255, 255, 255]),
            FillRule::Winding,
            id,
            None,
        );
        if let Some(c2) = PathBuilder::from_circle(x, y, r - 1.5) {
            pix.fill_path(&c2, &paint(rgba), FillRule::Winding, id, None);
        }
    }
}

fn polyline(pix: &mut Pixmap, view: &View, pts: &[P2], width: f32, rgba: [u8; 4]) {
    let mut pb = PathBuilder::new();
    for (i, &p) in pts.iter().enumerate() {
        let (x, y) = view.px(p);
        if i == 0 {
            pb.move_to(x, y);
        } else {
            pb.line_to(x, y);
        }
    }
    if let Some(path) = pb.finish() {
        let id = Transform::identity();
        pix.stroke_path(
            &path,
            &paint([255, 255, 255, 200]),
            &stroke(width + 2.0),
            id,
            None,
        );
        pix.stroke_path(&path, &paint(rgba), &stroke(width), id, None);
    }
}

/// What a close-up shows: `span` metres square around `centre`, the trajectories between
/// the times of `tracks`, the squad's shape at each time of `shots`.
struct CloseUp {
    centre: P2,
    span: f64,
    tracks: (f64, f64),
    shots: Vec<f64>,
    caption: String,
}

/// Renders a close-up, `size` pixels square.
fn close_up(setup: &Setup, run: &Run, c: &CloseUp, size: u32) -> Result<Pixmap, Error> {
    let (o, span) = (c.centre, c.span);
    // Rendered three times as wide, the map's own legends fall outside the middle third.
    let big = [
        o[0] - 1.5 * span,
        o[1] - 1.5 * span,
        o[0] + 1.5 * span,
        o[1] + 1.5 * span,
    ];
    let tmp = std::env::temp_dir().join(format!("formation-inset-{}.png", std::process::id()));
    let opts = RenderOptions {
        width: 3 * size,
        window: Some(big),
        ..RenderOptions::default()
    };
    render_site_with(&setup.site, &opts, &[], &tmp)?;
    let full = Pixmap::load_png(&tmp)?;
    std::fs::remove_file(&tmp)?;
    let mut pix = Pixmap::new(size, size).ok_or("bad inset size")?;
    let id = Transform::identity();
    let offset = -(size as i32);
    pix.draw_pixmap(
        offset,
        offset,
        full.as_ref(),
        &PixmapPaint::default(),
        id,
        None,
    );
    let view = View {
        x0: o[0] - span / 2.0,
        y1: o[1] + span / 2.0,
        scale: f64::from(size) / span,
    };
    for (k, body) in run.ids().into_iter().enumerate() {
        let track = run.track(body, c.tracks.0, c.tracks.1);
        polyline(&mut pix, &view, &track, 2.0, BODY[k]);
    }
    for &t in &c.shots {
        let Some(l) = run.at(run.leader, t) else {
            continue;
        };
        let (lx, ly) = view.px(l);
        for body in &run.members {
            let Some(p) = run.at(*body, t) else { continue };
            let (x, y) = view.px(p);
            let mut pb = PathBuilder::new();
            pb.move_to(lx, ly);
            pb.line_to(x, y);
            if let Some(path) = pb.finish() {
                pix.stroke_path(&path, &paint([40, 40, 40, 190]), &stroke(2.0), id, None);
            }
        }
        for (k, body) in run.ids().into_iter().enumerate() {
            if let Some(p) = run.at(body, t) {
                let (x, y) = view.px(p);
                dot(&mut pix, x, y, 7.0, BODY[k]);
            }
        }
    }
    if (run.red[0] - o[0]).abs() < span / 2.0 && (run.red[1] - o[1]).abs() < span / 2.0 {
        let (x, y) = view.px(run.red);
        dot(&mut pix, x, y, 10.0, RED);
    } else if dist(run.red, o) < 3.0 * span {
        // Off the close-up: an arrow from the middle towards it.
        let b = (run.red[1] - o[1]).atan2(run.red[0] - o[0]);
        let r = 0.42 * span;
        let (ax, ay) = view.px([o[0] + 0.25 * span * b.cos(), o[1] + 0.25 * span * b.sin()]);
        let (bx, by) = view.px([o[0] + r * b.cos(), o[1] + r * b.sin()]);
        let mut pb = PathBuilder::new();
        pb.move_to(ax, ay);
        pb.line_to(bx, by);
        let head = |a: f64| {
            let q = [
                o[0] + (r - 4.0) * b.cos() - 2.5 * (b + a).sin(),
                o[1] + (r - 4.0) * b.sin() + 2.5 * (b + a).cos(),
            ];
            view.px(q)
        };
        let (h1, h2) = (head(0.0), head(std::f64::consts::PI));
        pb.move_to(h1.0, h1.1);
        pb.line_to(bx, by);
        pb.line_to(h2.0, h2.1);
        if let Some(path) = pb.finish() {
            pix.stroke_path(&path, &paint(RED), &stroke(4.0), id, None);
        }
        if let Ok(font) = FontRef::try_from_slice(FONT) {
            let text = format!("red trooper, {:.0} m", dist(run.red, o));
            let w = text_width(&font, &text, 17.0);
            let x = (bx - w / 2.0).clamp(4.0, size as f32 - w - 4.0);
            let y = if by < size as f32 / 2.0 {
                by + 30.0
            } else {
                by - 14.0
            };
            label(&mut pix, &font, &text, x, y, 17.0, [180, 20, 20]);
        }
    }
    Ok(pix)
}

fn main() -> Result<(), Error> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| format!("{root}/docs/formation.png"));
    let setup = Setup::default_town()?;
    let wall = Instant::now();
    let run = run(&setup)?;
    println!(
        "the squad arrived after {:.0} s ({:.1} min) of simulated time, {:.1} s of wall time; {} changes of formation:",
        run.arrived,
        run.arrived / 60.0,
        wall.elapsed().as_secs_f64(),
        run.switches.len()
    );
    for s in &run.switches {
        println!(
            "  {:>7.1} s  {:<6} -> {:<6} ({})",
            s.t.as_secs_f64(),
            s.from,
            s.to,
            why(&s.reason)
        );
    }
    // The whole walk, with room above it for the legends.
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for p in run
        .log
        .iter()
        .map(|p| [p.pos[0], p.pos[1]])
        .chain([run.red])
    {
        (x0, y0, x1, y1) = (x0.min(p[0]), y0.min(p[1]), x1.max(p[0]), y1.max(p[1]));
    }
    let window = [
        x0 - 150.0,
        y0 - 120.0,
        x1 + 150.0,
        y1 + 0.22 * (y1 - y0) + 150.0,
    ];
    let width = 1500;
    let names = [
        "leader",
        "member 1 (alpha)",
        "member 2 (bravo)",
        "member 3 (charlie)",
    ];
    let mut overlays: Vec<Overlay> = run
        .ids()
        .into_iter()
        .enumerate()
        .map(|(k, body)| {
            let mut o = Overlay::line(names[k], run.track(body, 0.0, f64::MAX), BODY[k]);
            o.width = if k == 0 { 3.0 } else { 2.0 };
            o
        })
        .collect();
    // Legend entries only: the marks are drawn below, on top of everything.
    for p in Pattern::ALL {
        let cause = match p {
            Pattern::File => "narrow street",
            Pattern::Column => "street",
            Pattern::Line => "contact: line abreast facing the threat",
            Pattern::Wedge => "open ground",
        };
        let mut o = Overlay::line(
            format!("formation changes to {p} ({cause})"),
            Vec::new(),
            pattern_colour(p),
        );
        o.dots = 7.0;
        overlays.push(o);
    }
    let mut red = Overlay::line("red trooper (the squad sees it: contact)", Vec::new(), RED);
    red.dots = 9.0;
    overlays.push(red);
    let opts = RenderOptions {
        width,
        window: Some(window),
        title: format!(
            "A squad of four in formation across the town: {:.0} min, {} changes",
            run.arrived / 60.0,
            run.switches.len()
        ),
        ..RenderOptions::default()
    };
    let tmp = std::env::temp_dir().join(format!("formation-map-{}.png", std::process::id()));
    render_site_with(&setup.site, &opts, &overlays, &tmp)?;
    let map = Pixmap::load_png(&tmp)?;
    std::fs::remove_file(&tmp)?;
    let font = FontRef::try_from_slice(FONT)?;
    let view = View::of(window, width);
    // The close-ups: the middle of the longest stretch of wedge, the first line, the first
    // file.
    let mut longest = (0.0, 0.0);
    for w in run.switches.windows(2) {
        let (a, b) = (w[0].t.as_secs_f64(), w[1].t.as_secs_f64());
        if w[0].to == Pattern::Wedge && b - a > longest.1 - longest.0 {
            longest = (a, b);
        }
    }
    let first = |p: Pattern| {
        run.switches
            .iter()
            .find(|s| s.to == p)
            .map(|s| s.t.as_secs_f64())
    };
    let mut shots = Vec::new();
    let mid = (longest.0 + longest.1) / 2.0;
    if let Some(c) = run.at(run.leader, mid) {
        shots.push(CloseUp {
            centre: c,
            span: 80.0,
            tracks: (mid - 60.0, mid + 60.0),
            shots: vec![mid - 30.0, mid, mid + 30.0],
            caption: format!("wedge on open ground, {:.0} min", mid / 60.0),
        });
    }
    if let Some(t) = first(Pattern::Line)
        && let Some(l) = run.at(run.leader, t + 25.0)
    {
        shots.push(CloseUp {
            centre: l,
            span: 70.0,
            tracks: (t - 20.0, t + 45.0),
            shots: vec![t + 10.0, t + 25.0, t + 40.0],
            caption: format!("line abreast facing the red trooper, {:.0} min", t / 60.0),
        });
    }
    if let Some(t) = first(Pattern::File) {
        let t = t + 10.0;
        if let Some(c) = run.at(run.leader, t) {
            shots.push(CloseUp {
                centre: c,
                span: 80.0,
                tracks: (t - 40.0, t + 40.0),
                shots: vec![t - 10.0, t + 5.0, t + 20.0],
                caption: format!("file in a narrow street, {:.0} min", t / 60.0),
            });
        }
    }
    // The canvas: the map, and a column of close-ups on its right.
    let (inset, pad, head) = (520u32, 20u32, 34u32);
    let mut pix = Pixmap::new(width + inset + 2 * pad, map.height()).ok_or("bad canvas size")?;
    pix.fill(Color::WHITE);
    let id = Transform::identity();
    pix.draw_pixmap(0, 0, map.as_ref(), &PixmapPaint::default(), id, None);
    // Where each close-up is on the map.
    for (k, c) in shots.iter().enumerate() {
        let (cx, cy) = view.px(c.centre);
        let half = (c.span / 2.0 * view.scale) as f32;
        if let Some(r) = Rect::from_xywh(cx - half, cy - half, 2.0 * half, 2.0 * half) {
            pix.stroke_path(
                &PathBuilder::from_rect(r),
                &paint([40, 40, 40, 255]),
                &stroke(2.0),
                id,
                None,
            );
            label(
                &mut pix,
                &font,
                &format!("{}", k + 1),
                cx + half + 4.0,
                cy - half + 16.0,
                18.0,
                [20, 20, 20],
            );
        }
    }
    // The changes of formation: a dot each, named where there is room.
    let mut taken: Vec<Rect> = Vec::new();
    for s in &run.switches {
        let (x, y) = view.px(s.at);
        dot(&mut pix, x, y, 7.0, pattern_colour(s.to));
    }
    for p in [run.start, run.goal] {
        let (x, y) = view.px(p);
        dot(&mut pix, x, y, 9.0, [20, 20, 20, 255]);
    }
    let (rx, ry) = view.px(run.red);
    dot(&mut pix, rx, ry, 9.0, RED);
    let marks = [
        (run.start, "START".to_string()),
        (run.goal, "GOAL".to_string()),
    ]
    .into_iter()
    .chain(
        run.switches
            .iter()
            .map(|s| (s.at, format!("{} {:.0}'", s.to, s.t.as_secs_f64() / 60.0))),
    );
    for (p, text) in marks {
        let (x, y) = view.px(p);
        let size = 17.0;
        let tw = text_width(&font, &text, size);
        for (dx, dy) in [
            (10.0, 6.0),
            (-tw - 10.0, 6.0),
            (-tw / 2.0, -12.0),
            (-tw / 2.0, 26.0),
        ] {
            let Some(r) = Rect::from_xywh(x + dx - 3.0, y + dy - size, tw + 6.0, size * 1.2) else {
                continue;
            };
            if !taken.iter().any(|q| r.intersect(q).is_some()) {
                taken.push(r);
                label(&mut pix, &font, &text, x + dx, y + dy, size, [20, 20, 20]);
                break;
            }
        }
    }
    let mut y = pad;
    for (k, c) in shots.iter().enumerate() {
        let ip = close_up(&setup, &run, c, inset)?;
        let x = width + pad;
        pix.draw_pixmap(
            x as i32,
            (y + head) as i32,
            ip.as_ref(),
            &PixmapPaint::default(),
            id,
            None,
        );
        let frame = Rect::from_xywh(x as f32, (y + head) as f32, inset as f32, inset as f32)
            .ok_or("bad frame")?;
        pix.stroke_path(
            &PathBuilder::from_rect(frame),
            &paint([40, 40, 40, 255]),
            &stroke(2.0),
            id,
            None,
        );
        let title = format!("{} · {} ({:.0} m across)", k + 1, c.caption, c.span);
        label(
            &mut pix,
            &font,
            &title,
            x as f32,
            (y + 24) as f32,
            19.0,
            [20, 20, 20],
        );
        y += inset + head + pad;
    }
    let note = [
        "Close-ups: each body's trajectory, and the squad",
        "three times, 15 s apart (dots; grey lines from the",
        "leader, black, to each member).",
        "Map: a dot where the formation changed, named with",
        "the new formation and the minute, e.g. column 37'.",
    ];
    for (i, line) in note.iter().enumerate() {
        label(
            &mut pix,
            &font,
            line,
            (width + pad) as f32,
            (y + 10 + 24 * i as u32) as f32,
            17.0,
            [60, 60, 60],
        );
    }
    pix.save_png(&out)?;
    println!("wrote {out} ({} x {})", pix.width(), pix.height());
    Ok(())
}
