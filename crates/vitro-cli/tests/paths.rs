//! A path that is not a readable file of the expected kind (a directory, a missing file) is
//! bad input for every command that reads one: exit 2, the file named, the cause said once.

mod common;

use common::vitro;

/// Every command that reads a file, with `{}` where the file goes.
const COMMANDS: &[&[&str]] = &[
    &["run", "{}"],
    &["validate", "{}"],
    &["resume", "{}"],
    &["batch", "{}", "--out", "{out}"],
    &["search", "{}", "--out", "{out}"],
    &["plan", "{}", "crates/vitro-cli/tests/pddl/switch-easy.pddl"],
    &[
        "plan",
        "crates/vitro-cli/tests/pddl/switch-domain.pddl",
        "{}",
    ],
    &["solve", "cops", "{}"],
    &["solve", "patrol", "{}"],
    &[
        "solve",
        "pursuit",
        "{}",
        "--pursuers",
        "1",
        "--budget",
        "1",
        "--episodes",
        "1",
        "--turns",
        "1",
    ],
    &["map", "info", "{}"],
    &["map", "render", "{}", "--out", "{out}/map.png"],
    &[
        "terrain",
        "viewshed",
        "{}",
        "--observer",
        "1,1",
        "--observer-height",
        "1",
        "--target-height",
        "1",
        "--out",
        "{out}/v.asc",
    ],
    &["export", "kml", "{}"],
    &["calibrate", "{}", "--out", "{out}/c.toml"],
];

fn check(path: &str, os_message: &str) {
    let out = std::env::temp_dir().join(format!("vitro-paths-{}", std::process::id()));
    let out = out.to_str().expect("utf-8 path");
    for command in COMMANDS {
        let args: Vec<String> = command
            .iter()
            .map(|a| a.replace("{}", path).replace("{out}", out))
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, _, err) = vitro(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(err.contains(path), "{args:?} names the file: {err}");
        assert!(err.contains(os_message), "{args:?} says why: {err}");
        assert_eq!(
            err.matches(os_message).count(),
            1,
            "{args:?} says why once: {err}"
        );
        assert_eq!(
            err.matches(path).count(),
            1,
            "{args:?} names it once: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn a_directory_is_bad_input_said_once() {
    let dir = std::env::temp_dir();
    check(dir.to_str().expect("utf-8 path"), "directory");
}

#[test]
fn a_missing_file_is_bad_input_said_once() {
    check("no/such/file.toml", "No such file or directory");
}

#[test]
fn an_output_path_that_cannot_be_created_is_bad_input_said_once() {
    let dir = std::env::temp_dir();
    let dir = dir.to_str().expect("utf-8 path");
    for args in [
        &[
            "run",
            "scenarios/demo.toml",
            "--until",
            "1",
            "--record",
            dir,
        ][..],
        &[
            "run",
            "scenarios/demo.toml",
            "--until",
            "1",
            "--save-at",
            "0.5",
            "--save",
            dir,
        ],
    ] {
        let (code, _, err) = vitro(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        let last = err.lines().last().unwrap_or_default();
        assert_eq!(last.matches("directory").count(), 1, "{args:?}: {err}");
    }
}
