//! The scenario file: a typed configuration read from TOML.
//!
//! Unknown keys, wrong types, bad syntax and out-of-range values are all reported as a
//! [`ConfigError`] naming the file, the line and column, and what was expected; never a panic.
//!
//! ```
//! use vitro_demo::config::DemoConfig;
//! let src = r#"
//! seed = 7
//! end_s = 600.0
//! [town]
//! columns = 5
//! rows = 4
//! block_m = 80.0
//! diagonal_share = 0.2
//! missing_blocks = 1
//! [cars]
//! count = 3
//! speed_mps = 8.0
//! [channel]
//! delay_ms = 10.0
//! jitter_ms = 5.0
//! loss = 0.1
//! range_m = 300.0
//! "#;
//! let cfg = DemoConfig::parse("inline.toml", src).unwrap();
//! assert_eq!(cfg.cars.count, 3);
//!
//! let bad = src.replace("end_s = 600.0", "end_s = -1.0");
//! let err = DemoConfig::parse("bad.toml", &bad).unwrap_err();
//! assert!(err.to_string().starts_with("bad.toml:3:9: invalid value -1 for `end_s`"), "{err}");
//! ```

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::fmt;
use vitro::time::UtcTime;

/// Makes `kind` a required key of the schema: the tools pick the mission by it.
fn require_kind(schema: &mut schemars::Schema) {
    if let Some(required) = schema.get_mut("required").and_then(|r| r.as_array_mut()) {
        required.insert(0, "kind".into());
    }
}

/// The form of `start` in the JSON Schema (the parser also checks the calendar).
const START_PATTERN: &str = r"^[0-9]{4}-[0-9]{2}-[0-9]{2}[Tt][0-9]{2}:[0-9]{2}:[0-9]{2}(\.[0-9]{1,9})?([Zz]|[+-][0-9]{2}:[0-9]{2})$";
use std::path::Path;
use toml::de::DeTable;

/// A whole demo scenario.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = require_kind)]
pub struct DemoConfig {
    /// The kind of scenario, `"demo"`: the tools pick the mission by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("const" = "demo"))]
    pub kind: Option<String>,
    /// A short name shown in reports.
    #[serde(default = "default_name")]
    pub name: String,
    /// Master seed of every random stream.
    pub seed: u64,
    /// When simulated time 0 is on the calendar, RFC 3339 (`"2024-06-01T06:00:00Z"`;
    /// default 2024-06-01T06:00:00Z): the recording, KML tracks and the viewer's clock
    /// show it, the simulation never reads it (no trace changes with it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<String>", extend("pattern" = START_PATTERN, "format" = "date-time"))]
    pub start: Option<UtcTime>,
    /// Simulated time at which the run ends, in seconds.
    #[schemars(range(max = 1e9), extend("exclusiveMinimum" = 0.0))]
    pub end_s: f64,
    /// The street graph.
    pub town: TownConfig,
    /// The patrolling cars.
    pub cars: CarsConfig,
    /// The radio channel between cars.
    pub channel: ChannelConfig,
}

/// The generated town: a grid of junctions with some diagonal streets and a few missing blocks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TownConfig {
    /// Junctions from west to east (at least 2).
    #[schemars(range(min = 2, max = 1000))]
    pub columns: u32,
    /// Junctions from south to north (at least 2).
    #[schemars(range(min = 2, max = 1000))]
    pub rows: u32,
    /// Length of a street between neighbouring junctions, in metres.
    #[schemars(range(max = 1e6), extend("exclusiveMinimum" = 0.0))]
    pub block_m: f64,
    /// Share of blocks crossed by a diagonal street, in `[0, 1]`.
    #[schemars(range(min = 0.0, max = 1.0))]
    pub diagonal_share: f64,
    /// Inner junctions removed with their streets (a park or a square merging four blocks).
    /// At most [`TownConfig::max_missing_blocks`]; the town always stays connected.
    pub missing_blocks: u32,
}

