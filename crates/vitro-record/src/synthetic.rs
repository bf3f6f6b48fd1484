//! A synthetic scene and frames: what tests, examples, benchmarks and a viewer under
//! construction record and replay before (or without) the mission.
//!
//! A 1 km square town of 100 m blocks on rolling terrain, near Kotka (60.47° N, 26.95° E);
//! entities of every type and side circling the centre at their own radius and speed, ground
//! entities on the ground and aircraft 120 m above it; detections of hostiles by the nearest
//! friendly within 200 m, a few messages a second, intentions with paths, metrics, log lines.
//! Everything is a pure function of its arguments.

use crate::frame::{
    Building, Detection, EntityState, Frame, Geo, Heightmap, Intention, MessageEvent, Scene,
    SensorFootprint, Side,
};
use std::f64::consts::TAU;

/// Sample period of [`frame`]: one second.
pub const PERIOD_NS: u64 = 1_000_000_000;

/// Entity types in the order [`frame`] hands them out.
const KINDS: [&str; 10] = [
    "truck", "trooper", "car", "trooper", "ugv", "vip", "ctol", "trooper", "vtol", "hvt",
];

fn ground(scene: &Scene, x: f64, y: f64) -> f64 {
    scene.terrain.height_at(x, y).unwrap_or(0.0)
}

/// The synthetic town.
pub fn scene() -> Scene {
    let (nx, ny, cell) = (41, 41, 25.0);
    let mut z = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 * cell, j as f64 * cell);
            z.push((10.0 + 8.0 * (x / 200.0).sin() * (y / 300.0).cos()) as f32);
        }
    }
    let mut scene = Scene {
        geo: Geo {
            lat0: 60.466,
            lon0: 26.945,
            m_per_deg_lat: 111_370.0,
            m_per_deg_lon: 54_900.0,
            offset: [500.0, 500.0],
            z0: 5.0,
        },
        terrain: Heightmap {
            nx,
            ny,
            origin: [0.0, 0.0],
            cell,
            z,
        },
        ..Scene::flat("synthetic town".to_owned(), 0, [0.0, 0.0, 1000.0, 1000.0])
    };
    let line = |scene: &Scene, from: [f64; 2], to: [f64; 2], n: usize| -> Vec<[f64; 3]> {
        (0..=n)
            .map(|k| {
                let f = k as f64 / n as f64;
                let (x, y) = (
                    from[0] + (to[0] - from[0]) * f,
                    from[1] + (to[1] - from[1]) * f,
                );
                [x, y, ground(scene, x, y)]
            })
            .collect()
    };
    for k in 0..=10 {
        let c = k as f64 * 100.0;
        scene.streets.push(line(&scene, [0.0, c], [1000.0, c], 10));
        scene.streets.push(line(&scene, [c, 0.0], [c, 1000.0], 10));
    }
    scene
        .paths
        .push(line(&scene, [0.0, 0.0], [1000.0, 1000.0], 20));
    let mut bridge = line(&scene, [400.0, 850.0], [600.0, 850.0], 4);
    for p in &mut bridge {
        p[2] += 4.0;
    }
    scene.bridges.push(bridge);
    for bx in 0..10 {
        for by in 0..10 {
            let (x0, y0) = (bx as f64 * 100.0 + 15.0, by as f64 * 100.0 + 15.0);
            let footprint = if (bx + by) % 3 == 0 {
                // An L shape.
                vec![
                    [x0, y0],
                    [x0 + 50.0, y0],
                    [x0 + 50.0, y0 + 25.0],
                    [x0 + 25.0, y0 + 25.0],
                    [x0 + 25.0, y0 + 50.0],
                    [x0, y0 + 50.0],
                ]
            } else {
                vec![
                    [x0, y0],
                    [x0 + 40.0, y0],
                    [x0 + 40.0, y0 + 30.0],
                    [x0, y0 + 30.0],
                ]
            };
            scene.buildings.push(Building {
                footprint,
                base: ground(&scene, x0, y0),
                height: 6.0 + ((bx * 7 + by * 3) % 10) as f64,
            });
        }
    }
    scene.forbidden.push(vec![
        [710.0, 710.0],
        [770.0, 710.0],
        [770.0, 760.0],
        [710.0, 760.0],
    ]);
    for (name, x, y) in [
        ("start", 50.0, 50.0),
        ("safehouse", 650.0, 350.0),
        ("extraction", 950.0, 950.0),
    ] {
        let z = ground(&scene, x, y);
        scene.places.insert(name.to_owned(), [x, y, z]);
    }
    scene
}

/// Side of the `k`-th of `n` entities: half friendly, a third hostile, the rest neutral or
/// unknown.
fn side_of(k: usize, n: usize) -> Side {
    if 2 * k < n {
        Side::Friendly
    } else if 6 * k < 5 * n {
        Side::Hostile
    } else if k.is_multiple_of(2) {
        Side::Neutral
    } else {
        Side::Unknown
    }
}

