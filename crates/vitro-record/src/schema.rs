//! The JSON Schemas of a recording's channels (MCAP schema encoding `jsonschema`).
//!
//! Foxglove recognises a well-known message type by the schema *name* (`foxglove.SceneUpdate`);
//! the schema text describes the JSON a recording writes (the fields of [`crate::foxglove`]),
//! so generic MCAP tools can show and check it too.

use serde_json::{Value, json};

/// Schema name of the lossless scene channel.
pub const VITRO_SCENE: &str = "vitro.Scene";
/// Schema name of the lossless frame channel.
pub const VITRO_FRAME: &str = "vitro.Frame";
/// Schema name of the metrics channel.
pub const VITRO_METRICS: &str = "vitro.Metrics";
/// Foxglove's 3D scene update.
pub const SCENE_UPDATE: &str = "foxglove.SceneUpdate";
/// Foxglove's transforms.
pub const FRAME_TRANSFORMS: &str = "foxglove.FrameTransforms";
/// Foxglove's GNSS fix.
pub const LOCATION_FIX: &str = "foxglove.LocationFix";
/// Foxglove's log line.
pub const LOG: &str = "foxglove.Log";

/// The JSON Schema text for the schema `name`, or `None` if a recording does not use it.
pub fn schema_text(name: &str) -> Option<String> {
    let v = match name {
        VITRO_SCENE => vitro(
            name,
            "The static world of a Vitro run (vitro_record::Scene)",
        ),
        VITRO_FRAME => vitro(
            name,
            "One sampled instant of a Vitro run (vitro_record::Frame)",
        ),
        VITRO_METRICS => json!({
            "title": name,
            "description": "Mission metrics so far and events fired, by name",
            "type": "object",
            "additionalProperties": {"type": "number"},
        }),
        SCENE_UPDATE => scene_update(),
        FRAME_TRANSFORMS => frame_transforms(),
        LOCATION_FIX => location_fix(),
        LOG => log(),
        _ => return None,
    };
    Some(v.to_string())
}

fn vitro(name: &str, what: &str) -> Value {
    json!({
        "title": name,
        "description": format!("{what}: its serde JSON, read back exactly by vitro-record's Replay"),
        "type": "object",
    })
}

fn object(title: &str, props: Value) -> Value {
    let required: Vec<Value> = props
        .as_object()
        .map(|m| m.keys().map(|k| Value::from(k.as_str())).collect())
        .unwrap_or_default();
    json!({"title": title, "type": "object", "properties": props, "required": required})
}

fn number() -> Value {
    json!({"type": "number"})
}

fn array(items: Value) -> Value {
    json!({"type": "array", "items": items})
}

fn enumeration(title: &str, values: &[(&str, u8)]) -> Value {
    let one_of: Vec<Value> = values
        .iter()
        .map(|(t, c)| json!({"title": t, "const": c}))
        .collect();
    json!({"title": title, "oneOf": one_of})
}

fn time() -> Value {
    json!({
        "type": "object",
        "title": "time",
        "properties": {
            "sec": {"type": "integer", "minimum": 0},
            "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999},
        },
    })
}

fn duration() -> Value {
    json!({
        "type": "object",
        "title": "duration",
        "properties": {
            "sec": {"type": "integer"},
            "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999},
        },
    })
}

fn vector3(title: &str) -> Value {
    object(title, json!({"x": number(), "y": number(), "z": number()}))
}

fn quaternion() -> Value {
    object(
        "foxglove.Quaternion",
        json!({"x": number(), "y": number(), "z": number(), "w": number()}),
    )
}

fn pose() -> Value {
    object(
        "foxglove.Pose",
        json!({"position": vector3("foxglove.Vector3"), "orientation": quaternion()}),
    )
}

fn color() -> Value {
    object(
        "foxglove.Color",
        json!({"r": number(), "g": number(), "b": number(), "a": number()}),
    )
}

fn key_value() -> Value {
    object(
        "foxglove.KeyValuePair",
        json!({"key": {"type": "string"}, "value": {"type": "string"}}),
    )
}

fn indices() -> Value {
    array(json!({"type": "integer", "minimum": 0}))
}