/// The patrolling cars.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CarsConfig {
    /// Number of cars (at least 1, at most the number of junctions).
    #[schemars(range(min = 1))]
    pub count: u32,
    /// Cruising speed, in metres per second.
    #[schemars(range(max = 1e4), extend("exclusiveMinimum" = 0.0))]
    pub speed_mps: f64,
    /// Period of the motion updates, in seconds (positions move continuously between nodes).
    #[serde(default = "default_tick_s")]
    #[schemars(range(min = 1e-3, max = 3600.0))]
    pub tick_s: f64,
    /// Simulated deliberation cost per junction considered, in microseconds.
    #[serde(default)]
    #[schemars(range(max = 1_000_000))]
    pub think_us_per_node: u64,
    /// Seconds of idleness one second of travel is worth when picking the next junction
    /// (0: always the least recently visited, wherever it is).
    #[serde(default)]
    #[schemars(range(min = 0.0, max = 1e3))]
    pub distance_weight: f64,
}

/// The radio channel: every claim is broadcast through it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ChannelConfig {
    /// Fixed delivery delay, in milliseconds.
    #[schemars(range(min = 0.0, max = 3.6e6))]
    pub delay_ms: f64,
    /// Extra delay drawn uniformly in `[0, jitter_ms]`, in milliseconds.
    #[schemars(range(min = 0.0, max = 3.6e6))]
    pub jitter_ms: f64,
    /// Probability that a copy of a message is lost, in `[0, 1]`.
    #[schemars(range(min = 0.0, max = 1.0))]
    pub loss: f64,
    /// Range of the radio, in metres; leave it out for unlimited range.
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub range_m: Option<f64>,
}

fn default_name() -> String {
    "demo".to_owned()
}
fn default_tick_s() -> f64 {
    0.5
}

/// Longest run accepted, in simulated seconds (about 31 years: far below `SimTime`'s limit).
pub const MAX_END_S: f64 = 1e9;
/// Largest grid side accepted.
pub const MAX_GRID_SIDE: u32 = 1000;

/// A value that parsed but is out of range: where it is (a dotted key path) and what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct Invalid {
    /// Dotted key path, e.g. `cars.count`.
    pub key: &'static str,
    /// What was expected, e.g. `a probability in [0, 1]`.
    pub expected: String,
    /// The value found.
    pub found: String,
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid value {} for `{}`, expected {}",
            self.found, self.key, self.expected
        )
    }
}

impl std::error::Error for Invalid {}

/// Why a scenario could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read scenario {file}")]
    Read {
        /// The file.
        file: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file was read but its content is wrong.
    #[error("{0}")]
    Content(Box<Diagnostic>),
}

/// A located message about a scenario file, rendered like a compiler's:
/// `file:line:column: message`, then the line with a caret under the culprit.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// The file.
    pub file: String,
    /// 1-based line and column (in characters), when the problem has a place.
    pub position: Option<(usize, usize)>,
    /// What is wrong and what was expected.
    pub message: String,
    /// The offending line and the caret's (column, width), for display.
    snippet: Option<(String, usize, usize)>,
}

