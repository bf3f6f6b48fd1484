//! The committed JSON Schema of traffic scenarios is the one the code generates.
//!
//! After changing the scenario types, regenerate it with
//! `cargo test -p vitro-traffic --test schema -- --ignored`.

use std::path::PathBuf;
use vitro_traffic::scenario::{TOP_LEVEL_KEYS, json_schema};

fn generated() -> String {
    let mut text = serde_json::to_string_pretty(&json_schema()).expect("the schema is JSON");
    text.push('\n');
    text
}

fn committed() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/traffic.schema.json")
}

#[test]
fn committed_schema_is_current() {
    let on_disk = std::fs::read_to_string(committed()).expect("scenarios/traffic.schema.json");
    assert!(
        on_disk == generated(),
        "scenarios/traffic.schema.json is stale: regenerate it with \
         `cargo test -p vitro-traffic --test schema -- --ignored`"
    );
}

#[test]
fn schema_describes_the_file() {
    let schema = json_schema().to_value();
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
    assert_eq!(props["traffic"]["default"]["check_s"], 1.0);
}

#[test]
#[ignore = "writes scenarios/traffic.schema.json"]
fn regenerate_schema() {
    std::fs::write(committed(), generated()).expect("write the schema");
}
