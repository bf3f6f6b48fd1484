//! The static map as Foxglove draws it: terrain, streets, paths, bridges, buildings,
//! forbidden zones and named places.

use super::{kv, label, lines};
use crate::foxglove::{
    Color, CylinderPrimitive, LineType, Pose, SceneEntity, SceneUpdate, TriangleListPrimitive,
    Vector3,
};
use crate::frame::Scene;
use crate::geometry::triangulate;

/// Most terrain vertices along one side of the drawn ground mesh (finer grids are decimated).
const MAX_TERRAIN_SIDE: usize = 256;

/// Lines are drawn this far above the ground so the terrain does not hide them, metres.
const LIFT: f64 = 0.3;

/// A point lifted onto the ground (never below it) and a little above.
fn on_ground(scene: &Scene, p: [f64; 3]) -> [f64; 3] {
    let ground = scene.terrain.height_at(p[0], p[1]).unwrap_or(p[2]);
    [p[0], p[1], p[2].max(ground) + LIFT]
}

fn polyline_segments(scene: &Scene, lines: &[Vec<[f64; 3]>]) -> Vec<Vector3> {
    let mut out = Vec::new();
    for line in lines {
        for w in line.windows(2) {
            out.push(Vector3::mm(on_ground(scene, w[0])));
            out.push(Vector3::mm(on_ground(scene, w[1])));
        }
    }
    out
}

fn terrain_entity(scene: &Scene) -> Option<SceneEntity> {
    let t = &scene.terrain;
    if t.nx < 2 || t.ny < 2 || t.z.len() < t.nx * t.ny {
        return None;
    }
    let step = t.nx.max(t.ny).div_ceil(MAX_TERRAIN_SIDE).max(1);
    let cols: Vec<usize> = (0..t.nx).step_by(step).collect();
    let rows: Vec<usize> = (0..t.ny).step_by(step).collect();
    let (lo, hi) =
        t.z.iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &z| {
                (lo.min(z), hi.max(z))
            });
    let span = f64::from(hi - lo).max(1e-9);
    let (low, mid, high) = (
        Color::rgb(0.36, 0.55, 0.3),
        Color::rgb(0.62, 0.55, 0.38),
        Color::rgb(0.88, 0.87, 0.84),
    );
    let mix = |a: Color, b: Color, f: f64| {
        Color::rgb(
            ((a.r + (b.r - a.r) * f) * 1e3).round() / 1e3,
            ((a.g + (b.g - a.g) * f) * 1e3).round() / 1e3,
            ((a.b + (b.b - a.b) * f) * 1e3).round() / 1e3,
        )
    };
    let mut points = Vec::with_capacity(cols.len() * rows.len());
    let mut colors = Vec::with_capacity(cols.len() * rows.len());
    for &j in &rows {
        for &i in &cols {
            let z = f64::from(t.z[j * t.nx + i]);
            points.push(Vector3::mm([
                t.origin[0] + i as f64 * t.cell,
                t.origin[1] + j as f64 * t.cell,
                z,
            ]));
            let f = (z - f64::from(lo)) / span;
            colors.push(if f < 0.5 {
                mix(low, mid, f * 2.0)
            } else {
                mix(mid, high, f * 2.0 - 1.0)
            });
        }
    }
    let w = u32::try_from(cols.len()).ok()?;
    let h = u32::try_from(rows.len()).ok()?;
    let mut indices = Vec::with_capacity(6 * cols.len() * rows.len());
    for j in 0..h - 1 {
        for i in 0..w - 1 {
            let (a, b, c, d) = (
                j * w + i,
                j * w + i + 1,
                (j + 1) * w + i,
                (j + 1) * w + i + 1,
            );
            indices.extend([a, b, d, a, d, c]);
        }
    }
    let mut e = SceneEntity::new(0, "terrain");
    e.triangles.push(TriangleListPrimitive {
        pose: Pose::at([0.0; 3], 0.0),
        points,
        color: low,
        colors,
        indices,
    });
    e.metadata.push(kv("decimation", step));
    Some(e)
}

fn buildings_entity(scene: &Scene) -> SceneEntity {
    let mut points = Vec::new();
    let mut indices = Vec::new();
    let mut outline = Vec::new();
    for b in &scene.buildings {
        let mut ring = b.footprint.as_slice();
        if ring.len() >= 2 && ring.first() == ring.last() {
            ring = &ring[..ring.len() - 1];
        }
        let n = ring.len();
        let Ok(first) = u32::try_from(points.len()) else {
            break;
        };
        if n < 3 || u32::try_from(points.len() + 2 * n).is_err() {
            continue;
        }
        let top = b.base + b.height;
        for p in ring {
            points.push(Vector3::mm([p[0], p[1], b.base]));
        }
        for p in ring {
            points.push(Vector3::mm([p[0], p[1], top]));
        }
        // n < 2^31 here, so the casts below are exact.
        let n32 = n as u32;
        for k in 0..n32 {
            let (a, b2) = (first + k, first + (k + 1) % n32);
            let (at, bt) = (a + n32, b2 + n32);
            indices.extend([a, b2, bt, a, bt, at]);
            outline.push(points[(at) as usize]);
            outline.push(points[(bt) as usize]);
        }
        for t in triangulate(ring) {
            indices.extend(t.iter().map(|&k| first + n32 + k as u32));
        }
    }
    let mut e = SceneEntity::new(0, "buildings");
    e.triangles.push(TriangleListPrimitive {
        pose: Pose::at([0.0; 3], 0.0),
        points,
        color: Color::rgb(0.78, 0.74, 0.68),
        colors: Vec::new(),
        indices,
    });
    e.lines.push(lines(
        LineType::List,
        outline,
        1.0,
        true,
        Color::rgb(0.35, 0.32, 0.3),
    ));
    e.metadata.push(kv("count", scene.buildings.len()));
    e
}

