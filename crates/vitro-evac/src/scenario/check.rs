//! The semantic checks of a parsed scenario: ranges, files, fidelity levels, entities, the
//! mission's needs ([`check_file`]), and places against the site ([`check_site`]).
//!
//! Every check adds its problem and goes on, so one pass reports them all.

use super::ScenarioFile;
use super::loaded::Loaded;
use std::path::Path;
use vitro_behaviour::formation::Leader;
use vitro_site::site::Site;
use vitro_tactical::scenario::checker::{Checker, TOWN_XY};
use vitro_tactical::scenario::{
    Diagnostic, EntitySpec, EntityType, MAX_COUNT, MAX_END_S, SideSpec, SourceMap,
};

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
    let mut c = Checker::new(map, &f.entities);
    c.value(
        "name",
        format!("{:?}", f.name),
        !f.name.trim().is_empty(),
        "a non-empty name",
    );
    c.end(&f.end);
    c.site(&f.site, &loaded.site_files());
    c.fidelity(&f.fidelity);
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
    c.entities();
    composition(&mut c, f);

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

    c.channel(&f.channel);

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
        c.extend(program_problem(resolved));
    }
    c.num(
        "formation.spacing_m",
        f.formation.spacing_m,
        true,
        0.0,
        100.0,
        "metres",
    );
    c.record(&f.record);
    for (key, w) in f.env.reward.weights() {
        let path = format!("env.reward.{key}");
        c.value(&path, w, w.is_finite(), "a finite reward weight");
    }
    c.finish()
}

/// What the mission needs: one blue truck, blue troopers, one blue VIP, at most one red HVT.
fn composition(c: &mut Checker<'_>, f: &ScenarioFile) {
    let entities = &f.entities;
    let total = |pred: &dyn Fn(&EntitySpec) -> bool| -> u64 {
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
    let exactly_one = |c: &mut Checker<'_>, t: EntityType, side: SideSpec, what: &str| {
        let n = total(&|e| e.kind == t);
        if n == 0 {
            let message = format!("the mission has no {what}");
            let expected = format!("exactly one `[[entity]]` with type = \"{t}\"");
            c.push(anchor, message, &expected);
        }
        extra(c, entities, t, 1, what);
        sides(c, entities, t, side);
    };
    exactly_one(c, EntityType::Truck, SideSpec::Blue, "truck");
    exactly_one(c, EntityType::Vip, SideSpec::Blue, "VIP");
    extra(c, entities, EntityType::Hvt, 1, "HVT");
    sides(c, entities, EntityType::Hvt, SideSpec::Red);
    let blue = total(&|e| e.kind == EntityType::Trooper && e.side == SideSpec::Blue);
    if blue == 0 {
        let expected = "at least one `[[entity]]` with type = \"trooper\" and side = \"blue\"";
        c.push(anchor, "the mission has no blue trooper".into(), expected);
    }
    let pursuers = f.mission.hvt_pursuers;
    let has_hvt = total(&|e| e.kind == EntityType::Hvt) > 0;
    if has_hvt && blue > 0 && u64::from(pursuers) > blue {
        let message = format!("{pursuers} HVT pursuers but only {blue} blue troopers");
        let expected = format!("at most {blue} pursuers");
        c.push("mission.hvt_pursuers", message, &expected);
    }
}

/// Reports every entity of type `t` beyond the first `max`.
fn extra(c: &mut Checker<'_>, entities: &[EntitySpec], t: EntityType, max: u64, what: &str) {
    let mut n = 0u64;
    for (i, e) in entities.iter().enumerate() {
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
fn sides(c: &mut Checker<'_>, entities: &[EntitySpec], t: EntityType, side: SideSpec) {
    let wrong: Vec<(usize, String, SideSpec)> = entities
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
    let mut c = Checker::new(map, &file.entities);
    let places = &file.places;
    for (key, p) in [
        ("start", places.start),
        ("safehouse", places.safehouse),
        ("extraction", places.extraction),
    ] {
        c.place(site, &format!("places.{key}"), p, true);
    }
    c.starts(site);
    c.finish()
}