fn scene_entity() -> Value {
    let point = vector3("foxglove.Point3");
    let shape = |title: &str| {
        object(
            title,
            json!({"pose": pose(), "size": vector3("foxglove.Vector3"), "color": color()}),
        )
    };
    object(
        "foxglove.SceneEntity",
        json!({
            "timestamp": time(),
            "frame_id": {"type": "string"},
            "id": {"type": "string"},
            "lifetime": duration(),
            "frame_locked": {"type": "boolean"},
            "metadata": array(key_value()),
            "arrows": array(object("foxglove.ArrowPrimitive", json!({
                "pose": pose(),
                "shaft_length": number(),
                "shaft_diameter": number(),
                "head_length": number(),
                "head_diameter": number(),
                "color": color(),
            }))),
            "cubes": array(shape("foxglove.CubePrimitive")),
            "spheres": array(shape("foxglove.SpherePrimitive")),
            "cylinders": array(object("foxglove.CylinderPrimitive", json!({
                "pose": pose(),
                "size": vector3("foxglove.Vector3"),
                "bottom_scale": number(),
                "top_scale": number(),
                "color": color(),
            }))),
            "lines": array(object("foxglove.LinePrimitive", json!({
                "type": enumeration(
                    "foxglove.LineType",
                    &[("LINE_STRIP", 0), ("LINE_LOOP", 1), ("LINE_LIST", 2)],
                ),
                "pose": pose(),
                "thickness": number(),
                "scale_invariant": {"type": "boolean"},
                "points": array(point.clone()),
                "color": color(),
                "colors": array(color()),
                "indices": indices(),
            }))),
            "triangles": array(object("foxglove.TriangleListPrimitive", json!({
                "pose": pose(),
                "points": array(point),
                "color": color(),
                "colors": array(color()),
                "indices": indices(),
            }))),
            "texts": array(object("foxglove.TextPrimitive", json!({
                "pose": pose(),
                "billboard": {"type": "boolean"},
                "font_size": number(),
                "scale_invariant": {"type": "boolean"},
                "color": color(),
                "text": {"type": "string"},
            }))),
            "models": array(json!({"title": "foxglove.ModelPrimitive", "type": "object"})),
        }),
    )
}

fn scene_update() -> Value {
    let mut v = object(
        SCENE_UPDATE,
        json!({
            "deletions": array(object("foxglove.SceneEntityDeletion", json!({
                "timestamp": time(),
                "type": enumeration(
                    "foxglove.SceneEntityDeletionType",
                    &[("MATCHING_ID", 0), ("ALL", 1)],
                ),
                "id": {"type": "string"},
            }))),
            "entities": array(scene_entity()),
        }),
    );
    v["description"] = "An update to the entities displayed in a 3D scene".into();
    v
}

fn frame_transforms() -> Value {
    object(
        FRAME_TRANSFORMS,
        json!({
            "transforms": array(object("foxglove.FrameTransform", json!({
                "timestamp": time(),
                "parent_frame_id": {"type": "string"},
                "child_frame_id": {"type": "string"},
                "translation": vector3("foxglove.Vector3"),
                "rotation": quaternion(),
            }))),
        }),
    )
}

fn location_fix() -> Value {
    object(
        LOCATION_FIX,
        json!({
            "timestamp": time(),
            "frame_id": {"type": "string"},
            "latitude": number(),
            "longitude": number(),
            "altitude": number(),
            "position_covariance": {
                "type": "array", "items": number(), "minItems": 9, "maxItems": 9,
            },
            "position_covariance_type": enumeration(
                "foxglove.PositionCovarianceType",
                &[("UNKNOWN", 0), ("APPROXIMATED", 1), ("DIAGONAL_KNOWN", 2), ("KNOWN", 3)],
            ),
            "heading": number(),
            "velocity": vector3("foxglove.Vector3"),
            "color": color(),
        }),
    )
}

fn log() -> Value {
    object(
        LOG,
        json!({
            "timestamp": time(),
            "level": enumeration(
                "foxglove.LogLevel",
                &[("UNKNOWN", 0), ("DEBUG", 1), ("INFO", 2), ("WARNING", 3), ("ERROR", 4),
                  ("FATAL", 5)],
            ),
            "message": {"type": "string"},
            "name": {"type": "string"},
            "file": {"type": "string"},
            "line": {"type": "integer", "minimum": 0},
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_schema_is_json_titled_by_its_name() {
        for name in [
            VITRO_SCENE,
            VITRO_FRAME,
            VITRO_METRICS,
            SCENE_UPDATE,
            FRAME_TRANSFORMS,
            LOCATION_FIX,
            LOG,
        ] {
            let text = schema_text(name).expect("known schema");
            let v: Value = serde_json::from_str(&text).expect("JSON");
            assert_eq!(v["title"], name);
        }
        assert!(schema_text("foxglove.Grid").is_none());
    }

    #[test]
    fn schemas_require_every_field_the_messages_write() {
        // The entity schema lists exactly the fields a SceneEntity serializes.
        let v: Value = serde_json::from_str(&schema_text(SCENE_UPDATE).unwrap()).unwrap();
        let entity = &v["properties"]["entities"]["items"];
        let mut required: Vec<String> = entity["required"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k.as_str().unwrap().to_owned())
            .collect();
        let written = serde_json::to_value(crate::foxglove::SceneEntity::new(0, "x")).unwrap();
        let mut keys: Vec<String> = written.as_object().unwrap().keys().cloned().collect();
        required.sort();
        keys.sort();
        assert_eq!(required, keys);
    }
}