/// A layer of polylines: id, lines, width (metres) and colour.
type LineLayer<'a> = (&'a str, &'a [Vec<[f64; 3]>], f64, Color);

/// `/map`: terrain, streets, paths, bridges, buildings, forbidden zones and named places,
/// sent once (lifetime: forever).
pub fn map_update(scene: &Scene) -> SceneUpdate {
    let mut entities = Vec::new();
    entities.extend(terrain_entity(scene));
    let layers: [LineLayer<'_>; 3] = [
        ("streets", &scene.streets, 4.0, Color::rgb(0.3, 0.3, 0.32)),
        ("paths", &scene.paths, 1.5, Color::rgb(0.55, 0.42, 0.3)),
        ("bridges", &scene.bridges, 6.0, Color::rgb(0.5, 0.45, 0.6)),
    ];
    for (id, layer, width, color) in layers {
        if layer.is_empty() {
            continue;
        }
        let mut e = SceneEntity::new(0, id);
        e.lines.push(lines(
            LineType::List,
            polyline_segments(scene, layer),
            width,
            false,
            color,
        ));
        e.metadata.push(kv("count", layer.len()));
        entities.push(e);
    }
    if !scene.buildings.is_empty() {
        entities.push(buildings_entity(scene));
    }
    if !scene.forbidden.is_empty() {
        let rings: Vec<Vec<[f64; 3]>> = scene
            .forbidden
            .iter()
            .filter(|r| r.len() >= 2)
            .map(|r| {
                let mut v: Vec<[f64; 3]> = r.iter().map(|p| [p[0], p[1], 0.0]).collect();
                v.push(v[0]);
                v
            })
            .collect();
        let mut e = SceneEntity::new(0, "forbidden");
        e.lines.push(lines(
            LineType::List,
            polyline_segments(scene, &rings),
            2.0,
            true,
            Color::rgb(1.0, 0.2, 0.2).alpha(0.7),
        ));
        e.metadata.push(kv("count", scene.forbidden.len()));
        entities.push(e);
    }
    for (name, &p) in &scene.places {
        let gold = Color::rgb(1.0, 0.8, 0.1);
        let mut e = SceneEntity::new(0, format!("place/{name}"));
        e.cylinders.push(CylinderPrimitive {
            pose: Pose::at([p[0], p[1], p[2] + 5.0], 0.0),
            size: Vector3 {
                x: 1.0,
                y: 1.0,
                z: 10.0,
            },
            bottom_scale: 1.0,
            top_scale: 1.0,
            color: gold,
        });
        e.texts
            .push(label([p[0], p[1], p[2] + 13.0], name.clone(), 15.0, gold));
        entities.push(e);
    }
    SceneUpdate {
        deletions: Vec::new(),
        entities,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;

    #[test]
    fn buildings_are_closed_prisms_with_a_roof() {
        let scene = synthetic::scene();
        let e = buildings_entity(&scene);
        let mesh = &e.triangles[0];
        let n: usize = scene.buildings.iter().map(|b| b.footprint.len()).sum();
        assert_eq!(mesh.points.len(), 2 * n);
        // Two wall triangles per edge, n - 2 roof triangles per building.
        let triangles = 2 * n + (n - 2 * scene.buildings.len());
        assert_eq!(mesh.indices.len(), 3 * triangles);
        assert!(
            mesh.indices
                .iter()
                .all(|&i| (i as usize) < mesh.points.len())
        );
        let top = mesh.points.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        let highest = scene
            .buildings
            .iter()
            .map(|b| b.base + b.height)
            .fold(f64::MIN, f64::max);
        assert!((top - highest).abs() < 1e-3);
    }

    #[test]
    fn lines_never_sink_below_the_terrain_and_fine_terrain_is_decimated() {
        let mut scene = synthetic::scene();
        scene.streets = vec![vec![[100.0, 100.0, -50.0], [200.0, 100.0, -50.0]]];
        let segs = polyline_segments(&scene, &scene.streets);
        for p in segs {
            let ground = scene.terrain.height_at(p.x, p.y).unwrap();
            assert!(p.z > ground, "{} under {ground}", p.z);
        }
        scene.terrain.nx = 1000;
        scene.terrain.ny = 600;
        scene.terrain.z = vec![1.0; 600_000];
        let t = terrain_entity(&scene).unwrap();
        let side = 1000usize.div_ceil(4);
        assert_eq!(t.triangles[0].points.len(), side * 600usize.div_ceil(4));
    }
}
