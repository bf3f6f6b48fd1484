//! Reading a surveillance scenario's text: TOML syntax, then the types, each problem with
//! its file, line and column (the same [`Diagnostic`]s as every scenario of the toolkit).

use super::{
    AllocationSpec, AreaSpec, FailureSpec, LossSpec, RedSpec, SearchSpec, SensorSpec, StationSpec,
    SurveillanceFile, TeamSpec, TrackingSpec,
};
use std::path::Path;
use vitro_tactical::scenario::Diagnostic;
use vitro_tactical::scenario::tables::{self, Layout, each, one};

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

/// The surveillance's own top-level keys (beside the shared ones), each with the check of
/// its value, and those a file must have.
const LAYOUT: Layout<'static> = Layout {
    keys: &[
        ("station", one::<StationSpec>),
        ("search", one::<SearchSpec>),
        ("area", each::<AreaSpec>),
        ("loss", each::<LossSpec>),
        ("failures", one::<FailureSpec>),
        ("team", one::<TeamSpec>),
        ("sensors", one::<SensorSpec>),
        ("tracking", one::<TrackingSpec>),
        ("allocation", one::<AllocationSpec>),
        ("red", one::<RedSpec>),
    ],
    required: &[("station", "a `[station]` table with its `start`")],
};

/// Parses `text` (read from `file`) into a scenario, or every syntax or type error found
/// (`vitro_tactical::scenario::tables::parse`).
pub(crate) fn parse(file: &Path, text: &str) -> Result<SurveillanceFile, Vec<Diagnostic>> {
    tables::parse(file, text, &LAYOUT)
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
    fn the_layout_lists_the_top_level_keys() {
        let mut keys = LAYOUT.key_names();
        keys.sort_unstable();
        let mut want = TOP_LEVEL_KEYS;
        want.sort_unstable();
        assert_eq!(keys, want);
    }

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
