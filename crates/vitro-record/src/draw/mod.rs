//! How a scene and a frame look in Foxglove: the messages of the drawing channels.
//!
//! Everything is drawn in the world frame ([`WORLD_FRAME`], metres, x east, y north, z up).
//! Entities get a body shape per type (a box for vehicles, a cylinder for people and
//! helicopters, a flat box for fixed-wing aircraft), coloured by side (friendly blue, hostile
//! red, neutral green, unknown yellow), a heading arrow as long as a second of travel, and a
//! label.

pub use crate::foxglove::WORLD_FRAME;
use crate::foxglove::{
    ArrowPrimitive, Color, CubePrimitive, CylinderPrimitive, FrameTransform, FrameTransforms,
    KeyValuePair, LinePrimitive, LineType, LocationFix, Log, LogLevel, Pose, Quaternion,
    SceneEntity, SceneEntityDeletion, SceneUpdate, SpherePrimitive, TextPrimitive, Time, Vector3,
};
use crate::frame::{EntityState, Frame, Geo, Side};

mod map;

pub use map::map_update;

/// The colour of a side, as the viewer and KML draw it.
pub fn side_color(side: Side) -> Color {
    match side {
        Side::Friendly => Color::rgb(0.15, 0.4, 1.0),
        Side::Hostile => Color::rgb(0.9, 0.1, 0.1),
        Side::Neutral => Color::rgb(0.1, 0.65, 0.2),
        Side::Unknown => Color::rgb(0.95, 0.8, 0.1),
    }
}

/// The lowercase name of a side (`"friendly"`, ...).
pub fn side_name(side: Side) -> &'static str {
    match side {
        Side::Friendly => "friendly",
        Side::Hostile => "hostile",
        Side::Neutral => "neutral",
        Side::Unknown => "unknown",
    }
}

/// A body shape and its size, metres.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Body {
    /// A box: length (along the heading), width, height.
    Box(f64, f64, f64),
    /// An upright cylinder: diameter, height.
    Cylinder(f64, f64),
    /// A sphere: diameter.
    Sphere(f64),
}

impl Body {
    /// The body drawn for an entity type.
    pub fn of_kind(kind: &str) -> Self {
        match kind {
            "truck" => Self::Box(8.0, 2.5, 3.2),
            "car" => Self::Box(4.5, 1.8, 1.5),
            "ugv" => Self::Box(3.0, 2.0, 1.6),
            "trooper" | "vip" | "hvt" => Self::Cylinder(0.8, 1.8),
            "ctol" => Self::Box(1.2, 2.7, 0.3),
            "vtol" => Self::Cylinder(4.0, 1.0),
            _ => Self::Sphere(1.5),
        }
    }

    /// Height of the body, metres.
    pub fn height(self) -> f64 {
        match self {
            Self::Box(_, _, h) | Self::Cylinder(_, h) => h,
            Self::Sphere(d) => d,
        }
    }

    /// Length along the heading, metres.
    pub fn length(self) -> f64 {
        match self {
            Self::Box(l, _, _) => l,
            Self::Cylinder(d, _) | Self::Sphere(d) => d,
        }
    }
}

/// The colour an entity is drawn in: its side's, dimmed when down or captured, faded when
/// aboard a vehicle or extracted.
fn entity_color(e: &EntityState) -> Color {
    let c = side_color(e.side);
    match e.status.as_str() {
        "down" | "captured" => Color::rgb(c.r * 0.4, c.g * 0.4, c.b * 0.4).alpha(0.7),
        "aboard" | "extracted" => c.alpha(0.35),
        _ => c,
    }
}

fn kv(key: &str, value: impl ToString) -> KeyValuePair {
    KeyValuePair {
        key: key.to_owned(),
        value: value.to_string(),
    }
}

fn label(at: [f64; 3], text: String, size: f64, color: Color) -> TextPrimitive {
    TextPrimitive {
        pose: Pose::at(at, 0.0),
        billboard: true,
        font_size: size,
        scale_invariant: true,
        color,
        text,
    }
}

fn lines(
    kind: LineType,
    points: Vec<Vector3>,
    thickness: f64,
    pixels: bool,
    color: Color,
) -> LinePrimitive {
    LinePrimitive {
        kind,
        pose: Pose::at([0.0; 3], 0.0),
        thickness,
        scale_invariant: pixels,
        points,
        color,
        colors: Vec::new(),
        indices: Vec::new(),
    }
}

