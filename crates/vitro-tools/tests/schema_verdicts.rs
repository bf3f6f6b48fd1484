//! The committed JSON Schemas are as strict as the checkers: every scenario fixture (the
//! good scenarios, `vitro-cli`'s `tests/bad` and `tests/bad_scenarios`) gets the same
//! verdict from its kind's schema (the TOML read as JSON) as from `vitro validate`'s check
//! (the registry's), except the fixtures of [`CHECKER_ONLY`], which break a rule a JSON
//! Schema cannot state. The experiments in `experiments/` pass both their schema and the
//! experiment loader.

use std::path::{Path, PathBuf};

/// Fixtures that only the checker rejects, and why a JSON Schema cannot.
const CHECKER_ONLY: &[(&str, &str)] = &[
    (
        "crates/vitro-cli/tests/bad/too_many_cars.toml",
        "cars.count is bounded by the town's junctions (columns x rows - missing blocks)",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/calibration_for_another_map.toml",
        "the calibration file's content must match the map",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/duplicate_entity_names.toml",
        "names unique across entities and their generated `name-i`",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/entity_starts_inside_building.toml",
        "a point against the town's buildings",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/hvt_on_blue_side.toml",
        "the mission's composition: the HVT is red",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/missing_calibration_file.toml",
        "a file reference",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/missing_formation_program.toml",
        "a file reference",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/missing_map_file.toml",
        "a file reference",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/missing_terrain_file.toml",
        "a file reference",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/no_blue_trooper.toml",
        "the mission's composition: at least one blue trooper",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/no_truck.toml",
        "the mission's composition: exactly one blue truck",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/place_inside_building.toml",
        "a point against the town's buildings",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/place_outside_town.toml",
        "a point against the town's extent",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/too_many_hvt_pursuers.toml",
        "hvt_pursuers bounded by the number of blue troopers",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/town_off_terrain.toml",
        "the town's offset against the terrain grid",
    ),
    (
        "crates/vitro-cli/tests/bad_scenarios/two_vips.toml",
        "the mission's composition: exactly one VIP, counted over entities",
    ),
];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `.toml` files of `dir` (from the repository root), sorted.
fn tomls(dir: &str) -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir(repo().join(dir))
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|n| n.ends_with(".toml"))
        .map(|n| format!("{dir}/{n}"))
        .collect();
    out.sort();
    out
}

fn json_of(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"))
}

/// The validator of the committed schema file `name` in `dir`.
fn validator(dir: &str, name: &str) -> jsonschema::Validator {
    let schema = json_of(&repo().join(dir).join(name));
    jsonschema::validator_for(&schema).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The schema's verdict on a scenario text: `Err` with the reasons if it rejects it (a file
/// that is not TOML is rejected before any schema).
fn schema_verdict(
    schemas: &[(&str, jsonschema::Validator)],
    text: &str,
) -> Result<(), Vec<String>> {
    let table: toml::Table = text.parse().map_err(|e| vec![format!("not TOML: {e}")])?;
    let kind = table
        .get("kind")
        .and_then(toml::Value::as_str)
        .unwrap_or("");
    let Some((_, v)) = schemas.iter().find(|(k, _)| *k == kind) else {
        return Err(vec![format!("no schema for kind {kind:?}")]);
    };
    let value = serde_json::to_value(&table).expect("TOML is JSON");
    let errors: Vec<String> = v
        .iter_errors(&value)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors)
    }
}

#[test]
fn every_fixture_gets_the_same_verdict_from_its_schema_and_the_checker() {
    let schemas = [
        ("evacuation", validator("scenarios", "scenario.schema.json")),
        (
            "surveillance",
            validator("scenarios", "surveillance.schema.json"),
        ),
        ("demo", validator("scenarios", "demo.schema.json")),
        ("traffic", validator("scenarios", "traffic.schema.json")),
    ];
    let mut files = tomls("scenarios");
    files.extend(tomls("crates/vitro-cli/tests/bad"));
    files.extend(tomls("crates/vitro-cli/tests/bad_scenarios"));
    files.push("crates/vitro-cli/tests/small.toml".into());
    assert!(files.len() > 50, "only {} fixtures", files.len());
    // The registry resolves the files' relative paths from the current directory.
    std::env::set_current_dir(repo()).expect("the repository root");
    let mut problems = Vec::new();
    let mut checker_only = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).expect("readable");
        let schema = schema_verdict(&schemas, &text);
        let checker = vitro_tools::registry().validate(Path::new(path));
        let listed = CHECKER_ONLY.iter().find(|(p, _)| p == path);
        match (&schema, &checker, listed) {
            (Ok(()), Err(_), Some(_)) => checker_only.push(path.clone()),
            (_, _, Some((_, why))) => problems.push(format!(
                "{path}: listed as checker-only ({why}) but the schema says {:?} and the \
                 checker {}",
                schema.as_ref().err(),
                if checker.is_ok() {
                    "accepts it"
                } else {
                    "rejects it"
                },
            )),
            (Ok(()), Ok(_), None) | (Err(_), Err(_), None) => {}
            (Ok(()), Err(e), None) => problems.push(format!(
                "{path}: the schema accepts what the checker rejects: {}",
                vitro_tools::chain(e)
            )),
            (Err(why), Ok(_), None) => problems.push(format!(
                "{path}: the schema rejects what the checker accepts: {why:?}"
            )),
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert_eq!(checker_only.len(), CHECKER_ONLY.len());
}

#[test]
fn the_experiments_pass_their_schema_and_the_loader() {
    let schema = validator("experiments", "experiment.schema.json");
    std::env::set_current_dir(repo()).expect("the repository root");
    let files = tomls("experiments");
    assert!(files.len() >= 10, "only {} experiments", files.len());
    let mut problems = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).expect("readable");
        let table: toml::Table = text.parse().expect("TOML");
        let value = serde_json::to_value(&table).expect("JSON");
        for e in schema.iter_errors(&value) {
            problems.push(format!("{path}: schema: {}: {e}", e.instance_path()));
        }
        let path = Path::new(path);
        let runner = vitro_tools::runner_for(path);
        if let Err(e) = vitro_tools::load_experiment(path, runner.as_ref()) {
            problems.push(format!("{}: loader: {e}", path.display()));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn an_out_of_range_experiment_is_rejected_by_its_schema() {
    let schema = validator("experiments", "experiment.schema.json");
    let bad = |text: &str| {
        let table: toml::Table = text.parse().expect("TOML");
        !schema.is_valid(&serde_json::to_value(&table).expect("JSON"))
    };
    let base = "scenario = \"s.toml\"\nseed = 1\n";
    assert!(!bad(base));
    assert!(bad(&format!("{base}replicates = 0\n")));
    assert!(bad(&format!("{base}end_s = 0.0\n")));
    assert!(bad(&format!(
        "{base}[stop]\nmetric = \"m\"\nhalf_width = 0.0\n"
    )));
    assert!(bad(&format!(
        "{base}[search]\nelite = 1.0\nparameters = {{ seed = [0, 9] }}\nobjective = {{ maximise = \"m\" }}\n"
    )));
    assert!(bad(&format!(
        "{base}[search]\nparameters = {{ seed = [0, 9] }}\nobjective = {{}}\n"
    )));
}
