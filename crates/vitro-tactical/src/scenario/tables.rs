//! Reading any mission's scenario text: TOML syntax, then the types, every problem with
//! its file, line and column.
//!
//! A mission lists its top-level keys, each with the check that reads its value on its own
//! ([`one`] for a table or a value, [`each`] for an array of tables), and the keys a file
//! must have ([`Layout`]); [`parse`] reads the whole file into the mission's type, and when
//! that fails reports every problem rather than the first: all syntax errors the TOML parser
//! recovers from; else each top-level key (and each item of an array of tables) read on its
//! own, unknown keys and missing ones.
//!
//! ```
//! use std::path::Path;
//! use vitro_tactical::scenario::tables::{Layout, each, one, parse};
//! use vitro_tactical::scenario::{Diagnostics, EndSpec, EntitySpec};
//!
//! #[derive(Debug, serde::Deserialize)]
//! #[serde(deny_unknown_fields)]
//! struct Watch {
//!     name: String,
//!     end: EndSpec,
//!     #[serde(rename = "entity")]
//!     entities: Vec<EntitySpec>,
//! }
//! const LAYOUT: Layout = Layout {
//!     keys: &[("name", one::<String>), ("end", one::<EndSpec>), ("entity", each::<EntitySpec>)],
//!     required: &[("name", "a top-level `name`"), ("end", "an `[end]` table")],
//! };
//! let good = "name = \"w\"\nend = { time_s = 60 }\n[[entity]]\nname = \"u\"\ntype = \"ugv\"\nside = \"blue\"\n";
//! let w: Watch = parse(Path::new("w.toml"), good, &LAYOUT).unwrap();
//! assert_eq!(w.entities[0].name, "u");
//!
//! // Two problems in two places, both reported (in the order of their places).
//! let bad = "name = 3\nend = { time_s = \"soon\" }\n";
//! let problems = parse::<Watch>(Path::new("w.toml"), bad, &LAYOUT).unwrap_err();
//! let problems = Diagnostics::new(problems);
//! let lines: Vec<String> = problems.0.iter().map(|d| d.to_string()).collect();
//! assert_eq!(lines.len(), 2, "{lines:?}");
//! assert!(lines[0].starts_with("w.toml:1:8: invalid type: integer `3`"), "{lines:?}");
//! assert!(lines[1].starts_with("w.toml:2:18: invalid type: string \"soon\""), "{lines:?}");
//! ```

use super::span::{Diagnostic, MAX_PROBLEMS};
use serde::de::DeserializeOwned;
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

/// Reads one top-level value of a scenario on its own: each error found in it.
pub type PartCheck = for<'a> fn(Spanned<DeValue<'a>>) -> Vec<toml::de::Error>;

/// A [`PartCheck`] for a value of type `T` (a table, a string, a number).
pub fn one<T: DeserializeOwned>(value: Spanned<DeValue<'_>>) -> Vec<toml::de::Error> {
    T::deserialize(ValueDeserializer::from(value))
        .err()
        .into_iter()
        .collect()
}

/// A [`PartCheck`] for an array of tables of `T` (`[[entity]]`): every bad item reported.
pub fn each<T: DeserializeOwned>(value: Spanned<DeValue<'_>>) -> Vec<toml::de::Error> {
    match value.get_ref() {
        DeValue::Array(items) => items.iter().flat_map(|v| one::<T>(v.clone())).collect(),
        _ => one::<Vec<T>>(value),
    }
}

/// The top level of a mission's scenario files.
#[derive(Clone, Copy, Debug)]
pub struct Layout<'a> {
    /// Every top-level key, in the order of the file type's fields, with the check of its
    /// value.
    pub keys: &'a [(&'a str, PartCheck)],
    /// The keys a file must have, each with what is expected in words
    /// (`"at least one `[[entity]]` table"`).
    pub required: &'a [(&'a str, &'a str)],
}

impl Layout<'_> {
    /// The top-level keys, in order.
    pub fn key_names(&self) -> Vec<&str> {
        self.keys.iter().map(|(k, _)| *k).collect()
    }
}

/// Parses `text` (read from `file`) into a `T`, or every syntax or type error found (see the
/// module's doc).
///
/// # Errors
/// Every problem found, each with its file, line and column.
pub fn parse<T: DeserializeOwned>(
    file: &Path,
    text: &str,
    layout: &Layout<'_>,
) -> Result<T, Vec<Diagnostic>> {
    let (root, errors) = DeTable::parse_recoverable(text);
    let mut out = Capped::new(file);
    if !errors.is_empty() {
        for e in &errors {
            out.push(|| Diagnostic::from_toml(file, text, e));
        }
        return Err(out.finish());
    }
    let whole = match T::deserialize(toml::de::Deserializer::from(root.clone())) {
        Ok(t) => return Ok(t),
        Err(e) => Diagnostic::from_toml(file, text, &e),
    };
    // The first error hides the others: read each part on its own.
    let table = root.get_ref();
    for (key, value) in table.iter() {
        let name = key.get_ref().as_ref();
        let Some((_, check)) = layout.keys.iter().find(|(k, _)| *k == name) else {
            out.push(|| {
                let what = Some(one_of(&layout.key_names()));
                let message = format!("unknown field `{name}`");
                Diagnostic::new(file, text, Some(key.span()), message, what)
            });
            continue;
        };
        let span = value.span();
        for e in check(value.clone()) {
            out.push(|| Diagnostic::from_toml_or_at(file, text, &e, Some(span.clone())));
        }
    }
    for (key, what) in layout.required {
        if !table.contains_key(*key) {
            out.push(|| {
                let message = format!("missing field `{key}`");
                Diagnostic::new(file, text, Some(0..0), message, Some((*what).to_owned()))
            });
        }
    }
    let mut out = out.finish();
    if out.is_empty() {
        out.push(whole);
    }
    Err(out)
}

/// At most [`MAX_PROBLEMS`] diagnostics, each made only if it is kept, and a count of the
/// rest.
struct Capped<'a> {
    file: &'a Path,
    out: Vec<Diagnostic>,
    dropped: usize,
}

impl<'a> Capped<'a> {
    fn new(file: &'a Path) -> Self {
        Capped {
            file,
            out: Vec::new(),
            dropped: 0,
        }
    }

    fn push(&mut self, make: impl FnOnce() -> Diagnostic) {
        if self.out.len() < MAX_PROBLEMS {
            self.out.push(make());
        } else {
            self.dropped += 1;
        }
    }

    fn finish(mut self) -> Vec<Diagnostic> {
        if self.dropped > 0 {
            self.out.push(Diagnostic::more(self.file, self.dropped));
        }
        self.out
    }
}

/// "one of `a`, `b`, `c`".
pub fn one_of(keys: &[&str]) -> String {
    let keys: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
    format!("one of {}", keys.join(", "))
}
