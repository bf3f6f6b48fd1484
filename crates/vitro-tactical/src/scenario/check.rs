//! The semantic checks of a parsed scenario: ranges, files, fidelity levels, entities, the
//! mission's needs ([`check_file`]), and places against the site ([`check_site`]).
//!
//! Every check adds its problem and goes on, so one pass reports them all.

use super::loaded::Loaded;
use super::span::{Diagnostic, SourceMap};
use super::{EntityType, ScenarioFile, SideSpec, VisionSpec};
use crate::behaviour::formation::Leader;
use std::collections::BTreeMap;
use std::path::Path;
use vitro_site::site::Site;

/// Largest end time, seconds.
pub const MAX_END_S: f64 = 1e6;
/// Most entities in one `[[entity]]` group (a scenario may have many groups: swarms of
/// tens of thousands run, see the scaling tables in docs/benchmarks.md).
pub const MAX_COUNT: u32 = 20_000;
/// Flight altitudes above the ground, metres.
pub const ALTITUDE_M: (f64, f64) = (20.0, 3000.0);

/// What a town point is.
const TOWN_XY: &str = "town metres [x, y]";

/// Collects problems, each at the place of the key it names.
struct Checks<'a> {
    file: &'a ScenarioFile,
    map: &'a SourceMap<'a>,
    out: Vec<Diagnostic>,
}