/// Position, heading and speed of entity `k` at `t` seconds: a circle about the centre.
fn motion(scene: &Scene, k: usize, t: f64, airborne: bool) -> ([f64; 3], f64, f64) {
    let r = 60.0 + 9.0 * k as f64;
    let speed = if airborne { 20.0 } else { 2.0 + (k % 7) as f64 };
    let w = speed / r;
    let a = w * t + k as f64 * 0.7;
    let (x, y) = (500.0 + r * a.cos(), 500.0 + r * a.sin());
    let z = ground(scene, x, y) + if airborne { 120.0 } else { 0.0 };
    ([x, y, z], (a + TAU / 4.0).rem_euclid(TAU), speed)
}

/// Frame `i` (at `i` seconds) with `entities` entities.
pub fn frame(scene: &Scene, i: u64, entities: usize) -> Frame {
    let t_ns = i * PERIOD_NS;
    let t = i as f64;
    let mut f = Frame {
        t_ns,
        events: i * 137,
        ..Frame::default()
    };
    for k in 0..entities {
        let kind = KINDS[k % KINDS.len()];
        let airborne = matches!(kind, "ctol" | "vtol");
        let (pos, heading, speed) = motion(scene, k, t, airborne);
        let side = side_of(k, entities);
        let status = if kind == "vip" && i >= 10 {
            "aboard"
        } else {
            "active"
        };
        f.entities.push(EntityState {
            id: k as u32,
            name: format!("{}-{k}", kind),
            kind: kind.to_owned(),
            side,
            level: if airborne {
                "kinematic"
            } else {
                "interpolated"
            }
            .to_owned(),
            pos,
            heading,
            speed,
            status: status.to_owned(),
        });
    }
    for target in f.entities.iter().filter(|e| e.side == Side::Hostile) {
        let d2 = |e: &EntityState| {
            (e.pos[0] - target.pos[0]).powi(2) + (e.pos[1] - target.pos[1]).powi(2)
        };
        let nearest = f
            .entities
            .iter()
            .filter(|e| e.side == Side::Friendly)
            .min_by(|a, b| d2(a).total_cmp(&d2(b)));
        if let Some(o) = nearest.filter(|o| d2(o) < 200.0 * 200.0) {
            f.detections.push(Detection {
                observer: o.id,
                target: target.id,
                from: [o.pos[0], o.pos[1], o.pos[2] + 1.7],
                to: [target.pos[0], target.pos[1], target.pos[2] + 0.9],
                seen_as: if d2(o) < 100.0 * 100.0 {
                    Side::Hostile
                } else {
                    Side::Unknown
                },
            });
        }
    }
    if entities > 1 {
        let n = entities as u64;
        for m in 0..3u64 {
            let from = ((i * 3 + m) % n) as u32;
            f.messages.push(MessageEvent {
                t_ns: t_ns.saturating_sub(PERIOD_NS) + (m + 1) * PERIOD_NS / 4,
                from,
                to: (m != 2).then_some(((from as u64 + 1) % n) as u32),
                kind: if m == 2 { "claim" } else { "contact" }.to_owned(),
                delivered: !(i + m).is_multiple_of(5),
            });
        }
    }
    for (k, e) in f.entities.iter().enumerate().filter(|(k, _)| k % 3 == 0) {
        let airborne = matches!(e.kind.as_str(), "ctol" | "vtol");
        f.intentions.push(Intention {
            id: e.id,
            text: format!("patrol loop {k}"),
            plan: vec![
                format!("goto n{}", (i + 1) % 20),
                format!("goto n{}", (i + 2) % 20),
            ],
            path: (1..=5)
                .map(|s| motion(scene, k, t + 5.0 * s as f64, airborne).0)
                .collect(),
            original_path: if k % 2 == 0 {
                (0..3)
                    .map(|s| motion(scene, k + 1, t + 5.0 * s as f64, airborne).0)
                    .collect()
            } else {
                Vec::new()
            },
            belief: if k == 0 {
                vec![([500.0, 500.0, 10.0], 0.75), ([520.0, 480.0, 10.0], 0.25)]
            } else {
                Vec::new()
            },
            ..Intention::default()
        });
    }
    for e in f.entities.iter().filter(|e| e.side == Side::Friendly) {
        f.sensors.push(SensorFootprint {
            id: e.id,
            kind: "camera".to_owned(),
            range: 150.0,
            heading: e.heading,
            fov: 1.2,
        });
    }
    f.metrics
        .insert("detections".to_owned(), f.detections.len() as f64);
    f.metrics
        .insert("messages_sent".to_owned(), (3 * (i + 1)) as f64);
    f.metrics.insert("time_s".to_owned(), t);
    if i == 10 {
        f.log.push("VIP picked up".to_owned());
    }
    if i > 0 && i.is_multiple_of(60) {
        f.log.push(format!("minute {}", i / 60));
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_hold_every_part_and_are_pure() {
        let s = scene();
        let f = frame(&s, 12, 40);
        assert_eq!(f, frame(&s, 12, 40));
        assert_eq!(f.t_ns, 12 * PERIOD_NS);
        assert_eq!(f.entities.len(), 40);
        assert!(!f.detections.is_empty() && !f.messages.is_empty() && !f.intentions.is_empty());
        for side in [Side::Friendly, Side::Hostile, Side::Neutral, Side::Unknown] {
            assert!(f.entities.iter().any(|e| e.side == side), "{side:?}");
        }
        // Every entity stays inside the terrain grid.
        assert!(
            f.entities
                .iter()
                .all(|e| s.terrain.height_at(e.pos[0], e.pos[1]).is_some())
        );
    }
}
