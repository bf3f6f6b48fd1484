//! A scenario that validates always builds: `vitro validate` saying yes is a promise that
//! `vitro run` can set the run up. Each shipped scenario is mutated (a number set to an edge
//! value, a key removed) and given to its mission: where the check accepts the file, the build
//! must succeed too, and neither may panic.

use proptest::prelude::*;
use proptest::test_runner::{RngAlgorithm, TestRng, TestRunner};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use toml::Value;
use vitro_mission::BuildOptions;

/// One step of a path into a TOML document.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

/// Every path to a number, a boolean or a table entry (the mutation sites), in document order.
fn sites(value: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match value {
        Value::Table(t) => {
            for (k, v) in t {
                path.push(Step::Key(k.clone()));
                out.push(path.clone());
                sites(v, path, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                path.push(Step::Index(i));
                sites(v, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

/// What a mutation does at its site.
#[derive(Clone, Debug)]
enum Change {
    /// Replace a number or boolean with this value (of the same TOML type where it can be).
    Set(f64),
    /// Remove the key (the site is a table entry).
    Remove,
}

fn change() -> impl Strategy<Value = Change> {
    prop_oneof![
        4 => prop::sample::select(vec![
            0.0, -1.0, 1.0, 0.5, 2.0, 1e-9, 0.999, 7.0, 60.0, 3600.0, 1e6, -1e6, 1e12,
        ])
        .prop_map(Change::Set),
        1 => Just(Change::Remove),
    ]
}

/// `doc` with `change` applied at `site`; `None` if the change does not apply there.
fn mutated(doc: &Value, site: &[Step], change: &Change) -> Option<Value> {
    let mut doc = doc.clone();
    let (last, parents) = site.split_last()?;
    let mut at = &mut doc;
    for step in parents {
        at = match step {
            Step::Key(k) => at.get_mut(k.as_str())?,
            Step::Index(i) => at.get_mut(*i)?,
        };
    }
    let Step::Key(key) = last else { return None };
    let table = at.as_table_mut()?;
    match change {
        Change::Remove => {
            table.remove(key)?;
        }
        Change::Set(x) => {
            let v = table.get_mut(key)?;
            *v = match v {
                Value::Integer(_) => Value::Integer(*x as i64),
                Value::Float(_) => Value::Float(*x),
                Value::Boolean(b) => Value::Boolean(!*b),
                _ => return None,
            };
        }
    }
    Some(doc)
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Checks one mutation of `file`: `Ok(true)` if it validated and built, `Ok(false)` if the
/// check refused it; `Err` says what broke the promise.
fn check(file: &Path, text: &str) -> Result<bool, String> {
    let registry = vitro_tools::registry();
    let mission = match registry.mission_of(file, text) {
        Ok(m) => m,
        Err(_) => return Ok(false), // the kind itself was removed or changed: refused
    };
    let validated = catch_unwind(AssertUnwindSafe(|| mission.validate(file, text)))
        .map_err(|_| "validate panicked".to_string())?;
    if validated.is_err() {
        return Ok(false);
    }
    let built = catch_unwind(AssertUnwindSafe(|| {
        mission
            .build(file, text, &BuildOptions::default())
            .map(|_| ())
    }))
    .map_err(|_| "validated, then build panicked".to_string())?;
    built
        .map(|()| true)
        .map_err(|e| format!("validated, then build failed: {e}"))
}

fn scenario_cases(name: &str, cases: u32) {
    let file = repo().join("scenarios").join(name);
    let text = std::fs::read_to_string(&file).expect("the shipped scenario reads");
    let doc: Value = toml::from_str(&text).expect("the shipped scenario is TOML");
    let mut all = Vec::new();
    sites(&doc, &mut Vec::new(), &mut all);
    assert!(all.len() > 10, "{name}: {} mutation sites", all.len());
    let config = ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    // A fixed seed: the same mutations on every run and machine.
    let rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
    let mut runner = TestRunner::new_with_rng(config, rng);
    let built = std::cell::Cell::new(0u32);
    let result = runner.run(&(0..all.len(), change()), |(i, change)| {
        let Some(doc) = mutated(&doc, &all[i], &change) else {
            return Ok(());
        };
        let text = toml::to_string(&doc).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let ok = check(&file, &text).map_err(|why| {
            TestCaseError::fail(format!("{name}: {:?} at {:?}: {why}", change, all[i]))
        })?;
        built.set(built.get() + u32::from(ok));
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    // Most edge values are still valid somewhere: the promise was put to the test.
    assert!(
        built.get() >= cases / 4,
        "{name}: only {} of {cases} mutations validated and built",
        built.get()
    );
}

#[test]
fn a_mutated_demo_that_validates_builds() {
    scenario_cases("demo.toml", 48);
}

#[test]
fn a_mutated_evacuation_that_validates_builds() {
    scenario_cases("evacuation.toml", 16);
}

#[test]
fn a_mutated_surveillance_that_validates_builds() {
    scenario_cases("surveillance.toml", 16);
}

#[test]
fn a_mutated_traffic_that_validates_builds() {
    scenario_cases("traffic.toml", 64);
}
