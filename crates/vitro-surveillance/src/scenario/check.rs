//! Checking a surveillance scenario: ranges, names, the files it names, then its points
//! against the site. Every problem is reported together, each at the place of its key.

use super::SurveillanceFile;
use super::parse::parse;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::scenario::{
    ALTITUDE_M, Diagnostic, Diagnostics, EntityType, MAX_COUNT, MAX_END_S, SideSpec, SourceMap,
    VisionSpec,
};

/// Most sectors a scenario may cut its areas into.
pub const MAX_SECTORS: usize = 400;

/// A surveillance scenario read and checked against its site, with the site built.
#[derive(Debug)]
pub struct Validated {
    /// The scenario.
    pub file: SurveillanceFile,
    /// The scenario file's path, as it was named.
    pub path: PathBuf,
    /// The map, absolute.
    pub map: PathBuf,
    /// The terrain, absolute.
    pub terrain: PathBuf,
    /// The town on its terrain at the scenario's offset.
    pub site: Site,
}

/// Reads `text` as the scenario file at `path` (its paths resolve from `path`'s directory,
/// its problems name `path`) and checks it, the site included.
///
/// # Errors
/// Every problem found, each with its file, line and column.
pub fn validate_text(path: &Path, text: &str) -> Result<Validated, Diagnostics> {
    let file = parse(path, text).map_err(Diagnostics::new)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let resolve = |p: &Path| {
        let joined = dir.join(p);
        joined
            .canonicalize()
            .or_else(|_| std::path::absolute(&joined))
            .unwrap_or(joined)
    };
    let (map_file, terrain_file) = (resolve(&file.site.map), resolve(&file.site.terrain));
    let map = SourceMap::new(path, text);
    let mut c = Checks {
        file: &file,
        map: &map,
        out: Vec::new(),
    };
    c.file_exists(
        "site.map",
        &file.site.map,
        &map_file,
        "an OpenStreetMap .osm.pbf file",
    );
    c.file_exists(
        "site.terrain",
        &file.site.terrain,
        &terrain_file,
        "an elevation model",
    );
    check_file(&mut c);
    let mut problems = c.out;
    if map_file.is_file() && terrain_file.is_file() {
        match build_site(&file, &map, &map_file, &terrain_file) {
            Ok(site) => {
                problems.extend(check_site(&file, &site, &map));
                if problems.is_empty() {
                    return Ok(Validated {
                        file,
                        path: path.to_path_buf(),
                        map: map_file,
                        terrain: terrain_file,
                        site,
                    });
                }
            }
            Err(d) => problems.push(*d),
        }
    }
    Err(Diagnostics::new(problems))
}

/// Builds the town on its terrain; problems point at `[site]`.
fn build_site(
    file: &SurveillanceFile,
    map: &SourceMap<'_>,
    map_file: &Path,
    terrain_file: &Path,
) -> Result<Site, Box<Diagnostic>> {
    let town = TownMap::load(map_file, &MapConfig::default()).map_err(|e| {
        Box::new(map.at(
            "site.map",
            format!("cannot load the map: {e}"),
            "an OpenStreetMap .osm.pbf file",
        ))
    })?;
    let ground = Terrain::load(terrain_file).map_err(|e| {
        Box::new(map.at(
            "site.terrain",
            format!("cannot load the terrain: {e}"),
            "an ESRI ASCII grid (.asc) or a GeoTIFF",
        ))
    })?;
    let config = SiteConfig {
        offset: file.site.offset,
        ..SiteConfig::default()
    };
    Site::new(town, ground, &config).map_err(|e| {
        Box::new(map.at(
            "site.terrain",
            format!("cannot set the town on the terrain: {e}"),
            "an offset that keeps the whole town on the terrain",
        ))
    })
}

/// Collects problems, each at the place of the key it names.
struct Checks<'a> {
    file: &'a SurveillanceFile,
    map: &'a SourceMap<'a>,
    out: Vec<Diagnostic>,
}

