//! `vitro validate` on mission scenarios: the default scenario passes, and every file of the
//! catalogue in `tests/bad_scenarios/` is rejected with exit code 2 and a message that names
//! the right `line:column` and what was expected.
//!
//! Each bad file's first line is `# expect: LINE:COLUMN: TEXT`: stderr must hold
//! `FILE:LINE:COLUMN: TEXT`; its second line says what is wrong.

mod common;

use common::{repo, vitro};

const BAD: &str = "crates/vitro-cli/tests/bad_scenarios";

/// The catalogue: (path from the repository root, expected `line:column: text`).
fn catalogue() -> Vec<(String, String)> {
    let mut files: Vec<(String, String)> = std::fs::read_dir(repo().join(BAD))
        .expect("the catalogue")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|name| name.ends_with(".toml"))
        .map(|name| {
            let path = format!("{BAD}/{name}");
            let text = std::fs::read_to_string(repo().join(&path)).expect("readable");
            let expect = text
                .lines()
                .next()
                .and_then(|l| l.strip_prefix("# expect: "))
                .unwrap_or_else(|| panic!("{name}: no `# expect:` first line"))
                .to_owned();
            (path, expect)
        })
        .collect();
    files.sort();
    files
}

#[test]
fn every_malformed_scenario_is_rejected_at_its_place() {
    let files = catalogue();
    assert!(files.len() >= 20, "only {} malformed files", files.len());
    // Two threads: each run loads the town when the file gets that far.
    let failures: Vec<String> = std::thread::scope(|s| {
        let halves: Vec<_> = files
            .chunks(files.len().div_ceil(2))
            .map(|chunk| {
                s.spawn(move || {
                    chunk
                        .iter()
                        .filter_map(|(path, expect)| {
                            let (code, out, err) = vitro(&["validate", path]);
                            let want = format!("{path}:{expect}");
                            let ok = code == 2 && out.is_empty() && err.contains(&want);
                            (!ok).then(|| format!("{path}: exit {code}, want {want:?}\n{err}"))
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        halves
            .into_iter()
            .flat_map(|h| h.join().expect("no panic"))
            .collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_problem_is_shown_with_its_line() {
    let path = format!("{BAD}/count_zero.toml");
    let (code, _, err) = vitro(&["validate", &path]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with(&format!("error: invalid scenario {path}: 2 problems\n")),
        "{err}"
    );
    assert!(
        err.contains(&format!("{path}:19:1: the mission has no blue trooper")),
        "{err}"
    );
    assert!(err.contains("28 | count = 0\n   |         ^"), "{err}");
    // Syntax errors the parser recovers from are all reported too.
    let (code, _, err) = vitro(&["validate", &format!("{BAD}/syntax_unclosed_table.toml")]);
    assert_eq!(code, 2);
    assert!(err.contains(": 3 problems"), "{err}");
}

#[test]
fn the_default_scenario_validates() {
    let (code, out, err) = vitro(&["validate", "scenarios/evacuation.toml"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.starts_with(
            "scenarios/evacuation.toml: ok (\"evacuation\": 20 entities in 10 groups, \
             kotka.osm.pbf on valley_64x64_90m.asc"
        ),
        "{out}"
    );
}

#[test]
fn the_demo_scenario_still_validates() {
    let (code, out, err) = vitro(&["validate", "scenarios/demo.toml"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.starts_with("scenarios/demo.toml: ok (76 junctions"),
        "{out}"
    );
    let (code, _, err) = vitro(&["validate", "crates/vitro-cli/tests/bad/loss_above_one.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("expected a probability in [0, 1]"), "{err}");
}

#[test]
fn a_missing_scenario_is_bad_input() {
    let (code, _, err) = vitro(&["validate", "scenarios/no_such_scenario.toml"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("cannot read scenario scenarios/no_such_scenario.toml"),
        "{err}"
    );
}

#[test]
fn a_formation_program_that_does_not_parse_is_rejected_at_its_own_place() {
    // The default scenario with its own leader program, which has a syntax error on line 3.
    let dir = std::env::temp_dir().join(format!("vitro-bad-program-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let data = repo()
        .join("data")
        .canonicalize()
        .expect("the data directory");
    let text = std::fs::read_to_string(repo().join("scenarios/evacuation.toml"))
        .expect("the default scenario")
        .replace(
            "# program = \"../data/rules/formation/wedge.rules\"",
            "program = \"broken.jz\"",
        )
        .replace("\"../data/", &format!("\"{}/", data.display()));
    assert!(text.contains("program = \"broken.jz\""));
    let scenario = dir.join("scenario.toml");
    std::fs::write(&scenario, text).expect("written");
    std::fs::write(
        dir.join("broken.jz"),
        "// A leader program.\n// Line 3 misses a bracket.\nwhen eyes [contact then form squad [line]\n",
    )
    .expect("written");
    let (code, out, err) = vitro(&["validate", &scenario.display().to_string()]);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty(), "{out}");
    let program = dir.join("broken.jz").display().to_string();
    assert!(err.contains(&format!("{program}:3:")), "{err}");
    assert!(
        err.contains("expected a leader program in the rule language"),
        "{err}"
    );
}
