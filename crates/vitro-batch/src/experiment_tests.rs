//! Tests of experiment files: levels, coercion, located errors.

use super::*;
use crate::runner::{RunOutput, RunSettings};

struct Names;
impl Runner for Names {
    fn metric_names(&self, s: &toml::Table) -> Result<Vec<String>, String> {
        if s.get("bad").is_some() {
            return Err("`bad` is not allowed".into());
        }
        Ok(vec!["score".into(), "time".into()])
    }
    fn run(&self, _: &toml::Table, _: u64, _: &RunSettings<'_>) -> Result<RunOutput, String> {
        Ok(RunOutput::default())
    }
}

const SCENARIO: &str = "\
seed = 1
end_s = 100.0
[cars]
count = 3
speed = 2.5
[channel]
loss = 0.1
mode = 'radio'
";

fn load(exp: &str) -> Result<Experiment, ExperimentError> {
    load_with(exp, SCENARIO)
}

fn load_with(exp: &str, scenario: &str) -> Result<Experiment, ExperimentError> {
    let file: ExperimentFile = toml::from_str(exp)
        .map_err(|e| ExperimentError::Invalid(Box::new(Located::from_toml("e.toml", exp, &e))))?;
    Experiment::check(
        file,
        Path::new("e.toml"),
        exp.to_owned(),
        PathBuf::from("s.toml"),
        scenario.to_owned(),
        &Names,
    )
}

fn invalid(exp: &str) -> Located {
    match load(exp) {
        Err(ExperimentError::Invalid(l)) => *l,
        other => panic!("expected an invalid experiment, got {other:?}"),
    }
}

#[test]
fn levels_in_written_order_and_scenario_types() {
    let e = load(
        "scenario = 's.toml'\nseed = 3\nreplicates = 2\n[parameters]\n\
         \"channel.loss\" = { start = 0.0, stop = 0.3, step = 0.1 }\n\
         \"cars.count\" = [2.0, 4]\n\"cars.speed\" = [1, 2]\n",
    )
    .unwrap();
    let d = &e.design;
    assert_eq!(
        d.parameter_names(),
        ["channel.loss", "cars.count", "cars.speed"]
    );
    assert_eq!(
        d.factors[0].levels,
        [0.0, 0.1, 0.2, 0.3].map(Value::Float).to_vec()
    );
    assert_eq!(d.factors[1].levels, [Value::Int(2), Value::Int(4)]);
    assert_eq!(d.factors[2].levels, [Value::Float(1.0), Value::Float(2.0)]);
    assert_eq!(d.runs(), Some(4 * 2 * 2 * 2));
    assert_eq!(e.keep.metrics, ["score", "time"]);
    // Run 3: point 1 (the last parameter varies fastest), replicate 1.
    let t = e.scenario_for(&d.run(3).unwrap().params);
    assert_eq!(t["cars"]["count"].as_integer(), Some(2));
    assert_eq!(t["cars"]["speed"].as_float(), Some(2.0));
    let t = e.scenario_for(&d.run(4).unwrap().params);
    assert_eq!(t["cars"]["count"].as_integer(), Some(4));
    assert_eq!(t["channel"]["loss"].as_float(), Some(0.0));
    assert_eq!(t["channel"]["mode"].as_str(), Some("radio"));
}

#[test]
fn integer_ranges_and_hypercube() {
    let e = load(
        "scenario = 's.toml'\nseed = 3\n[parameters]\n\"cars.count\" = { start = 1, stop = 7, step = 3 }\n\
         [latin_hypercube]\nsamples = 4\nintervals = { \"channel.loss\" = [0.0, 0.5] }\n",
    )
    .unwrap();
    assert_eq!(
        e.design.factors[0].levels,
        [1, 4, 7].map(Value::Int).to_vec()
    );
    assert_eq!(e.design.runs(), Some(12));
    assert_eq!(e.design.hypercube.as_ref().unwrap().points.len(), 4);
}

#[test]
fn unknown_key_is_an_error_at_its_place() {
    let l = invalid("scenario = 's.toml'\nseed = 3\n[parameters]\n\"channel.los\" = [0.1]\n");
    assert_eq!(l.position, Some((4, 17)));
    assert!(
        l.message.contains("unknown scenario key `channel.los`"),
        "{}",
        l.message
    );
    assert!(l.message.contains("channel.loss"), "{}", l.message);
    let l = invalid("scenario = 's.toml'\nseed = 3\n[parameters]\n\"cars\" = [1]\n");
    assert!(l.message.contains("is a table"), "{}", l.message);
}

