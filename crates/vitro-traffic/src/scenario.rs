//! The traffic scenario file: the tables every tactical mission shares (`[end]`, `[site]`,
//! `[fidelity]`, `[[entity]]`, `[channel]`, `[record]`, from `vitro_tactical::scenario`) and
//! the `[traffic]` table of its own. Every problem is reported at its file, line and column.
//!
//! ```
//! use vitro_traffic::scenario::TrafficFile;
//!
//! let text = r#"
//! kind = "traffic"
//! name = "rush hour"
//! seed = 7
//! end = { time_s = 600 }
//! site = { map = "town.osm.pbf", terrain = "valley.asc" }
//!
//! [[entity]]
//! name = "car"
//! type = "car"
//! side = "neutral"
//! count = 5
//! "#;
//! let file: TrafficFile = toml::from_str(text).unwrap();
//! assert_eq!(file.entities[0].count, 5);
//! assert_eq!(file.traffic.check_s, 1.0);
//! ```

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use vitro::time::UtcTime;
use vitro_site::site::Site;
use vitro_tactical::calibration::{Calibration, site_fingerprint, types_fingerprint};
use vitro_tactical::entity::roads::{FreeGraph, Roads};
use vitro_tactical::scenario::checker::{Checker, SiteFiles, resolve};
use vitro_tactical::scenario::tables::{self, Layout, one};
use vitro_tactical::scenario::{
    ChannelSpec, Diagnostic, Diagnostics, EndSpec, EntitySpec, FidelitySpec, RecordSpec,
    START_PATTERN, SiteSpec, SourceMap,
};
use vitro_tactical::types::TypeBook;

/// A whole scenario file of the traffic kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = schema_rules)]
pub struct TrafficFile {
    /// The kind of scenario, `"traffic"`: the tools pick the mission by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("const" = "traffic"))]
    pub kind: Option<String>,
    /// A short name for reports.
    #[schemars(regex(pattern = r"\S"))]
    pub name: String,
    /// Master seed of every random stream of the run (starts and destinations).
    pub seed: u64,
    /// When simulated time 0 is on the calendar, RFC 3339 (default
    /// 2024-06-01T06:00:00Z): recordings and the viewer's clock show it, the simulation
    /// never reads it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<String>", extend("pattern" = START_PATTERN, "format" = "date-time"))]
    pub start: Option<UtcTime>,
    /// When the run stops.
    pub end: EndSpec,
    /// The town and its terrain.
    pub site: SiteSpec,
    /// Fidelity level of each entity type.
    #[serde(default)]
    pub fidelity: FidelitySpec,
    /// The entities, one `[[entity]]` table per group: vehicles (car, truck, ugv) and
    /// troopers; any side.
    #[serde(rename = "entity")]
    pub entities: Vec<EntitySpec>,
    /// How the traffic is measured.
    #[serde(default)]
    pub traffic: TrafficSpec,
    /// The simulated radio channel (nobody talks in traffic; kept for the shared layout).
    #[serde(default)]
    pub channel: ChannelSpec,
    /// Sampling of the recording.
    #[serde(default)]
    pub record: RecordSpec,
}

/// The traffic's own settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TrafficSpec {
    /// Time between two looks of the referee at every body, seconds: a body commanded to
    /// move that has not moved since the last look has waited this long more
    /// (`deadlock_s` is measured to this resolution).
    #[schemars(range(min = 0.05, max = 60.0))]
    pub check_s: f64,
    /// Speeds below this count as standing still, metres per second.
    #[schemars(range(min = 0.0, max = 5.0))]
    pub still_mps: f64,
}

impl Default for TrafficSpec {
    fn default() -> Self {
        TrafficSpec {
            check_s: 1.0,
            still_mps: 0.1,
        }
    }
}

/// The traffic's rules on top of the shared tables' schemas: `kind` is required, and
/// every entity moves on the ground.
fn schema_rules(schema: &mut schemars::Schema) {
    vitro_tactical::scenario::require_kind(schema);
    let ground = schemars::json_schema!({
        "properties": { "type": { "enum": ["car", "truck", "ugv", "trooper"] } }
    });
    if let Some(items) = schema
        .get_mut("properties")
        .and_then(|p| p.get_mut("entity"))
        .and_then(|e| e.get_mut("items"))
    {
        let entity = items.take();
        *items = schemars::json_schema!({ "allOf": [entity, ground] }).into();
    }
}

/// The JSON Schema of traffic scenario files (draft 7, for editors): what
/// `scenarios/traffic.schema.json` holds, pretty-printed.
pub fn json_schema() -> schemars::Schema {
    let generator = schemars::generate::SchemaSettings::draft07().into_generator();
    generator.into_root_schema_for::<TrafficFile>()
}

/// The keys of a traffic scenario's top level, in the order of [`TrafficFile`]'s fields.
pub const TOP_LEVEL_KEYS: [&str; 11] = [
    "kind", "name", "seed", "start", "end", "site", "fidelity", "entity", "traffic", "channel",
    "record",
];

/// The traffic's own top-level keys beside the shared ones.
const LAYOUT: Layout<'static> = Layout {
    keys: &[("traffic", one::<TrafficSpec>)],
    required: &[],
};

/// A traffic scenario read and checked against its site, with the site built.
#[derive(Debug)]
pub struct Validated {
    /// The scenario.
    pub file: TrafficFile,
    /// The scenario file's path, as it was named.
    pub path: PathBuf,
    /// The town on its terrain at the scenario's offset.
    pub site: Site,
    /// The calibration of the abstract levels `[fidelity] calibration` names, checked
    /// against the site and the types.
    pub calibration: Option<Calibration>,
}