/// The drawn entity for one entity state: body, heading arrow, label and its state as metadata.
pub fn entity(t_ns: u64, e: &EntityState) -> SceneEntity {
    let body = Body::of_kind(&e.kind);
    let color = entity_color(e);
    let h = body.height();
    let centre = [e.pos[0], e.pos[1], e.pos[2] + h / 2.0];
    let mut out = SceneEntity::new(t_ns, e.name.clone());
    let pose = Pose::at(centre, e.heading);
    match body {
        Body::Box(l, w, h) => out.cubes.push(CubePrimitive {
            pose,
            size: Vector3 { x: l, y: w, z: h },
            color,
        }),
        Body::Cylinder(d, h) => out.cylinders.push(CylinderPrimitive {
            pose,
            size: Vector3 { x: d, y: d, z: h },
            bottom_scale: 1.0,
            top_scale: 1.0,
            color,
        }),
        Body::Sphere(d) => out.spheres.push(SpherePrimitive {
            pose,
            size: Vector3 { x: d, y: d, z: d },
            color,
        }),
    }
    let speed = if e.speed.is_finite() {
        e.speed.abs()
    } else {
        0.0
    };
    let length = (body.length() / 2.0 + speed).clamp(1.0, 60.0);
    out.arrows.push(ArrowPrimitive {
        pose,
        shaft_length: length * 0.8,
        shaft_diameter: 0.3,
        head_length: length * 0.2,
        head_diameter: 0.9,
        color: color.alpha(0.9),
    });
    let text = if e.status == "active" {
        e.name.clone()
    } else {
        format!("{} ({})", e.name, e.status)
    };
    out.texts.push(label(
        [e.pos[0], e.pos[1], e.pos[2] + h + 2.0],
        text,
        13.0,
        Color::rgb(1.0, 1.0, 1.0),
    ));
    out.metadata = vec![
        kv("id", e.id),
        kv("kind", &e.kind),
        kv("side", side_name(e.side)),
        kv("level", &e.level),
        kv("status", &e.status),
        kv("speed_mps", format!("{:.2}", e.speed)),
    ];
    out
}

/// `/entities`: every entity of a frame, replacing the previous frame's.
pub fn entities_update(frame: &Frame) -> SceneUpdate {
    SceneUpdate {
        deletions: vec![SceneEntityDeletion::all(frame.t_ns)],
        entities: frame
            .entities
            .iter()
            .map(|e| entity(frame.t_ns, e))
            .collect(),
    }
}

/// `/detections`: a line from each observer's eye to what it sees, coloured by the side the
/// observer takes the target for.
pub fn detections_update(frame: &Frame) -> SceneUpdate {
    let mut update = SceneUpdate {
        deletions: vec![SceneEntityDeletion::all(frame.t_ns)],
        entities: Vec::new(),
    };
    if frame.detections.is_empty() {
        return update;
    }
    let mut points = Vec::with_capacity(2 * frame.detections.len());
    let mut colors = Vec::with_capacity(2 * frame.detections.len());
    for d in &frame.detections {
        points.push(Vector3::mm(d.from));
        points.push(Vector3::mm(d.to));
        let c = side_color(d.seen_as).alpha(0.8);
        colors.extend([c, c]);
    }
    let mut line = lines(LineType::List, points, 2.0, true, Color::rgb(1.0, 1.0, 1.0));
    line.colors = colors;
    let mut e = SceneEntity::new(frame.t_ns, "detections");
    e.lines.push(line);
    e.metadata.push(kv("count", frame.detections.len()));
    update.entities.push(e);
    update
}

fn find(frame: &Frame, id: u32) -> Option<&EntityState> {
    frame.entities.iter().find(|e| e.id == id)
}

fn name_of(frame: &Frame, id: u32) -> String {
    find(frame, id).map_or_else(|| format!("#{id}"), |e| e.name.clone())
}

/// `/intentions`: each stating agent's path as a line strip and its intention as a label.
pub fn intentions_update(frame: &Frame) -> SceneUpdate {
    let mut update = SceneUpdate {
        deletions: vec![SceneEntityDeletion::all(frame.t_ns)],
        entities: Vec::with_capacity(frame.intentions.len()),
    };
    for i in &frame.intentions {
        let who = find(frame, i.id);
        let name = who.map_or_else(|| format!("#{}", i.id), |e| e.name.clone());
        let color = who.map_or(side_color(Side::Unknown), |e| side_color(e.side));
        let mut e = SceneEntity::new(frame.t_ns, format!("intent/{name}"));
        if i.original_path.len() >= 2 {
            let points = i.original_path.iter().map(|&p| Vector3::mm(p)).collect();
            let grey = Color::rgb(0.6, 0.6, 0.6).alpha(0.6);
            e.lines
                .push(lines(LineType::Strip, points, 1.0, true, grey));
        }
        if i.path.len() >= 2 {
            let points = i.path.iter().map(|&p| Vector3::mm(p)).collect();
            e.lines
                .push(lines(LineType::Strip, points, 2.0, true, color.alpha(0.7)));
        }
        let anchor = who
            .map(|w| {
                let h = Body::of_kind(&w.kind).height();
                [w.pos[0], w.pos[1], w.pos[2] + h + 6.0]
            })
            .or_else(|| i.path.first().copied());
        if let Some(at) = anchor {
            e.texts
                .push(label(at, format!("{name}: {}", i.text), 11.0, color));
        }
        e.metadata = vec![kv("intention", &i.text), kv("plan", i.plan.join("; "))];
        update.entities.push(e);
    }
    update
}

