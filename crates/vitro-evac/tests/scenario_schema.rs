//! The committed JSON Schema of scenario files is the one the code generates.
//!
//! After changing the scenario types, regenerate it with
//! `cargo test -p vitro-tactical --test scenario_schema -- --ignored`.

use std::path::PathBuf;
use vitro_evac::scenario::{TOP_LEVEL_KEYS, json_schema};

/// The schema as the committed file holds it: pretty JSON and a final newline.
fn generated() -> String {
    let mut text = serde_json::to_string_pretty(&json_schema()).expect("the schema is JSON");
    text.push('\n');
    text
}

fn committed() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/scenario.schema.json")
}

#[test]
fn committed_schema_is_current() {
    let on_disk = std::fs::read_to_string(committed()).expect("scenarios/scenario.schema.json");
    assert!(
        on_disk == generated(),
        "scenarios/scenario.schema.json is stale: regenerate it with \
         `cargo test -p vitro-tactical --test scenario_schema -- --ignored`"
    );
}

#[test]
fn schema_describes_the_file() {
    let schema = json_schema().to_value();
    assert_eq!(schema["$schema"], "http://json-schema.org/draft-07/schema#");
    assert_eq!(
        schema["additionalProperties"], false,
        "unknown keys are errors"
    );
    let props = schema["properties"].as_object().expect("properties");
    let mut keys: Vec<&str> = props.keys().map(String::as_str).collect();
    let mut expected = TOP_LEVEL_KEYS.to_vec();
    keys.sort_unstable();
    expected.sort_unstable();
    assert_eq!(keys, expected);
    let mut required: Vec<&str> = schema["required"]
        .as_array()
        .expect("required")
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    required.sort_unstable();
    assert_eq!(
        required,
        ["end", "entity", "kind", "name", "places", "seed", "site"]
    );
    // The checker's bounds are the schema's.
    let def = &schema["definitions"];
    assert_eq!(def["ChannelSpec"]["properties"]["loss"]["minimum"], 0.0);
    assert_eq!(def["ChannelSpec"]["properties"]["loss"]["maximum"], 1.0);
    assert_eq!(
        def["EndSpec"]["properties"]["time_s"]["exclusiveMinimum"],
        0.0
    );
    assert_eq!(def["EntitySpec"]["properties"]["count"]["minimum"], 1);
    assert_eq!(props["kind"]["const"], "evacuation");
    assert_eq!(props["start"]["format"], "date-time");
    // Defaults reach the schema, so editors show them; absent options are left out.
    assert_eq!(props["repair"]["default"]["strategy"], "repeated_lazy");
    assert_eq!(props["mission"]["default"]["hit_probability"], 0.3);
    assert_eq!(
        props["fidelity"]["default"],
        serde_json::json!({"level": "discrete"})
    );
    // Levels are spelled as in the files.
    let levels: Vec<&str> = schema["definitions"]["Level"]["oneOf"]
        .as_array()
        .expect("Level variants")
        .iter()
        .filter_map(|v| v["const"].as_str())
        .collect();
    assert_eq!(
        levels,
        [
            "discrete",
            "interpolated",
            "physical",
            "directed",
            "kinematic",
            "dynamic"
        ]
    );
}

#[test]
#[ignore = "writes scenarios/scenario.schema.json"]
fn regenerate_schema() {
    std::fs::write(committed(), generated()).expect("write the schema");
}
