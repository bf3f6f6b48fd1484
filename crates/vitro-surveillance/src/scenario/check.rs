//! Checking a surveillance scenario: ranges, names, the files it names, then its points
//! against the site. Every problem is reported together, each at the place of its key; the
//! shared tables are checked by `vitro_tactical::scenario::checker`.

use super::SurveillanceFile;
use super::parse::parse;
use std::path::{Path, PathBuf};
use vitro_site::site::Site;
use vitro_tactical::scenario::checker::{Checker, SiteFiles, TOWN_XY};
use vitro_tactical::scenario::{Diagnostics, EntityType, MAX_END_S, SideSpec, SourceMap};

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
    let files = SiteFiles::resolve(path, &file.site);
    let map = SourceMap::new(path, text);
    let mut c = Checker::new(&map, &file.entities);
    c.site(&file.site, &files);
    check_file(&mut c, &file);
    let site = if files.exist() {
        match files.load(&file.site, &map) {
            Ok(site) => {
                check_site(&mut c, &file, &site);
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
    let problems = c.finish();
    match site {
        Some(site) if problems.is_empty() => Ok(Validated {
            file,
            path: path.to_path_buf(),
            map: files.map,
            terrain: files.terrain,
            site,
        }),
        _ => Err(Diagnostics::new(problems)),
    }
}

/// Every problem that can be found without the site.
fn check_file(c: &mut Checker<'_>, f: &SurveillanceFile) {
    c.end(&f.end);
    c.fidelity(&f.fidelity);
    c.point("station.start", f.station.start, TOWN_XY);
    c.entities();
    composition(c, f);
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
    c.channel(&f.channel);
    c.record(&f.record);
}

/// What the mission is made of: blue UAVs and red ground units, at least one of each.
fn composition(c: &mut Checker<'_>, f: &SurveillanceFile) {
    let (mut uavs, mut reds) = (0u64, 0u64);
    for (i, e) in f.entities.iter().enumerate() {
        match (e.side, e.kind) {
            (SideSpec::Blue, t) if t.is_aircraft() => uavs += u64::from(e.count),
            (SideSpec::Red, EntityType::Trooper | EntityType::Car)
            | (SideSpec::Red, EntityType::Truck | EntityType::Ugv) => reds += u64::from(e.count),
            (side, _) => {
                let message =
                    format!("entity `{}` is a {:?} {}", e.name, side, e.kind.name()).to_lowercase();
                let expected = "blue UAVs (procerus, vidar, skeldar) or red ground units \
                                (trooper, car, truck, ugv)";
                c.push(&format!("entity.{i}.type"), message, expected);
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
fn check_site(c: &mut Checker<'_>, file: &SurveillanceFile, site: &Site) {
    c.place(site, "station.start", file.station.start, true);
    c.starts(site);
    let [x0, y0, x1, y1] = site.map.extent;
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
            c.push(
                path,
                format!("`{path}` {a:?} lies outside the town"),
                &expected,
            );
        }
        sectors += crate::sector::grid_size(*a, file.search.sector_m);
    }
    if sectors > MAX_SECTORS {
        let message = format!(
            "the areas make {sectors} sectors of {} m",
            file.search.sector_m
        );
        let expected = format!("at most {MAX_SECTORS} sectors: larger sectors");
        c.push("search.sector_m", message, &expected);
    }
}
