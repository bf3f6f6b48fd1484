//! The `kind` a scenario file names, read with its place in the file.

use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};

/// Why a scenario's kind could not be told. Each names the file, and the line and column
/// where there is one, then what was expected.
/// All are bad input (exit code 2). New variants may be added.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum KindError {
    /// The file is not TOML.
    #[error("{}:{line}:{column}: {message} (expected a TOML scenario file)", .file.display())]
    Syntax {
        /// The file.
        file: PathBuf,
        /// Line, from 1.
        line: usize,
        /// Column, from 1.
        column: usize,
        /// What the TOML reader said.
        message: String,
    },
    /// No top-level `kind` key.
    #[error("{}:1:1: the scenario names no kind (expected a top-level key `kind = \"...\"`, one of: {})", .file.display(), .kinds.join(", "))]
    Missing {
        /// The file.
        file: PathBuf,
        /// The kinds there are.
        kinds: Vec<String>,
    },
    /// `kind` is not a string, or no mission has it.
    #[error("{}:{line}:{column}: {found} is not a kind of scenario (expected one of: {})", .file.display(), .kinds.join(", "))]
    Unknown {
        /// The file.
        file: PathBuf,
        /// Line, from 1.
        line: usize,
        /// Column, from 1.
        column: usize,
        /// What the file says, as written.
        found: String,
        /// The kinds there are.
        kinds: Vec<String>,
    },
}

/// Line and column (from 1, in characters) of byte `offset` in `text`.
fn place(text: &str, offset: usize) -> (usize, usize) {
    let mut at = offset.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    (
        text[..at].matches('\n').count() + 1,
        text[line_start..at].chars().count() + 1,
    )
}

/// The kind the scenario text names (its top-level `kind`), checked against `kinds`.
///
/// # Errors
/// A [`KindError`] naming `file`, line and column.
pub fn kind_of(file: &Path, text: &str, kinds: &[&str]) -> Result<String, KindError> {
    let all = || kinds.iter().map(|k| (*k).to_owned()).collect::<Vec<_>>();
    // The recovering parser: a file with syntax errors but a readable kind goes on to its
    // mission, which reports every problem in it.
    let (root, errors) = DeTable::parse_recoverable(text);
    let Some(value) = root.get_ref().get("kind") else {
        return Err(match errors.first() {
            Some(e) => {
                let (line, column) = place(text, e.span().map_or(0, |s| s.start));
                KindError::Syntax {
                    file: file.to_path_buf(),
                    line,
                    column,
                    message: e.message().trim().replace('\n', "; "),
                }
            }
            None => KindError::Missing {
                file: file.to_path_buf(),
                kinds: all(),
            },
        });
    };
    let span = value.span();
    let found = match value.get_ref() {
        DeValue::String(s) if kinds.contains(&s.as_ref()) => return Ok(s.to_string()),
        DeValue::String(s) => format!("\"{s}\""),
        _ => text.get(span.clone()).unwrap_or("this value").to_owned(),
    };
    let (line, column) = place(text, span.start);
    Err(KindError::Unknown {
        file: file.to_path_buf(),
        line,
        column,
        found,
        kinds: all(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const KINDS: [&str; 2] = ["demo", "evacuation"];

    #[test]
    fn an_unknown_kind_is_located_and_the_kinds_listed() {
        let text = "# a scenario\nname = \"x\"\nkind = \"evacuaton\"\n";
        let e = kind_of(Path::new("s.toml"), text, &KINDS).unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.toml:3:8: \"evacuaton\" is not a kind of scenario (expected one of: demo, evacuation)"
        );
    }

    #[test]
    fn a_kind_that_is_not_a_string_is_refused() {
        let e = kind_of(Path::new("s.toml"), "kind = 3\n", &KINDS).unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.toml:1:8: 3 is not a kind of scenario (expected one of: demo, evacuation)"
        );
    }

    #[test]
    fn broken_toml_without_a_kind_is_a_located_syntax_error() {
        let e = kind_of(Path::new("s.toml"), "name = \"x\"\nseed = \n", &KINDS).unwrap_err();
        assert!(matches!(e, KindError::Syntax { line: 2, .. }), "{e}");
    }

    #[test]
    fn broken_toml_with_a_kind_goes_to_its_mission() {
        let kind = kind_of(Path::new("s.toml"), "kind = \"demo\"\nseed = \n", &KINDS);
        assert_eq!(kind.unwrap(), "demo");
    }

    #[test]
    fn a_kind_inside_a_table_does_not_count() {
        let e = kind_of(Path::new("s.toml"), "[site]\nkind = \"demo\"\n", &KINDS).unwrap_err();
        assert!(matches!(e, KindError::Missing { .. }), "{e}");
    }
}