/// Reads `text` as the scenario file at `path` (its paths resolve from `path`'s directory,
/// its problems name `path`) and checks it, the site included.
///
/// # Errors
/// Every problem found, each with its file, line and column.
pub fn validate_text(path: &Path, text: &str) -> Result<Validated, Diagnostics> {
    let file: TrafficFile = tables::parse(path, text, &LAYOUT).map_err(Diagnostics::new)?;
    let files = SiteFiles::resolve(path, &file.site);
    let map = SourceMap::new(path, text);
    let mut c = Checker::new(&map, &file.entities);
    c.site(&file.site, &files);
    check_file(&mut c, &file);
    let given = file.fidelity.calibration.as_deref();
    let calibration_file = given.map(|p| resolve(path, p));
    if let (Some(given), Some(resolved)) = (given, &calibration_file) {
        c.file_exists(
            "fidelity.calibration",
            given,
            resolved,
            "a calibration file made by `vitro calibrate`",
        );
    }
    let mut calibration = None;
    let site = if files.exist() {
        match files.load(&file.site, &map) {
            Ok(site) => {
                check_room(&mut c, &file, &site);
                if let Some(resolved) = calibration_file.filter(|p| p.is_file()) {
                    match load_calibration(&resolved, &files, &file) {
                        Ok(cal) => calibration = Some(cal),
                        Err(e) => c.push(
                            "fidelity.calibration",
                            e,
                            "a calibration made by `vitro calibrate` on this scenario's map and types",
                        ),
                    }
                }
                for (i, e) in file.entities.iter().enumerate() {
                    if let Some(p) = e.start {
                        c.place(&site, &format!("entity.{i}.start"), p, true);
                    }
                }
                Some(site)
            }
            Err(d) => {
                c.extend([*d]);
                None
            }
        }
    } else {
        None
    };
    let problems: Vec<Diagnostic> = c.finish();
    match site {
        Some(site) if problems.is_empty() => Ok(Validated {
            file,
            path: path.to_path_buf(),
            site,
            calibration,
        }),
        _ => Err(Diagnostics::new(problems)),
    }
}

/// Reads the calibration at `path` and checks it was made on this site and these types.
fn load_calibration(
    path: &Path,
    files: &SiteFiles,
    f: &TrafficFile,
) -> Result<Calibration, String> {
    let cal = Calibration::read(path).map_err(|e| e.to_string())?;
    let site =
        site_fingerprint(&files.map, &files.terrain, f.site.offset).map_err(|e| e.to_string())?;
    cal.check(&site, &types_fingerprint(TypeBook::builtin()))
        .map_err(|e| e.to_string())?;
    Ok(cal)
}

/// Each body starts at a junction of its own: the groups must fit the main free street
/// graph (vehicles) and walk graph (troopers) of the site.
fn check_room(c: &mut Checker<'_>, f: &TrafficFile, site: &Site) {
    let roads = Roads::new(site);
    let room = |g: &FreeGraph| g.main.iter().filter(|&&m| m).count() as u64;
    let (drive, walk) = (room(&roads.drive), room(&roads.walk));
    let (mut vehicles, mut troopers) = (0u64, 0u64);
    for (i, e) in f.entities.iter().enumerate() {
        let (used, room, what) = if e.kind.is_vehicle() {
            (&mut vehicles, drive, "vehicles")
        } else {
            (&mut troopers, walk, "troopers")
        };
        *used += u64::from(e.count);
        if *used > room {
            let message = format!("{} {what} in all", *used);
            let expected = format!("at most {room} {what}, one per junction of the town");
            c.push(&format!("entity.{i}.count"), message, &expected);
        }
    }
}

/// Every problem that can be found without the site.
fn check_file(c: &mut Checker<'_>, f: &TrafficFile) {
    c.end(&f.end);
    c.fidelity(&f.fidelity);
    c.entities();
    c.channel(&f.channel);
    c.record(&f.record);
    for (i, e) in f.entities.iter().enumerate() {
        if !(e.kind.is_vehicle() || e.kind == vitro_tactical::scenario::EntityType::Trooper) {
            let message = format!("a {} in traffic", e.kind.name());
            c.push(
                &format!("entity.{i}.type"),
                message,
                "a ground unit: car, truck, ugv or trooper",
            );
        }
    }
    let t = &f.traffic;
    c.num("traffic.check_s", t.check_s, false, 0.05, 60.0, "seconds");
    c.num(
        "traffic.still_mps",
        t.still_mps,
        false,
        0.0,
        5.0,
        "metres per second",
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"kind = "traffic"
name = "x"
seed = 1
end = { time_s = 60 }
site = { map = "m.osm.pbf", terrain = "t.asc" }

[[entity]]
name = "car"
type = "car"
side = "neutral"
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
        let f: TrafficFile = tables::parse(Path::new("t.toml"), GOOD, &LAYOUT).unwrap();
        assert_eq!(f.entities.len(), 1);
        assert_eq!(f.traffic, TrafficSpec::default());
    }

    #[test]
    fn a_bad_value_is_reported_at_its_place() {
        let text = format!("{GOOD}\n[traffic]\ncheck_s = \"often\"\n");
        let e = tables::parse::<TrafficFile>(Path::new("t.toml"), &text, &LAYOUT).unwrap_err();
        assert_eq!(
            e[0].to_string(),
            "t.toml:13:11: invalid type: string \"often\" (expected a number)"
        );
    }

    #[test]
    fn an_aircraft_is_refused() {
        let text = GOOD.replace("type = \"car\"", "type = \"vidar\"");
        let e = validate_text(Path::new("t.toml"), &text).unwrap_err();
        let all = e.report();
        assert!(all.contains("a vidar in traffic"), "{all}");
    }
}