impl Diagnostic {
    fn new(file: &str, src: &str, span: Option<std::ops::Range<usize>>, message: String) -> Self {
        let Some(span) = span.filter(|s| s.start <= src.len()) else {
            return Diagnostic {
                file: file.to_owned(),
                position: None,
                message,
                snippet: None,
            };
        };
        // Clamp to char boundaries.
        let mut start = span.start;
        while !src.is_char_boundary(start) {
            start -= 1;
        }
        let line_start = src[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = src[start..].find('\n').map_or(src.len(), |i| start + i);
        let line_no = src[..start].matches('\n').count() + 1;
        let col = src[line_start..start].chars().count() + 1;
        let text = src[line_start..line_end].trim_end_matches('\r').to_owned();
        let end = span.end.clamp(start, line_end);
        let width = src.get(start..end).map_or(1, |s| s.chars().count().max(1));
        Diagnostic {
            file: file.to_owned(),
            position: Some((line_no, col)),
            message,
            snippet: Some((text, col, width)),
        }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position {
            Some((line, col)) => write!(f, "{}:{line}:{col}: {}", self.file, self.message)?,
            None => write!(f, "{}: {}", self.file, self.message)?,
        }
        if let (Some((line, _)), Some((text, col, width))) = (self.position, &self.snippet) {
            let gutter = line.to_string().len();
            write!(
                f,
                "\n{:gutter$} |\n{line} | {text}\n{:gutter$} | {:pad$}{}",
                "",
                "",
                "",
                "^".repeat(*width),
                pad = col - 1
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostic {}

impl DemoConfig {
    /// Reads and checks the scenario at `path`.
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let file = path.display().to_string();
        let src = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            file: file.clone(),
            source,
        })?;
        Self::parse(&file, &src)
    }

    /// Parses and checks scenario text; `file` names it in messages.
    pub fn parse(file: &str, src: &str) -> Result<Self, ConfigError> {
        let cfg: DemoConfig = toml::from_str(src).map_err(|e| {
            ConfigError::Content(Box::new(Diagnostic::new(
                file,
                src,
                e.span(),
                e.message().to_owned(),
            )))
        })?;
        cfg.validate().map_err(|inv| {
            let span = span_of(src, inv.key);
            ConfigError::Content(Box::new(Diagnostic::new(file, src, span, inv.to_string())))
        })?;
        Ok(cfg)
    }

    /// Checks every value's range; the first problem found is returned.
    pub fn validate(&self) -> Result<(), Invalid> {
        let t = &self.town;
        check(
            "end_s",
            self.end_s,
            self.end_s > 0.0 && self.end_s <= MAX_END_S,
            format!("a number of seconds in (0, {MAX_END_S:e}]"),
        )?;
        let side = format!("an integer in 2..={MAX_GRID_SIDE}");
        let side_ok = |n: u32| (2..=MAX_GRID_SIDE).contains(&n);
        check("town.columns", t.columns, side_ok(t.columns), side.clone())?;
        check("town.rows", t.rows, side_ok(t.rows), side)?;
        check(
            "town.block_m",
            t.block_m,
            t.block_m > 0.0 && t.block_m <= 1e6,
            "a length in metres in (0, 1e6]",
        )?;
        check(
            "town.diagonal_share",
            t.diagonal_share,
            (0.0..=1.0).contains(&t.diagonal_share),
            "a share in [0, 1]",
        )?;
        let max_missing = t.max_missing_blocks();
        check(
            "town.missing_blocks",
            t.missing_blocks,
            t.missing_blocks <= max_missing,
            format!("at most {max_missing} for a {}x{} grid", t.columns, t.rows),
        )?;
        let junctions = t.junctions();
        check(
            "cars.count",
            self.cars.count,
            self.cars.count >= 1 && u64::from(self.cars.count) <= junctions,
            format!("a number of cars in 1..={junctions} (one per junction at most)"),
        )?;
        check(
            "cars.speed_mps",
            self.cars.speed_mps,
            self.cars.speed_mps > 0.0 && self.cars.speed_mps <= 1e4,
            "a speed in m/s in (0, 1e4]",
        )?;
        check(
            "cars.tick_s",
            self.cars.tick_s,
            self.cars.tick_s >= 1e-3 && self.cars.tick_s <= 3600.0,
            "a period in seconds in [0.001, 3600]",
        )?;
        check(
            "cars.think_us_per_node",
            self.cars.think_us_per_node,
            self.cars.think_us_per_node <= 1_000_000,
            "at most 1000000 microseconds",
        )?;
        check(
            "cars.distance_weight",
            self.cars.distance_weight,
            (0.0..=1e3).contains(&self.cars.distance_weight),
            "a weight in [0, 1000]",
        )?;
        let c = &self.channel;
        let ms = "a duration in milliseconds in [0, 3.6e6]";
        let ms_ok = |v: f64| (0.0..=3.6e6).contains(&v);
        check("channel.delay_ms", c.delay_ms, ms_ok(c.delay_ms), ms)?;
        check("channel.jitter_ms", c.jitter_ms, ms_ok(c.jitter_ms), ms)?;
        check(
            "channel.loss",
            c.loss,
            (0.0..=1.0).contains(&c.loss),
            "a probability in [0, 1]",
        )?;
        if let Some(r) = c.range_m {
            check(
                "channel.range_m",
                r,
                r > 0.0 && r.is_finite(),
                "a positive range in metres (leave it out for unlimited)",
            )?;
        }
        Ok(())
    }
}

/// The JSON Schema of demo scenario files (draft 7, for editors): what
/// `scenarios/demo.schema.json` holds, pretty-printed. The limits that depend on other keys
/// (missing blocks and cars against the grid's size) are `validate`'s alone.
///
/// ```
/// let schema = vitro_demo::config::json_schema();
/// assert_eq!(schema.get("title").and_then(|t| t.as_str()), Some("DemoConfig"));
/// ```
pub fn json_schema() -> schemars::Schema {
    let generator = schemars::generate::SchemaSettings::draft07().into_generator();
    generator.into_root_schema_for::<DemoConfig>()
}

impl TownConfig {
    /// Number of junctions of the full grid before blocks go missing.
    fn grid_junctions(&self) -> u64 {
        u64::from(self.columns) * u64::from(self.rows)
    }
    /// Number of junctions of the town.
    pub fn junctions(&self) -> u64 {
        self.grid_junctions()
            .saturating_sub(u64::from(self.missing_blocks))
    }
    /// How many inner junctions can go missing: those at odd (column, row), none of which
    /// touch another, so the town stays connected whichever are chosen.
    pub fn max_missing_blocks(&self) -> u32 {
        let odd = |n: u32| n.saturating_sub(1) / 2;
        odd(self.columns).saturating_mul(odd(self.rows))
    }
}

fn check<T: fmt::Display>(
    key: &'static str,
    value: T,
    ok: bool,
    expected: impl Into<String>,
) -> Result<(), Invalid> {
    if ok {
        Ok(())
    } else {
        Err(Invalid {
            key,
            expected: expected.into(),
            found: value.to_string(),
        })
    }
}

/// The span of the value at a dotted key path in TOML text, if present.
fn span_of(src: &str, key: &str) -> Option<std::ops::Range<usize>> {
    let root = DeTable::parse(src).ok()?;
    let mut table = root.get_ref();
    let mut parts = key.split('.').peekable();
    while let Some(part) = parts.next() {
        let value = table.get(part)?;
        if parts.peek().is_none() {
            return Some(value.span());
        }
        table = value.get_ref().as_table()?;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
seed = 1
end_s = 100.0
[town]
columns = 4
rows = 3
block_m = 50.0
diagonal_share = 0.5
missing_blocks = 1
[cars]
count = 2
speed_mps = 5.0
[channel]
delay_ms = 1.0
jitter_ms = 0.0
loss = 0.0
"#;

    fn err(src: &str) -> Diagnostic {
        match DemoConfig::parse("t.toml", src) {
            Err(ConfigError::Content(d)) => *d,
            other => panic!("expected a content error, got {other:?}"),
        }
    }

    #[test]
    fn good_file_parses_with_defaults() {
        let c = DemoConfig::parse("t.toml", GOOD).unwrap();
        assert_eq!(c.name, "demo");
        assert_eq!(c.cars.tick_s, 0.5);
        assert_eq!(c.channel.range_m, None);
        assert_eq!(c.town.junctions(), 11);
    }

    #[test]
    fn unknown_key_is_located() {
        let d = err(&GOOD.replace("rows = 3", "rows = 3\nrow = 3"));
        assert_eq!(d.position, Some((7, 1)));
        assert!(d.message.contains("unknown field `row`"), "{}", d.message);
        assert!(d.message.contains("expected one of"), "{}", d.message);
    }

    #[test]
    fn range_error_points_at_value() {
        let d = err(&GOOD.replace("loss = 0.0", "loss = 1.5"));
        assert_eq!(d.position, Some((16, 8)));
        assert!(d.message.contains("channel.loss"), "{}", d.message);
        assert!(d.message.contains("probability in [0, 1]"), "{}", d.message);
        let shown = d.to_string();
        assert!(
            shown.ends_with("16 | loss = 1.5\n   |        ^^^"),
            "{shown}"
        );
    }

    #[test]
    fn cross_field_limits() {
        let d = err(&GOOD.replace("count = 2", "count = 12"));
        assert!(d.message.contains("1..=11"), "{}", d.message);
        let d = err(&GOOD.replace("missing_blocks = 1", "missing_blocks = 2"));
        assert!(
            d.message.contains("at most 1 for a 4x3 grid"),
            "{}",
            d.message
        );
    }

    #[test]
    fn missing_section_has_no_panic() {
        let d = err("seed = 1\nend_s = 5.0\n");
        assert!(d.message.contains("missing field"), "{}", d.message);
    }

    #[test]
    fn max_missing_blocks_counts_odd_inner_junctions() {
        let t = |columns, rows| TownConfig {
            columns,
            rows,
            block_m: 1.0,
            diagonal_share: 0.0,
            missing_blocks: 0,
        };
        assert_eq!(t(2, 2).max_missing_blocks(), 0);
        assert_eq!(t(3, 3).max_missing_blocks(), 1);
        assert_eq!(t(9, 8).max_missing_blocks(), 4 * 3);
    }
}
