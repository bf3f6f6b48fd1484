//! Checks that every number of a scene or frame is finite before it is written.
//!
//! JSON has no NaN or infinity (serde_json writes `null`, which does not read back as a
//! number), so a recording refuses them with the place of the first one.

use crate::error::RecordError;
use crate::frame::{Frame, Scene};

fn check(
    values: impl IntoIterator<Item = f64>,
    t_ns: u64,
    what: impl Fn() -> String,
) -> Result<(), RecordError> {
    match values.into_iter().find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(value) => Err(RecordError::NotFinite {
            what: what(),
            value,
            t_ns,
        }),
    }
}

/// Every number of `scene` is finite.
pub(crate) fn check_scene(scene: &Scene) -> Result<(), RecordError> {
    let g = &scene.geo;
    check(
        [
            g.lat0,
            g.lon0,
            g.m_per_deg_lat,
            g.m_per_deg_lon,
            g.offset[0],
            g.offset[1],
            g.z0,
        ],
        0,
        || "the scene's geo-reference".to_owned(),
    )?;
    check(scene.extent, 0, || "the scene's extent".to_owned())?;
    for (name, layer) in [
        ("street", &scene.streets),
        ("path", &scene.paths),
        ("bridge", &scene.bridges),
    ] {
        for (k, line) in layer.iter().enumerate() {
            check(line.iter().flatten().copied(), 0, || format!("{name} {k}"))?;
        }
    }
    for (k, b) in scene.buildings.iter().enumerate() {
        let ring = b.footprint.iter().flatten().copied();
        check(ring.chain([b.base, b.height]), 0, || {
            format!("building {k}")
        })?;
    }
    for (k, ring) in scene.forbidden.iter().enumerate() {
        check(ring.iter().flatten().copied(), 0, || {
            format!("forbidden zone {k}")
        })?;
    }
    for (name, p) in &scene.places {
        check(*p, 0, || format!("place {name:?}"))?;
    }
    let t = &scene.terrain;
    check(
        [t.origin[0], t.origin[1], t.cell]
            .into_iter()
            .chain(t.z.iter().map(|&z| f64::from(z))),
        0,
        || "the terrain".to_owned(),
    )
}

/// Every number of `frame` is finite.
pub(crate) fn check_frame(frame: &Frame) -> Result<(), RecordError> {
    let t = frame.t_ns;
    for e in &frame.entities {
        check(e.pos.into_iter().chain([e.heading, e.speed]), t, || {
            format!("the pose of {}", e.name)
        })?;
    }
    for d in &frame.detections {
        check(d.from.into_iter().chain(d.to), t, || {
            format!("the detection of {} by {}", d.target, d.observer)
        })?;
    }
    for i in &frame.intentions {
        let paths = i.path.iter().chain(&i.original_path).flatten().copied();
        let weighted = i.heat.iter().chain(&i.belief);
        let weights = weighted.flat_map(|(p, w)| p.iter().copied().chain([*w]));
        check(paths.chain(weights), t, || {
            format!("the intention of entity {}", i.id)
        })?;
    }
    for s in &frame.sensors {
        check([s.range, s.heading, s.fov], t, || {
            format!("the {} footprint of entity {}", s.kind, s.id)
        })?;
    }
    for (name, &v) in &frame.metrics {
        check([v], t, || format!("metric {name:?}"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;

    #[test]
    fn the_first_non_finite_number_is_named() {
        let mut scene = synthetic::scene();
        assert!(check_scene(&scene).is_ok());
        scene.terrain.z[7] = f32::INFINITY;
        let err = check_scene(&scene).unwrap_err().to_string();
        assert!(err.contains("terrain") && err.contains("inf"), "{err}");

        let scene = synthetic::scene();
        let mut frame = synthetic::frame(&scene, 3, 4);
        assert!(check_frame(&frame).is_ok());
        frame.entities[2].heading = f64::NAN;
        let err = check_frame(&frame).unwrap_err().to_string();
        let name = &frame.entities[2].name;
        assert!(err.contains(name.as_str()) && err.contains("NaN"), "{err}");
    }
}