/// `/sensors`: each sensor's footprint as the outline of its sector (a circle when it sees
/// all around), one indexed line list per side, in the side's colour.
pub fn sensors_update(frame: &Frame) -> SceneUpdate {
    let mut update = SceneUpdate {
        deletions: vec![SceneEntityDeletion::all(frame.t_ns)],
        entities: Vec::new(),
    };
    let sides = [Side::Friendly, Side::Hostile, Side::Neutral, Side::Unknown];
    let mut by_side: [LinePrimitive; 4] = sides.map(|side| {
        lines(
            LineType::List,
            Vec::new(),
            1.0,
            true,
            side_color(side).alpha(0.5),
        )
    });
    for s in &frame.sensors {
        let Some(e) = find(frame, s.id) else {
            continue;
        };
        let Some(line) = sides
            .iter()
            .position(|&x| x == e.side)
            .map(|k| &mut by_side[k])
        else {
            continue;
        };
        let o = [e.pos[0], e.pos[1], e.pos[2] + 0.5];
        let full = s.fov >= std::f64::consts::TAU;
        let fov = s.fov.clamp(0.0, std::f64::consts::TAU);
        let (start, steps) = (s.heading - fov / 2.0, if full { 24u32 } else { 8 });
        let Ok(first) = u32::try_from(line.points.len()) else {
            break;
        };
        // The centre, then the arc; segments by index: centre-arc-...-arc-centre.
        line.points.push(Vector3::mm(o));
        for k in 0..=steps {
            let a = start + fov * f64::from(k) / f64::from(steps);
            let (x, y) = (o[0] + s.range * a.cos(), o[1] + s.range * a.sin());
            line.points.push(Vector3::mm([x, y, o[2]]));
        }
        if !full {
            line.indices.extend([first, first + 1]);
        }
        for k in 1..=steps {
            line.indices.extend([first + k, first + k + 1]);
        }
        if !full {
            line.indices.extend([first + steps + 1, first]);
        }
    }
    let drawn: Vec<LinePrimitive> = by_side
        .into_iter()
        .filter(|l| !l.points.is_empty())
        .collect();
    if !drawn.is_empty() {
        let mut e = SceneEntity::new(frame.t_ns, "sensors");
        e.lines = drawn;
        e.metadata.push(kv("count", frame.sensors.len()));
        update.entities.push(e);
    }
    update
}

/// `/tf`: one transform per entity, world → the entity (frame named after it).
pub fn transforms(frame: &Frame) -> FrameTransforms {
    FrameTransforms {
        transforms: frame
            .entities
            .iter()
            .map(|e| FrameTransform {
                timestamp: Time::from_ns(frame.t_ns),
                parent_frame_id: WORLD_FRAME.to_owned(),
                child_frame_id: e.name.clone(),
                translation: Vector3::mm(e.pos),
                rotation: Quaternion::yaw(e.heading),
            })
            .collect(),
    }
}

/// A GNSS fix for one entity (latitude and longitude through `geo`).
pub fn location_fix(geo: &Geo, t_ns: u64, e: &EntityState) -> LocationFix {
    let [lat, lon, alt] = geo.to_wgs84(e.pos);
    let h = if e.heading.is_finite() {
        e.heading
    } else {
        0.0
    };
    let speed = if e.speed.is_finite() { e.speed } else { 0.0 };
    let clockwise_from_north = (std::f64::consts::FRAC_PI_2 - h).rem_euclid(std::f64::consts::TAU);
    LocationFix {
        timestamp: Time::from_ns(t_ns),
        frame_id: e.name.clone(),
        latitude: crate::foxglove::round_to(lat, 1e9),
        longitude: crate::foxglove::round_to(lon, 1e9),
        altitude: crate::foxglove::round_to(alt, 1e3),
        position_covariance: [0.0; 9],
        position_covariance_type: 0,
        heading: crate::foxglove::round_to(clockwise_from_north, 1e6),
        velocity: Vector3::mm([speed * h.cos(), speed * h.sin(), 0.0]),
        color: entity_color(e),
    }
}

