//! The perimeter watch's scenario file: the tables every tactical mission shares, and its own
//! `[watch]` table, read and checked with the shared parser and checker.

use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;
use vitro::time::UtcTime;
use vitro_site::site::Site;
use vitro_tactical::scenario::checker::{Checker, SiteFiles, TOWN_XY};
use vitro_tactical::scenario::tables::{self, Layout, one};
use vitro_tactical::scenario::{
    ChannelSpec, Diagnostics, EndSpec, EntitySpec, FidelitySpec, RecordSpec, SideSpec, SiteSpec,
    SourceMap, VisionSpec,
};

// ANCHOR: tables
/// A perimeter-watch scenario file: the shared tables, then `[watch]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WatchFile {
    /// `"watch"`: the tools pick the mission by it.
    pub kind: Option<String>,
    /// A short name for reports.
    pub name: String,
    /// Master seed of every random stream of the run.
    pub seed: u64,
    /// When simulated time 0 is on the calendar.
    pub start: Option<UtcTime>,
    /// When the run stops.
    pub end: EndSpec,
    /// The town and its terrain.
    pub site: SiteSpec,
    /// The level of fidelity of each entity type.
    #[serde(default)]
    pub fidelity: FidelitySpec,
    /// Blue ground vehicles (the guards) and red troopers (the walkers).
    #[serde(rename = "entity")]
    pub entities: Vec<EntitySpec>,
    /// The radio.
    #[serde(default)]
    pub channel: ChannelSpec,
    /// Sampling of recordings.
    #[serde(default)]
    pub record: RecordSpec,
    /// The mission's own settings.
    pub watch: WatchSpec,
}

/// The `[watch]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WatchSpec {
    /// The place guarded, town metres.
    pub depot: [f64; 2],
    /// The guards patrol the junctions about this far around the depot, metres.
    pub ring_m: f64,
    /// The walkers start this far from the depot, metres `[min, max]`.
    pub approach_m: [f64; 2],
    /// A walker this close to the depot has reached it, metres.
    pub reach_m: f64,
    /// Time between two looks of a guard's camera, seconds.
    pub look_s: f64,
    /// A guard's camera.
    pub camera: VisionSpec,
}

/// The mission's own top-level keys (beside the shared ones) and those a file must have.
const LAYOUT: Layout<'static> = Layout {
    keys: &[("watch", one::<WatchSpec>)],
    required: &[("watch", "a `[watch]` table")],
};
// ANCHOR_END: tables

/// A scenario read and checked, with its site built.
#[derive(Debug)]
pub struct Validated {
    /// The scenario.
    pub file: WatchFile,
    /// The town on its terrain.
    pub site: Arc<Site>,
}

// ANCHOR: check
/// Reads `text` as the scenario file at `path` and checks it, the site included.
///
/// # Errors
/// Every problem found, each with its file, line and column.
pub fn validate(path: &Path, text: &str) -> Result<Validated, Diagnostics> {
    let file: WatchFile = tables::parse(path, text, &LAYOUT).map_err(Diagnostics::new)?;
    let files = SiteFiles::resolve(path, &file.site);
    let map = SourceMap::new(path, text);
    let mut c = Checker::new(&map, &file.entities);
    // The shared tables.
    c.site(&file.site, &files);
    c.end(&file.end);
    c.fidelity(&file.fidelity);
    c.entities();
    c.channel(&file.channel);
    c.record(&file.record);
    // The mission's own.
    let w = &file.watch;
    c.point("watch.depot", w.depot, TOWN_XY);
    c.num("watch.ring_m", w.ring_m, true, 0.0, 5000.0, "metres");
    c.range("watch.approach_m", w.approach_m, "metres");
    c.num("watch.reach_m", w.reach_m, true, 0.0, 1000.0, "metres");
    c.num("watch.look_s", w.look_s, true, 0.0, 600.0, "seconds");
    c.vision("watch.camera", &w.camera);
    for (i, e) in file.entities.iter().enumerate() {
        let fits = match e.side {
            SideSpec::Blue => e.kind.is_vehicle(),
            SideSpec::Red => e.kind.is_trooper(),
            SideSpec::Neutral => false,
        };
        if !fits {
            let side = format!("{:?}", e.side).to_lowercase();
            let message = format!("a {side} {} has no part here", e.kind.name());
            c.push(
                &format!("entity.{i}.type"),
                message,
                "blue ground vehicles (ugv, car, truck) or red troopers",
            );
        }
    }
    // The points against the site.
    let site = match files.exist().then(|| files.load(&file.site, &map)) {
        Some(Ok(site)) => {
            c.place(&site, "watch.depot", w.depot, true);
            c.starts(&site);
            Some(site)
        }
        Some(Err(d)) => {
            c.extend([*d]);
            None
        }
        None => None,
    };
    match (site, c.finish()) {
        (Some(site), problems) if problems.is_empty() => Ok(Validated {
            file,
            site: Arc::new(site),
        }),
        (_, problems) => Err(Diagnostics::new(problems)),
    }
}
// ANCHOR_END: check