impl Checks<'_> {
    fn push(&mut self, path: &str, message: String, expected: &str) {
        self.out.push(self.map.at(path, message, expected));
    }

    /// A number in `[lo, hi]` (or `(lo, hi]` when `open_lo`).
    fn num(&mut self, path: &str, v: f64, open_lo: bool, lo: f64, hi: f64, what: &str) {
        let ok = if open_lo { v > lo } else { v >= lo } && v <= hi;
        if !ok {
            let bracket = if open_lo { '(' } else { '[' };
            let expected = format!("{what} in {bracket}{lo}, {hi}]");
            self.push(path, format!("invalid value {v} for `{path}`"), &expected);
        }
    }

    fn file_exists(&mut self, path: &str, given: &Path, resolved: &Path, what: &str) {
        if !resolved.is_file() {
            let message = format!(
                "file `{}` not found for `{path}` (looked at {})",
                given.display(),
                resolved.display()
            );
            let expected = format!("{what}, relative to the scenario file's directory");
            self.push(path, message, &expected);
        }
    }

    fn vision(&mut self, path: &str, v: &VisionSpec) {
        let p = |k: &str| format!("{path}.{k}");
        self.num(&p("range_m"), v.range_m, true, 0.0, 1e5, "metres");
        self.num(&p("fov_deg"), v.fov_deg, true, 0.0, 360.0, "degrees");
        self.num(&p("p0"), v.p0, false, 0.0, 1.0, "a probability");
        self.num(&p("falloff"), v.falloff, false, 0.0, 100.0, "an exponent");
        let m = v.misidentification;
        self.num(&p("misidentification"), m, false, 0.0, 1.0, "a probability");
    }

    /// An area `[x_min, y_min, x_max, y_max]`: finite, non-empty.
    fn area(&mut self, path: &str, a: [f64; 4]) {
        let ok = a.iter().all(|v| v.is_finite()) && a[0] < a[2] && a[1] < a[3];
        if !ok {
            let message = format!("invalid area {a:?} for `{path}`");
            self.push(
                path,
                message,
                "town metres [x_min, y_min, x_max, y_max], min < max",
            );
        }
    }

    /// A range `[min, max]` of non-negative numbers.
    fn range(&mut self, path: &str, r: [f64; 2], what: &str) {
        let ok = r.iter().all(|v| v.is_finite()) && 0.0 <= r[0] && r[0] <= r[1];
        if !ok {
            let message = format!("invalid range {r:?} for `{path}`");
            self.push(
                path,
                message,
                &format!("[min, max] {what}, 0 <= min <= max"),
            );
        }
    }
}

