//! The committed JSON Schema of demo scenario files is the one the code generates.
//!
//! After changing the scenario types, regenerate it with
//! `cargo test -p vitro-demo --test schema -- --ignored`.

use std::path::PathBuf;
use vitro_demo::config::json_schema;

/// The schema as the committed file holds it: pretty JSON and a final newline.
fn generated() -> String {
    let mut text = serde_json::to_string_pretty(&json_schema()).expect("the schema is JSON");
    text.push('\n');
    text
}

fn committed() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/demo.schema.json")
}

#[test]
fn committed_schema_is_current() {
    let on_disk = std::fs::read_to_string(committed()).expect("scenarios/demo.schema.json");
    assert!(
        on_disk == generated(),
        "scenarios/demo.schema.json is stale: regenerate it with \
         `cargo test -p vitro-demo --test schema -- --ignored`"
    );
}

#[test]
fn schema_bounds_are_the_checks() {
    let schema = json_schema().to_value();
    assert_eq!(schema["$schema"], "http://json-schema.org/draft-07/schema#");
    assert_eq!(schema["additionalProperties"], false);
    let channel = &schema["definitions"]["ChannelConfig"]["properties"];
    assert_eq!(channel["loss"]["minimum"], 0.0);
    assert_eq!(channel["loss"]["maximum"], 1.0);
    assert_eq!(channel["range_m"]["exclusiveMinimum"], 0.0);
    let town = &schema["definitions"]["TownConfig"]["properties"];
    assert_eq!(town["columns"]["type"], "integer");
    assert_eq!(town["columns"]["minimum"], 2);
    assert_eq!(town["columns"]["maximum"], 1000);
}

#[test]
#[ignore = "writes scenarios/demo.schema.json"]
fn regenerate_schema() {
    std::fs::write(committed(), generated()).expect("write the schema");
}