#[test]
fn wrong_levels_are_errors() {
    for (exp, needle) in [
        (
            "\"cars.count\" = [2.5]",
            "is a float, but the scenario's value is an integer",
        ),
        (
            "\"channel.mode\" = [1]",
            "is an integer, but the scenario's value is a string",
        ),
        ("\"cars.count\" = []", "at least one level"),
        ("\"cars.count\" = [1, 1]", "appears twice"),
        (
            "\"cars.count\" = { start = 3, stop = 1, step = 1 }",
            "invalid range",
        ),
        (
            "\"channel.loss\" = { start = 0.0, stop = 1.0, step = 0.0 }",
            "invalid range",
        ),
        (
            "\"channel.loss\" = { start = 0.0, stop = 1.0 }",
            "missing field `step`",
        ),
        (
            "\"channel.loss\" = { start = 0.0, stop = 1.0, step = 0.1, by = 2 }",
            "unknown field `by`",
        ),
        ("\"channel.loss\" = 0.5", "a list of levels or a range"),
    ] {
        let l = invalid(&format!(
            "scenario = 's.toml'\nseed = 3\n[parameters]\n{exp}\n"
        ));
        assert!(l.message.contains(needle), "{exp}: {}", l.message);
        assert_eq!(l.position.map(|p| p.0), Some(4), "{exp}: {l}");
    }
}

#[test]
fn other_checks() {
    let base = "scenario = 's.toml'\nseed = 3\n";
    for (extra, needle, line) in [
        ("replicates = 0\n", "at least 1 replicate", 3),
        ("end_s = -5.0\n", "invalid end time", 3),
        ("seeds = 4\n", "unknown field `seeds`", 3),
        (
            "[keep]\nmetrics = ['score', 'nope']\n",
            "unknown metric `nope`",
            4,
        ),
        ("[keep]\nseries = ['time']\n", "sampling period", 4),
        (
            "[keep]\nseries = ['time']\nevery_s = 0.0\n",
            "invalid period",
            5,
        ),
        (
            "[parameters]\n\"cars.count\" = [1]\n[latin_hypercube]\nsamples = 2\nintervals = { \"cars.count\" = [1, 2] }\n",
            "already varied",
            7,
        ),
        (
            "[latin_hypercube]\nsamples = 2\nintervals = { \"channel.mode\" = [1, 2] }\n",
            "only numbers can be sampled",
            5,
        ),
        (
            "[latin_hypercube]\nsamples = 2\nintervals = { \"channel.loss\" = [1.0, 0.0] }\n",
            "invalid interval",
            5,
        ),
    ] {
        let l = invalid(&format!("{base}{extra}"));
        assert!(l.message.contains(needle), "{extra}: {}", l.message);
        assert_eq!(l.position.map(|p| p.0), Some(line), "{extra}: {l}");
    }
    match load_with(
        &format!("{base}[parameters]\n\"cars.count\" = [1]\n"),
        &format!("bad = 1\n{SCENARIO}"),
    ) {
        Err(ExperimentError::Scenario { message, .. }) => assert!(message.contains("`bad`")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn schema_is_current_and_describes_the_file() {
    let schema = experiment_schema();
    let v: serde_json::Value = serde_json::from_str(&schema).unwrap();
    let props = &v["properties"];
    for key in [
        "scenario",
        "seed",
        "replicates",
        "parameters",
        "latin_hypercube",
        "keep",
        "end_s",
    ] {
        assert!(props.get(key).is_some(), "missing {key}");
    }
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../experiments/experiment.schema.json"
    );
    let on_disk = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        on_disk == schema,
        "experiments/experiment.schema.json is stale: regenerate it with `vitro batch --print-schema > experiments/experiment.schema.json`"
    );
}

#[test]
fn parameter_paths_index_arrays_of_tables() {
    let mut s: toml::Table = toml::from_str(
        "[[entity]]\nname = \"a\"\ncount = 1\n[[entity]]\nname = \"b\"\ncount = 2\n",
    )
    .expect("toml");
    assert_eq!(scenario_kind(&s, "entity.1.count"), Ok(Value::Int(2)));
    assert!(scenario_kind(&s, "entity.count").is_err());
    assert!(scenario_kind(&s, "entity.2.count").is_err());
    set_path(&mut s, "entity.1.count", toml::Value::Integer(5));
    assert_eq!(scenario_kind(&s, "entity.1.count"), Ok(Value::Int(5)));
    assert_eq!(scenario_kind(&s, "entity.0.count"), Ok(Value::Int(1)));
}