impl Checks<'_> {
    fn push(&mut self, path: &str, message: String, expected: &str) {
        self.out.push(self.map.at(path, message, expected));
    }

    /// The key at `path` for a message: `channel.loss`, or `count` of entity `scouts`.
    fn label(&self, path: &str) -> String {
        let mut parts = path.splitn(3, '.');
        if let (Some("entity"), Some(i), Some(rest)) = (parts.next(), parts.next(), parts.next())
            && let Some(e) = i
                .parse::<usize>()
                .ok()
                .and_then(|i| self.file.entities.get(i))
        {
            return format!("`{rest}` of entity `{}`", e.name);
        }
        format!("`{path}`")
    }

    /// Reports `value` at `path` unless `ok`.
    fn value(&mut self, path: &str, value: impl std::fmt::Display, ok: bool, expected: &str) {
        if !ok {
            let message = format!("invalid value {value} for {}", self.label(path));
            self.push(path, message, expected);
        }
    }

    /// A number in `[lo, hi]` (or `(lo, hi]` when `open_lo`).
    fn num(&mut self, path: &str, v: f64, open_lo: bool, lo: f64, hi: f64, what: &str) {
        let ok = if open_lo { v > lo } else { v >= lo } && v <= hi;
        let bracket = if open_lo { '(' } else { '[' };
        let expected = format!("{what} in {bracket}{lo}, {hi}]");
        self.value(path, v, ok, &expected);
    }

    /// A point `[x, y]`: finite, and two numbers in the file (toml reads the first two of
    /// a longer array without a word).
    fn point(&mut self, path: &str, p: [f64; 2], what: &str) {
        if let Some(n) = self.map.array_len(path).filter(|&n| n != 2) {
            let message = format!("{n} numbers for {}", self.label(path));
            self.push(path, message, &format!("an array of 2 numbers, {what}"));
        }
        let ok = p.iter().all(|c| c.is_finite());
        self.value(path, format!("{p:?}"), ok, &format!("finite {what}"));
    }

    fn file_exists(&mut self, path: &str, given: &Path, resolved: &Path, what: &str) {
        if !resolved.is_file() {
            let message = format!(
                "file `{}` not found for {} (looked at {})",
                given.display(),
                self.label(path),
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
}

/// The first problem of the formation rule program at `path` (if it can be read), at its
/// own line and column: the program is checked as the leader will load it.
fn program_problem(path: &Path) -> Option<Diagnostic> {
    let text = std::fs::read_to_string(path).ok()?;
    let name = path.display().to_string();
    let e = Leader::check_program(&name, &text).err()?;
    // The byte offset of the error's line and column (columns count characters).
    let (line, column) = (e.pos.line.max(1) as usize, e.pos.column.max(1) as usize);
    let start: usize = text
        .split_inclusive('\n')
        .take(line - 1)
        .map(str::len)
        .sum();
    let rest = text.get(start..).unwrap_or("");
    let offset = start
        + rest
            .char_indices()
            .nth(column - 1)
            .map_or(rest.len(), |(i, _)| i);
    let expected = Some("a leader program in the rule language".to_string());
    Some(Diagnostic::new(
        path,
        &text,
        Some(offset..offset + 1),
        e.kind.to_string(),
        expected,
    ))
}

/// Every problem of `loaded` that can be found without its site.
pub(crate) fn check_file(loaded: &Loaded, map: &SourceMap<'_>) -> Vec<Diagnostic> {
    let f = &loaded.file;
    let mut c = Checks {
        file: f,
        map,
        out: Vec::new(),
    };
    c.value(
        "name",
        format!("{:?}", f.name),
        !f.name.trim().is_empty(),
        "a non-empty name",
    );
    c.num(
        "end.time_s",
        f.end.time_s,
        true,
        0.0,
        MAX_END_S,
        "simulated seconds",
    );
    let site = &f.site;
    c.file_exists("site.map", &site.map, &loaded.map, "an .osm.pbf file");
    c.file_exists(
        "site.terrain",
        &site.terrain,
        &loaded.terrain,
        "a terrain grid",
    );
    if let Some(o) = site.offset {
        c.point("site.offset", o, "metres [east, north]");
    }
    fidelity(&mut c);
    if let (Some(given), Some(resolved)) = (&f.fidelity.calibration, &loaded.calibration) {
        c.file_exists(
            "fidelity.calibration",
            given,
            resolved,
            "a calibration file made by `vitro calibrate`",
        );
    }
    c.point("places.start", f.places.start, TOWN_XY);
    c.point("places.safehouse", f.places.safehouse, TOWN_XY);
    c.point("places.extraction", f.places.extraction, TOWN_XY);
    entities(&mut c);
    composition(&mut c);

    let m = &f.mission;
    c.num(
        "mission.pickup_s",
        m.pickup_s,
        false,
        0.0,
        MAX_END_S,
        "seconds",
    );
    c.num(
        "mission.hvt_appear_s",
        m.hvt_appear_s,
        false,
        0.0,
        MAX_END_S,
        "seconds",
    );
    let pursuers = m.hvt_pursuers;
    c.value(
        "mission.hvt_pursuers",
        pursuers,
        pursuers <= MAX_COUNT,
        "a number of troopers in 0..=100",
    );
    c.num(
        "mission.capture_range_m",
        m.capture_range_m,
        true,
        0.0,
        1e4,
        "metres",
    );
    c.num(
        "mission.attack_range_m",
        m.attack_range_m,
        true,
        0.0,
        1e4,
        "metres",
    );
    c.num(
        "mission.attack_aim_s",
        m.attack_aim_s,
        false,
        0.0,
        MAX_END_S,
        "seconds",
    );
    c.num(
        "mission.hit_probability",
        m.hit_probability,
        false,
        0.0,
        1.0,
        "a probability",
    );
    c.num(
        "mission.cover_radius_m",
        m.cover_radius_m,
        true,
        0.0,
        1e4,
        "metres",
    );

    c.num(
        "sensors.period_s",
        f.sensors.period_s,
        true,
        0.0,
        3600.0,
        "seconds",
    );
    c.num(
        "sensors.report_period_s",
        f.sensors.report_period_s,
        false,
        0.0,
        3600.0,
        "seconds",
    );
    c.num(
        "sensors.stale_s",
        f.sensors.stale_s,
        true,
        0.0,
        1e6,
        "seconds",
    );
    c.vision("sensors.ground", &f.sensors.ground);
    c.vision("sensors.air", &f.sensors.air);

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

    let p = &f.patrol;
    c.num("patrol.step_s", p.step_s, true, 0.0, MAX_END_S, "seconds");
    let steps = p.attack_steps;
    c.value(
        "patrol.attack_steps",
        steps,
        (1..=100).contains(&steps),
        "a number of steps in 1..=100",
    );
    let h = p.horizon;
    c.value(
        "patrol.horizon",
        h,
        (0..=100).contains(&h),
        "a number of steps in 0..=100",
    );
    let it = p.iterations;
    c.value(
        "patrol.iterations",
        it,
        (1..=1000).contains(&it),
        "a number of iterations in 1..=1000",
    );
    let a = p.attackers;
    c.value(
        "patrol.attackers",
        a,
        (0..=100).contains(&a),
        "a number of attackers in 0..=100",
    );
    c.num(
        "patrol.watch_range_m",
        p.watch_range_m,
        true,
        0.0,
        1e6,
        "metres",
    );

    let budget = f.pursuit.budget;
    let ok = (1..=10_000_000).contains(&budget);
    c.value(
        "pursuit.budget",
        budget,
        ok,
        "a number of iterations in 1..=10000000",
    );
    let h = f.pursuit.horizon;
    c.value(
        "pursuit.horizon",
        h,
        (1..=1000).contains(&h),
        "a number of turns in 1..=1000",
    );
    let think = f.pursuit.think_us_per_iteration;
    c.num(
        "pursuit.think_us_per_iteration",
        think,
        false,
        0.0,
        1e6,
        "microseconds",
    );

    if let Some(d) = f.repair.max_depth {
        c.value("repair.max_depth", d, d >= 1, "a depth of at least 1");
    }
    let rate = f.repair.failure_rate;
    c.num(
        "repair.failure_rate",
        rate,
        false,
        0.0,
        1.0,
        "a probability",
    );
    if let (Some(given), Some(resolved)) = (&f.formation.program, &loaded.program) {
        c.file_exists(
            "formation.program",
            given,
            resolved,
            "a formation rule file",
        );
        c.out.extend(program_problem(resolved));
    }
    c.num(
        "formation.spacing_m",
        f.formation.spacing_m,
        true,
        0.0,
        100.0,
        "metres",
    );
    c.num(
        "record.sample_s",
        f.record.sample_s,
        true,
        0.0,
        3600.0,
        "seconds",
    );
    for (key, w) in f.env.reward.weights() {
        let path = format!("env.reward.{key}");
        c.value(&path, w, w.is_finite(), "a finite reward weight");
    }
    c.out
}

/// Overrides must be levels their type has.
fn fidelity(c: &mut Checks<'_>) {
    let f = &c.file.fidelity;
    let keys = [
        EntityType::Truck,
        EntityType::Car,
        EntityType::Ugv,
        EntityType::Trooper,
        EntityType::Procerus,
        EntityType::Vidar,
        EntityType::Skeldar,
    ];
    for t in keys {
        if let Some(level) = f.override_of(t)
            && !t.levels().contains(&level)
        {
            let names: Vec<String> = t.levels().iter().map(|l| format!("`{l}`")).collect();
            let key = t.fidelity_key();
            let message = format!("unknown fidelity level `{level}` for `{key}`");
            let expected = format!("one of {}", names.join(", "));
            c.push(&format!("fidelity.{key}"), message, &expected);
        }
    }
}

/// Names, counts, starts and altitudes of each `[[entity]]`.
fn entities(c: &mut Checks<'_>) {
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    for (i, e) in c.file.entities.iter().enumerate() {
        let at = |k: &str| format!("entity.{i}.{k}");
        if e.name.trim().is_empty() {
            c.push(&at("name"), "empty entity name".into(), "a non-empty name");
        }
        let mut names = e.names();
        if e.count > 1 {
            names.insert(0, e.name.clone());
        }
        for name in names {
            if let Some(&first) = seen.get(&name) {
                let line = c.map.at(&format!("entity.{first}.name"), "", "").position;
                let line = line.map_or(String::new(), |(l, _)| format!(" (first at line {l})"));
                let message = format!("duplicate entity name `{name}`{line}");
                c.push(&at("name"), message, "a name used by one entity only");
                break;
            }
            seen.insert(name, i);
        }
        let count = e.count;
        let ok = (1..=MAX_COUNT).contains(&count);
        c.value(
            &at("count"),
            count,
            ok,
            &format!("a count in 1..={MAX_COUNT}"),
        );
        if let Some(p) = e.start {
            c.point(&at("start"), p, TOWN_XY);
        }
        let (lo, hi) = ALTITUDE_M;
        match (e.kind.is_aircraft(), e.altitude_m) {
            (true, None) => {
                let message = format!("entity `{}` is a {} without `altitude_m`", e.name, e.kind);
                let expected = format!("`altitude_m` for an aircraft, metres in [{lo}, {hi}]");
                c.push(&at("type"), message, &expected);
            }
            (true, Some(a)) => c.num(&at("altitude_m"), a, false, lo, hi, "metres"),
            (false, Some(_)) => {
                let message = format!("entity `{}` is a {} with `altitude_m`", e.name, e.kind);
                let expected =
                    "no `altitude_m` for a ground entity (only procerus, vidar, skeldar fly)";
                c.push(&at("altitude_m"), message, expected);
            }
            (false, None) => {}
        }
    }
}

/// What the mission needs: one blue truck, blue troopers, one blue VIP, at most one red HVT.
fn composition(c: &mut Checks<'_>) {
    let entities = &c.file.entities;
    let total = |pred: &dyn Fn(&super::EntitySpec) -> bool| -> u64 {
        entities
            .iter()
            .filter(|e| pred(e))
            .map(|e| u64::from(e.count))
            .sum()
    };
    // Where to point when something is missing: the first `[[entity]]`.
    let anchor = if entities.is_empty() {
        "entity"
    } else {
        "entity.0"
    };
    let exactly_one = |c: &mut Checks<'_>, t: EntityType, side: SideSpec, what: &str| {
        let n = total(&|e| e.kind == t);
        if n == 0 {
            let message = format!("the mission has no {what}");
            let expected = format!("exactly one `[[entity]]` with type = \"{t}\"");
            c.push(anchor, message, &expected);
        }
        extra(c, t, 1, what);
        sides(c, t, side);
    };
    exactly_one(c, EntityType::Truck, SideSpec::Blue, "truck");
    exactly_one(c, EntityType::Vip, SideSpec::Blue, "VIP");
    extra(c, EntityType::Hvt, 1, "HVT");
    sides(c, EntityType::Hvt, SideSpec::Red);
    let blue = total(&|e| e.kind == EntityType::Trooper && e.side == SideSpec::Blue);
    if blue == 0 {
        let expected = "at least one `[[entity]]` with type = \"trooper\" and side = \"blue\"";
        c.push(anchor, "the mission has no blue trooper".into(), expected);
    }
    let pursuers = c.file.mission.hvt_pursuers;
    let has_hvt = total(&|e| e.kind == EntityType::Hvt) > 0;
    if has_hvt && blue > 0 && u64::from(pursuers) > blue {
        let message = format!("{pursuers} HVT pursuers but only {blue} blue troopers");
        let expected = format!("at most {blue} pursuers");
        c.push("mission.hvt_pursuers", message, &expected);
    }
}

/// Reports every entity of type `t` beyond the first `max`.
fn extra(c: &mut Checks<'_>, t: EntityType, max: u64, what: &str) {
    let mut n = 0u64;
    for (i, e) in c.file.entities.iter().enumerate() {
        if e.kind != t {
            continue;
        }
        let before = n;
        n += u64::from(e.count);
        if n > max {
            let key = if before < max { "count" } else { "type" };
            let message = format!("more than {max} {what} (entity `{}`)", e.name);
            let expected = format!("at most {max} {what} in the mission");
            c.push(&format!("entity.{i}.{key}"), message, &expected);
            return;
        }
    }
}

/// Reports every entity of type `t` not on `side`.
fn sides(c: &mut Checks<'_>, t: EntityType, side: SideSpec) {
    let wrong: Vec<(usize, String, SideSpec)> = c
        .file
        .entities
        .iter()
        .enumerate()
        .filter(|(_, e)| e.kind == t && e.side != side)
        .map(|(i, e)| (i, e.name.clone(), e.side))
        .collect();
    let want = format!("{side:?}").to_lowercase();
    for (i, name, got) in wrong {
        let got = format!("{got:?}").to_lowercase();
        let message = format!("the {t} `{name}` is on side `{got}`");
        let expected = format!("side = \"{want}\" for the {t}");
        c.push(&format!("entity.{i}.side"), message, &expected);
    }
}

/// Every place and start of `file` that is outside the town or, for ground entities and the
/// places, in a building or forbidden zone.
pub(crate) fn check_site(file: &ScenarioFile, site: &Site, map: &SourceMap<'_>) -> Vec<Diagnostic> {
    let mut c = Checks {
        file,
        map,
        out: Vec::new(),
    };
    let places = &file.places;
    for (key, p) in [
        ("start", places.start),
        ("safehouse", places.safehouse),
        ("extraction", places.extraction),
    ] {
        place(&mut c, site, &format!("places.{key}"), p, true);
    }
    for (i, e) in file.entities.iter().enumerate() {
        if let Some(p) = e.start {
            place(
                &mut c,
                site,
                &format!("entity.{i}.start"),
                p,
                !e.kind.is_aircraft(),
            );
        }
    }
    c.out
}

/// Checks one point (town metres): in the town's extent and, when `on_ground`, free.
fn place(c: &mut Checks<'_>, site: &Site, path: &str, p: [f64; 2], on_ground: bool) {
    if !p.iter().all(|x| x.is_finite()) {
        return; // reported already
    }
    let [x0, y0, x1, y1] = site.map.extent;
    if !(x0..=x1).contains(&p[0]) || !(y0..=y1).contains(&p[1]) {
        let message = format!("{} {p:?} lies outside the town", c.label(path));
        let expected =
            format!("town metres with x in [{x0:.0}, {x1:.0}] and y in [{y0:.0}, {y1:.0}]");
        c.push(path, message, &expected);
        return;
    }
    if !on_ground {
        return;
    }
    if !site.zones.is_forbidden(p) {
        return;
    }
    let inside = site.map.buildings.iter().position(|b| {
        let [bx0, by0, bx1, by1] = b.footprint.bbox();
        (bx0..=bx1).contains(&p[0]) && (by0..=by1).contains(&p[1]) && b.footprint.contains(p)
    });
    let what = match inside {
        Some(b) => format!("inside building #{b}"),
        None => "in a forbidden zone (too close to a building or water)".to_owned(),
    };
    let free = site.zones.nearest_free(p);
    let message = format!("{} {p:?} lies {what}", c.label(path));
    let expected = format!(
        "a free point outside buildings and forbidden zones, e.g. [{:.1}, {:.1}]",
        free[0], free[1]
    );
    c.push(path, message, &expected);
}
