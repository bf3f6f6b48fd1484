//! Reading a surveillance scenario's text: TOML syntax, then the types, each problem with
//! its file, line and column (the same [`Diagnostic`]s as every scenario of the toolkit).

use super::{
    AllocationSpec, AreaSpec, FailureSpec, LossSpec, RedSpec, SearchSpec, SensorSpec, StationSpec,
    SurveillanceFile, TeamSpec, TrackingSpec,
};
use serde::Deserialize as _;
use serde::de::DeserializeOwned;
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};
use vitro::time::UtcTime;
use vitro_tactical::scenario::{
    ChannelSpec, Diagnostic, EndSpec, EntitySpec, FidelitySpec, RecordSpec, SiteSpec,
};

/// The keys of a surveillance scenario's top level, in the order of
/// [`SurveillanceFile`]'s fields.
pub const TOP_LEVEL_KEYS: [&str; 20] = [
    "kind",
    "name",
    "seed",
    "start",
    "end",
    "site",
    "fidelity",
    "station",
    "entity",
    "search",
    "area",
    "loss",
    "failures",
    "team",
    "sensors",
    "tracking",
    "allocation",
    "red",
    "channel",
    "record",
];

/// The keys a file must have.
const REQUIRED: [&str; 6] = ["name", "seed", "end", "site", "station", "entity"];

/// Parses `text` (read from `file`) into a scenario, or every syntax or type error found:
/// all syntax errors the parser recovers from; else, if the whole document does not fit
/// the types, each top-level key and each array item on its own.
pub(crate) fn parse(file: &Path, text: &str) -> Result<SurveillanceFile, Vec<Diagnostic>> {
    let (root, errors) = DeTable::parse_recoverable(text);
    if !errors.is_empty() {
        return Err(errors
            .iter()
            .map(|e| Diagnostic::from_toml(file, text, e))
            .collect());
    }
    let whole = match SurveillanceFile::deserialize(toml::de::Deserializer::from(root.clone())) {
        Ok(scenario) => return Ok(scenario),
        Err(e) => Diagnostic::from_toml(file, text, &e),
    };
    let mut out = Vec::new();
    let table = root.get_ref();
    for (key, value) in table.iter() {
        let v = value.clone();
        let result = match key.get_ref().as_ref() {
            "kind" | "name" => part::<String>(v),
            "seed" => part::<u64>(v),
            "start" => {
                let span = v.span();
                if let Err(e) = part::<UtcTime>(v) {
                    out.push(Diagnostic::from_toml_or_at(file, text, &e, Some(span)));
                }
                Ok(())
            }
            "end" => part::<EndSpec>(v),
            "site" => part::<SiteSpec>(v),
            "fidelity" => part::<FidelitySpec>(v),
            "station" => part::<StationSpec>(v),
            "entity" => items::<EntitySpec>(v, file, text, &mut out),
            "search" => part::<SearchSpec>(v),
            "area" => items::<AreaSpec>(v, file, text, &mut out),
            "loss" => items::<LossSpec>(v, file, text, &mut out),
            "failures" => part::<FailureSpec>(v),
            "team" => part::<TeamSpec>(v),
            "sensors" => part::<SensorSpec>(v),
            "tracking" => part::<TrackingSpec>(v),
            "allocation" => part::<AllocationSpec>(v),
            "red" => part::<RedSpec>(v),
            "channel" => part::<ChannelSpec>(v),
            "record" => part::<RecordSpec>(v),
            other => {
                out.push(Diagnostic::new(
                    file,
                    text,
                    Some(key.span()),
                    format!("unknown field `{other}`"),
                    Some(one_of(&TOP_LEVEL_KEYS)),
                ));
                Ok(())
            }
        };
        if let Err(e) = result {
            out.push(Diagnostic::from_toml(file, text, &e));
        }
    }
    for key in REQUIRED {
        if !table.contains_key(key) {
            let what = match key {
                "entity" => "at least one `[[entity]]` table".to_owned(),
                "station" => "a `[station]` table with its `start`".to_owned(),
                _ => format!("a top-level `{key}`"),
            };
            out.push(Diagnostic::new(
                file,
                text,
                Some(0..0),
                format!("missing field `{key}`"),
                Some(what),
            ));
        }
    }
    if out.is_empty() {
        out.push(whole);
    }
    Err(out)
}

/// Deserializes one part of the document on its own.
fn part<T: DeserializeOwned>(value: Spanned<DeValue<'_>>) -> Result<(), toml::de::Error> {
    T::deserialize(ValueDeserializer::from(value)).map(|_| ())
}

/// Deserializes each item of an array of tables on its own (every bad item reported).
fn items<T: DeserializeOwned>(
    value: Spanned<DeValue<'_>>,
    file: &Path,
    text: &str,
    out: &mut Vec<Diagnostic>,
) -> Result<(), toml::de::Error> {
    match value.get_ref() {
        DeValue::Array(items) => {
            for item in items {
                if let Err(e) = part::<T>(item.clone()) {
                    out.push(Diagnostic::from_toml(file, text, &e));
                }
            }
            Ok(())
        }
        _ => part::<Vec<T>>(value),
    }
}

/// "one of `a`, `b`, `c`".
fn one_of(keys: &[&str]) -> String {
    let keys: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
    format!("one of {}", keys.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use vitro_tactical::scenario::Diagnostics;

    const GOOD: &str = r#"kind = "surveillance"
name = "x"
seed = 1
end = { time_s = 60 }
site = { map = "m.osm.pbf", terrain = "t.asc" }
station = { start = [0, 0] }

[[entity]]
name = "uav"
type = "vidar"
side = "blue"
altitude_m = 100
"#;

    #[test]
    fn a_good_file_parses() {
        let f = parse(Path::new("s.toml"), GOOD).unwrap();
        assert_eq!(f.entities.len(), 1);
    }

    #[test]
    fn every_bad_part_is_reported_with_its_place() {
        let text = format!("{GOOD}\n[team]\nheartbeat_s = \"often\"\n\n[[loss]]\nat_s = 3\n");
        let e = Diagnostics::new(parse(Path::new("s.toml"), &text).unwrap_err());
        let lines: Vec<String> = e.0.iter().map(ToString::to_string).collect();
        assert_eq!(
            lines,
            [
                "s.toml:15:15: invalid type: string \"often\" (expected a number)",
                "s.toml:17:1: missing field `uav` (expected a key `uav` in this table)",
            ]
        );
    }

    #[test]
    fn an_unknown_key_lists_the_keys() {
        let text = format!("sectors = 3\n{GOOD}");
        let e = parse(Path::new("s.toml"), &text).unwrap_err();
        let line = e[0].to_string();
        assert!(
            line.starts_with("s.toml:1:1: unknown field `sectors`"),
            "{line}"
        );
        assert!(line.contains("`allocation`"), "{line}");
    }
}