/// Every problem that can be found without the site.
fn check_file(c: &mut Checks<'_>) {
    let f = c.file;
    c.num("end.time_s", f.end.time_s, true, 0.0, MAX_END_S, "seconds");
    for t in EntityType::ALL {
        if let Some(level) = f.fidelity.override_of(t)
            && !t.levels().contains(&level)
        {
            let names: Vec<String> = t.levels().iter().map(|l| format!("`{l}`")).collect();
            let key = t.fidelity_key();
            let message = format!("unknown fidelity level `{level}` for `{key}`");
            c.push(
                &format!("fidelity.{key}"),
                message,
                &format!("one of {}", names.join(", ")),
            );
        }
    }
    entities(c);
    let s = &f.search;
    if let Some(a) = s.area {
        c.area("search.area", a);
    }
    c.num(
        "search.sector_m",
        s.sector_m,
        false,
        50.0,
        10_000.0,
        "metres",
    );
    c.num(
        "search.spacing_m",
        s.spacing_m,
        false,
        10.0,
        s.sector_m.max(10.0),
        "metres, at most `sector_m`",
    );
    for (i, a) in f.areas.iter().enumerate() {
        c.num(
            &format!("area.{i}.appear_s"),
            a.appear_s,
            false,
            0.0,
            MAX_END_S,
            "seconds",
        );
        c.area(&format!("area.{i}.area"), a.area);
    }
    let uavs: Vec<String> = f
        .entities
        .iter()
        .filter(|e| e.kind.is_aircraft())
        .flat_map(|e| e.names())
        .collect();
    for (i, l) in f.losses.iter().enumerate() {
        if !uavs.contains(&l.uav) {
            let message = format!("no UAV is named `{}`", l.uav);
            c.push(
                &format!("loss.{i}.uav"),
                message,
                &format!("one of {}", uavs.join(", ")),
            );
        }
        c.num(
            &format!("loss.{i}.at_s"),
            l.at_s,
            false,
            0.0,
            MAX_END_S,
            "seconds",
        );
    }
    c.num(
        "failures.rate_per_h",
        f.failures.rate_per_h,
        false,
        0.0,
        1000.0,
        "failures per hour",
    );
    let t = &f.team;
    c.num(
        "team.heartbeat_s",
        t.heartbeat_s,
        true,
        0.0,
        3600.0,
        "seconds",
    );
    let lost = t.lost_after_s;
    c.num(
        "team.lost_after_s",
        lost,
        true,
        t.heartbeat_s,
        36_000.0,
        "seconds, more than `heartbeat_s`",
    );
    c.num("team.report_s", t.report_s, true, 0.0, 3600.0, "seconds");
    c.num(
        "team.report_fresh_s",
        t.report_fresh_s,
        true,
        0.0,
        36_000.0,
        "seconds",
    );
    c.num("team.orbit_m", t.orbit_m, false, 20.0, 5000.0, "metres");
    c.num(
        "team.reacquire_s",
        t.reacquire_s,
        false,
        0.0,
        36_000.0,
        "seconds",
    );
    c.num("team.cue_m", t.cue_m, false, 0.0, 1e5, "metres");
    c.num(
        "sensors.period_s",
        f.sensors.period_s,
        true,
        0.0,
        600.0,
        "seconds",
    );
    c.vision("sensors.camera", &f.sensors.camera);
    let tr = &f.tracking;
    let confirm = f64::from(tr.confirm_looks);
    c.num(
        "tracking.confirm_looks",
        confirm,
        false,
        1.0,
        1000.0,
        "a count",
    );
    let misses = f64::from(tr.misses_to_lose);
    c.num(
        "tracking.misses_to_lose",
        misses,
        false,
        1.0,
        10_000.0,
        "a count",
    );
    c.num(
        "tracking.max_locks",
        f64::from(tr.max_locks),
        false,
        1.0,
        100.0,
        "a count",
    );
    let a = &f.allocation;
    c.num(
        "allocation.budget",
        a.budget as f64,
        false,
        1.0,
        1e6,
        "iterations",
    );
    c.num(
        "allocation.iteration_ms",
        a.iteration_ms,
        false,
        0.0,
        1e4,
        "milliseconds",
    );
    c.num(
        "allocation.proposal_deadline_s",
        a.proposal_deadline_s,
        true,
        0.0,
        3600.0,
        "seconds",
    );
    c.num(
        "allocation.report_deadline_s",
        a.report_deadline_s,
        true,
        0.0,
        3600.0,
        "seconds",
    );
    let expiry = a.proposal_expiry_s;
    let deadline = a.proposal_deadline_s;
    c.num(
        "allocation.proposal_expiry_s",
        expiry,
        true,
        deadline,
        36_000.0,
        "seconds, more than `proposal_deadline_s`",
    );
    c.num(
        "allocation.retry_s",
        a.retry_s,
        true,
        0.0,
        36_000.0,
        "seconds",
    );
    c.range("red.leg_m", f.red.leg_m, "metres");
    c.range("red.dwell_s", f.red.dwell_s, "seconds");
    let ch = &f.channel;
    c.num(
        "channel.delay_ms",
        ch.delay_ms,
        false,
        0.0,
        1e6,
        "milliseconds",
    );
    c.num(
        "channel.jitter_ms",
        ch.jitter_ms,
        false,
        0.0,
        1e6,
        "milliseconds",
    );
    c.num("channel.loss", ch.loss, false, 0.0, 1.0, "a probability");
    c.num("channel.range_m", ch.range_m, true, 0.0, 1e6, "metres");
    c.num(
        "record.sample_s",
        f.record.sample_s,
        true,
        0.0,
        3600.0,
        "seconds",
    );
}

