//! Reading any mission's scenario text: TOML syntax, then the types, every problem with
//! its file, line and column.
//!
//! Every tactical scenario has the shared top-level keys ([`SHARED`]: `kind`, `name`, `seed`,
//! `start`, `end`, `site`, `fidelity`, `entity`, `channel`, `record`), of which `name`,
//! `seed`, `end`, `site` and at least one `[[entity]]` are required ([`SHARED_REQUIRED`]). A
//! mission lists its own keys, each with the check that reads its value on its own ([`one`]
//! for a table or a value, [`each`] for an array of tables), and its own required keys
//! ([`Layout`]); [`parse`] reads the whole file into the mission's type, and when that fails
//! reports every problem rather than the first: all syntax errors the TOML parser recovers
//! from; else each top-level key (and each item of an array of tables) read on its own,
//! unknown keys and missing ones.
//!
//! ```
//! use std::path::Path;
//! use vitro_tactical::scenario::tables::{Layout, each, one, parse};
//! use vitro_tactical::scenario::{Diagnostics, EndSpec, EntitySpec, SiteSpec};
//!
//! #[derive(Debug, serde::Deserialize)]
//! #[serde(deny_unknown_fields)]
//! struct Watch {
//!     name: String,
//!     seed: u64,
//!     end: EndSpec,
//!     site: SiteSpec,
//!     #[serde(rename = "entity")]
//!     entities: Vec<EntitySpec>,
//!     depot: [f64; 2],
//! }
//! // The mission's own key: the depot, required.
//! const LAYOUT: Layout = Layout {
//!     keys: &[("depot", one::<[f64; 2]>)],
//!     required: &[("depot", "a top-level `depot`, town metres [x, y]")],
//! };
//! let good = r#"
//! name = "w"
//! seed = 1
//! end = { time_s = 60 }
//! site = { map = "town.osm.pbf", terrain = "valley.asc" }
//! depot = [0, 0]
//! [[entity]]
//! name = "u"
//! type = "ugv"
//! side = "blue"
//! "#;
//! let w: Watch = parse(Path::new("w.toml"), good, &LAYOUT).unwrap();
//! assert_eq!(w.entities[0].name, "u");
//!
//! // Two problems in two places, both reported (in the order of their places).
//! let bad = good.replace("name = \"w\"", "name = 3").replace("time_s = 60", "time_s = \"soon\"");
//! let problems = parse::<Watch>(Path::new("w.toml"), &bad, &LAYOUT).unwrap_err();
//! let problems = Diagnostics::new(problems);
//! let lines: Vec<String> = problems.0.iter().map(|d| d.to_string()).collect();
//! assert_eq!(lines.len(), 2, "{lines:?}");
//! assert!(lines[0].starts_with("w.toml:2:8: invalid type: integer `3`"), "{lines:?}");
//! assert!(lines[1].starts_with("w.toml:4:18: invalid type: string \"soon\""), "{lines:?}");
//! ```

use super::span::{Capped, Diagnostic};
use super::{ChannelSpec, EndSpec, EntitySpec, FidelitySpec, RecordSpec, SiteSpec};
use serde::de::DeserializeOwned;
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};
use vitro::time::UtcTime;

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

/// The top-level keys every tactical scenario has, each with the check of its value.
pub const SHARED: [(&str, PartCheck); 10] = [
    ("kind", one::<String>),
    ("name", one::<String>),
    ("seed", one::<u64>),
    ("start", one::<UtcTime>),
    ("end", one::<EndSpec>),
    ("site", one::<SiteSpec>),
    ("fidelity", one::<FidelitySpec>),
    ("entity", each::<EntitySpec>),
    ("channel", one::<ChannelSpec>),
    ("record", one::<RecordSpec>),
];

/// The shared keys every tactical scenario must have, each with what is expected in words.
pub const SHARED_REQUIRED: [(&str, &str); 5] = [
    ("name", "a top-level `name`"),
    ("seed", "a top-level `seed`"),
    ("end", "a top-level `end`"),
    ("site", "a top-level `site`"),
    ("entity", "at least one `[[entity]]` table"),
];

/// The mission's own top-level keys: beside the [`SHARED`] ones.
#[derive(Clone, Copy, Debug)]
pub struct Layout<'a> {
    /// The mission's own top-level keys, each with the check of its value.
    pub keys: &'a [(&'a str, PartCheck)],
    /// The mission's own keys a file must have, each with what is expected in words
    /// (for the surveillance, its `station` table).
    pub required: &'a [(&'a str, &'a str)],
}

impl Layout<'_> {
    /// Every top-level key: the shared ones, then the mission's.
    pub fn key_names(&self) -> Vec<&str> {
        let own = self.keys.iter().map(|(k, _)| *k);
        SHARED.iter().map(|(k, _)| *k).chain(own).collect()
    }

    /// The check of the value of top-level key `key`, if it is one.
    fn check(&self, key: &str) -> Option<PartCheck> {
        let mut all = SHARED.iter().chain(self.keys);
        all.find(|(k, _)| *k == key).map(|(_, c)| *c)
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
        let Some(check) = layout.check(name) else {
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
    for (key, what) in SHARED_REQUIRED.iter().chain(layout.required) {
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

/// "one of `a`, `b`, `c`".
pub fn one_of(keys: &[&str]) -> String {
    let keys: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
    format!("one of {}", keys.join(", "))
}