/// `/log`: one line per message sent (at its sending time) and per line of the frame's log.
pub fn logs(frame: &Frame) -> Vec<(u64, Log)> {
    let mut out = Vec::with_capacity(frame.messages.len() + frame.log.len());
    for m in &frame.messages {
        let to =
            m.to.map_or_else(|| "all".to_owned(), |id| name_of(frame, id));
        let from = name_of(frame, m.from);
        let (level, fate) = if m.delivered {
            (LogLevel::Debug, "")
        } else {
            (LogLevel::Warning, " (not delivered)")
        };
        out.push((
            m.t_ns,
            Log {
                timestamp: Time::from_ns(m.t_ns),
                level,
                message: format!("{from} -> {to}: {}{fate}", m.kind),
                name: from,
                file: String::new(),
                line: 0,
            },
        ));
    }
    for line in &frame.log {
        out.push((
            frame.t_ns,
            Log {
                timestamp: Time::from_ns(frame.t_ns),
                level: LogLevel::Info,
                message: line.clone(),
                name: "mission".to_owned(),
                file: String::new(),
                line: 0,
            },
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;

    #[test]
    fn bodies_follow_the_entity_type_and_colours_the_side() {
        let scene = synthetic::scene();
        let f = synthetic::frame(&scene, 3, 10);
        let drawn = entities_update(&f);
        assert_eq!(drawn.entities.len(), 10);
        for (e, d) in f.entities.iter().zip(&drawn.entities) {
            let shapes = (d.cubes.len(), d.cylinders.len(), d.spheres.len());
            let want = match Body::of_kind(&e.kind) {
                Body::Box(..) => (1, 0, 0),
                Body::Cylinder(..) => (0, 1, 0),
                Body::Sphere(..) => (0, 0, 1),
            };
            assert_eq!(shapes, want, "{}", e.kind);
            assert_eq!(d.arrows.len(), 1);
            let colour = d.arrows[0].color.alpha(1.0);
            if e.status == "active" {
                assert_eq!(colour, side_color(e.side), "{}", e.name);
            }
        }
        assert!(matches!(Body::of_kind("truck"), Body::Box(..)));
        assert!(matches!(Body::of_kind("vtol"), Body::Cylinder(..)));
        assert!(matches!(Body::of_kind("balloon"), Body::Sphere(..)));
    }

    #[test]
    fn sensors_draw_sector_outlines_at_their_range() {
        let scene = synthetic::scene();
        let mut f = synthetic::frame(&scene, 0, 4);
        f.sensors.truncate(1);
        f.sensors[0].fov = std::f64::consts::FRAC_PI_2;
        let e = f
            .entities
            .iter()
            .find(|e| e.id == f.sensors[0].id)
            .unwrap()
            .clone();
        let update = sensors_update(&f);
        let line = &update.entities[0].lines[0];
        assert_eq!(line.color, side_color(e.side).alpha(0.5));
        // The centre and 9 arc points; 8 arc segments and two radii, by index.
        assert_eq!(line.points.len(), 10);
        assert_eq!(line.indices.len(), 2 * 10);
        assert!(line.indices.iter().all(|&i| i < 10));
        let dist = |p: &Vector3| ((p.x - e.pos[0]).powi(2) + (p.y - e.pos[1]).powi(2)).sqrt();
        assert!(dist(&line.points[0]) < 1e-3);
        for p in &line.points[1..] {
            assert!((dist(p) - f.sensors[0].range).abs() < 0.01);
        }
        // All around: a closed circle, no radii.
        f.sensors[0].fov = 7.0;
        let circle = sensors_update(&f).entities[0].lines[0].clone();
        assert_eq!(circle.indices.len(), 2 * 24);
        assert_eq!(circle.indices.last(), Some(&25));
        f.sensors.clear();
        assert!(sensors_update(&f).entities.is_empty());
    }

    #[test]
    fn logs_name_sender_receiver_and_fate() {
        let scene = synthetic::scene();
        let f = synthetic::frame(&scene, 10, 5);
        let logs = logs(&f);
        assert_eq!(logs.len(), f.messages.len() + f.log.len());
        let lost = f.messages.iter().filter(|m| !m.delivered).count();
        let warned = logs
            .iter()
            .filter(|(_, l)| l.level == LogLevel::Warning)
            .count();
        assert_eq!(lost, warned);
        assert!(logs.iter().any(|(_, l)| l.message == "VIP picked up"));
        let m = &f.messages[0];
        assert_eq!(logs[0].0, m.t_ns);
        assert!(logs[0].1.message.starts_with(&name_of(&f, m.from)));
    }
}