/// Names, counts, sides, types and altitudes of each `[[entity]]`.
fn entities(c: &mut Checks<'_>) {
    let f = c.file;
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let (mut uavs, mut reds) = (0u64, 0u64);
    let (lo, hi) = ALTITUDE_M;
    for (i, e) in f.entities.iter().enumerate() {
        let at = |k: &str| format!("entity.{i}.{k}");
        if e.name.trim().is_empty() {
            c.push(&at("name"), "empty entity name".into(), "a non-empty name");
        }
        for name in e.names() {
            if let Some(&first) = seen.get(&name) {
                let line = c.map.at(&format!("entity.{first}.name"), "", "").position;
                let line = line.map_or(String::new(), |(l, _)| format!(" (first at line {l})"));
                let message = format!("duplicate entity name `{name}`{line}");
                c.push(&at("name"), message, "a name used by one entity only");
                break;
            }
            seen.insert(name, i);
        }
        let count = f64::from(e.count);
        c.num(
            &at("count"),
            count,
            false,
            1.0,
            f64::from(MAX_COUNT),
            "a count",
        );
        match (e.side, e.kind.is_aircraft()) {
            (SideSpec::Blue, true) => {
                uavs += u64::from(e.count);
                match e.altitude_m {
                    Some(a) => c.num(&at("altitude_m"), a, false, lo, hi, "metres"),
                    None => {
                        let message = format!("UAV `{}` has no `altitude_m`", e.name);
                        c.push(
                            &at("type"),
                            message,
                            &format!("`altitude_m` in [{lo}, {hi}]"),
                        );
                    }
                }
            }
            (SideSpec::Red, false)
                if matches!(
                    e.kind,
                    EntityType::Trooper | EntityType::Car | EntityType::Truck | EntityType::Ugv
                ) =>
            {
                reds += u64::from(e.count);
                if e.altitude_m.is_some() {
                    let message = format!("red unit `{}` has an `altitude_m`", e.name);
                    c.push(
                        &at("altitude_m"),
                        message,
                        "no `altitude_m` for a ground unit",
                    );
                }
            }
            (side, _) => {
                let message =
                    format!("entity `{}` is a {:?} {}", e.name, side, e.kind.name()).to_lowercase();
                let expected = "blue UAVs (procerus, vidar, skeldar) or red ground units \
                                (trooper, car, truck, ugv)";
                c.push(&at("type"), message, expected);
            }
        }
    }
    if uavs == 0 {
        let expected = "an `[[entity]]` of blue procerus, vidar or skeldar";
        c.push("entity", "the scenario has no UAV".into(), expected);
    }
    if reds == 0 {
        let expected = "an `[[entity]]` of red trooper, car, truck or ugv";
        c.push("entity", "the scenario has no red unit".into(), expected);
    }
}

/// The points of the file against the site: in the town, and on free ground for the
/// station and the red units; the areas overlap the town; not too many sectors.
fn check_site(file: &SurveillanceFile, site: &Site, map: &SourceMap<'_>) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let [x0, y0, x1, y1] = site.map.extent;
    let mut point = |path: &str, p: [f64; 2], free: bool| {
        if !p.iter().all(|v| v.is_finite()) {
            out.push(map.at(
                path,
                format!("invalid point {p:?} for `{path}`"),
                "finite town metres",
            ));
        } else if !(x0..=x1).contains(&p[0]) || !(y0..=y1).contains(&p[1]) {
            let expected =
                format!("town metres with x in [{x0:.0}, {x1:.0}] and y in [{y0:.0}, {y1:.0}]");
            out.push(map.at(
                path,
                format!("`{path}` {p:?} lies outside the town"),
                &expected,
            ));
        } else if free && site.zones.is_forbidden(p) {
            let q = site.zones.nearest_free(p);
            let expected = format!(
                "a free point outside buildings and forbidden zones, e.g. [{:.1}, {:.1}]",
                q[0], q[1]
            );
            out.push(map.at(
                path,
                format!("`{path}` {p:?} lies in a building or a forbidden zone"),
                &expected,
            ));
        }
    };
    point("station.start", file.station.start, true);
    for (i, e) in file.entities.iter().enumerate() {
        if let Some(p) = e.start {
            point(&format!("entity.{i}.start"), p, !e.kind.is_aircraft());
        }
    }
    let mut areas: Vec<(String, [f64; 4])> = Vec::new();
    areas.push((
        "search.area".into(),
        file.search.area.unwrap_or(site.map.extent),
    ));
    for (i, a) in file.areas.iter().enumerate() {
        areas.push((format!("area.{i}.area"), a.area));
    }
    let mut sectors = 0;
    for (path, a) in &areas {
        let overlap = a[0] < x1 && a[2] > x0 && a[1] < y1 && a[3] > y0;
        if !overlap {
            let expected =
                format!("an area overlapping the town [{x0:.0}, {y0:.0}, {x1:.0}, {y1:.0}]");
            out.push(map.at(
                path,
                format!("`{path}` {a:?} lies outside the town"),
                &expected,
            ));
        }
        sectors += crate::sector::grid_size(*a, file.search.sector_m);
    }
    if sectors > MAX_SECTORS {
        let message = format!(
            "the areas make {sectors} sectors of {} m",
            file.search.sector_m
        );
        out.push(map.at(
            "search.sector_m",
            message,
            &format!("at most {MAX_SECTORS} sectors: larger sectors"),
        ));
    }
    out
}
