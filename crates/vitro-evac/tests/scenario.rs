//! Scenario files of the evacuation mission: the default scenario, defaults and presets,
//! and the problems validation reports (every one, each at its place).

// Measurements of the outcome (distances, angles, fits), not model code: platform math is
// allowed here (clippy.toml bans it where it could change a trace hash).
#![allow(clippy::disallowed_methods)]

use std::path::{Path, PathBuf};
use vitro_evac::scenario::{RepairStrategy, ScenarioFile};
use vitro_site::geo::dist;
use vitro_site::map::{MapConfig, TownMap};
use vitro_tactical::entity::Level;
use vitro_tactical::scenario::{Diagnostics, EntityType, Preset, SideSpec};
use vitro_tactical::world::Side;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn map_path() -> PathBuf {
    repo().join("data/maps/kotka.osm.pbf")
}

/// Writes `text` to a fresh file under the test's temporary directory.
fn write(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("scenario-tests");
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write the scenario");
    path
}

/// A small valid mission (absolute site paths) followed by `extra`.
fn minimal(extra: &str) -> String {
    let map = map_path();
    let terrain = repo().join("data/terrain/valley_64x64_90m.asc");
    format!(
        r#"name = "small"
seed = 1
end = {{ time_s = 600 }}
site = {{ map = "{}", terrain = "{}" }}
places = {{ start = [-579.4, -783.8], safehouse = [98.1, 11.1], extraction = [717.2, 844.6] }}

[[entity]]
name = "truck"
type = "truck"
side = "blue"

[[entity]]
name = "blue"
type = "trooper"
side = "blue"
count = 2

[[entity]]
name = "vip"
type = "vip"
side = "blue"
{extra}"#,
        map.display(),
        terrain.display()
    )
}

/// The `line:column` of every problem.
fn places(d: &Diagnostics) -> Vec<String> {
    d.0.iter()
        .map(|d| {
            let (l, c) = d.position.expect("a place");
            format!("{l}:{c}")
        })
        .collect()
}

#[test]
fn the_default_scenario_validates_with_every_entity_type() {
    let path = repo().join("scenarios/evacuation.toml");
    let v = ScenarioFile::validate(&path).unwrap_or_else(|d| panic!("{}", d.render()));
    let f = &v.loaded.file;
    assert!(v.loaded.map.is_absolute() && v.loaded.map.ends_with("data/maps/kotka.osm.pbf"));
    assert!(
        v.loaded
            .terrain
            .ends_with("data/terrain/valley_64x64_90m.asc")
    );
    for t in EntityType::ALL {
        assert!(f.entities.iter().any(|e| e.kind == t), "no {t}");
    }
    let count = |t: EntityType, side: SideSpec| -> u32 {
        f.entities
            .iter()
            .filter(|e| e.kind == t && e.side == side)
            .map(|e| e.count)
            .sum()
    };
    assert_eq!(count(EntityType::Truck, SideSpec::Blue), 1);
    assert_eq!(count(EntityType::Trooper, SideSpec::Blue), 4);
    assert_eq!(count(EntityType::Vip, SideSpec::Blue), 1);
    assert_eq!(count(EntityType::Hvt, SideSpec::Red), 1);
    assert_eq!(count(EntityType::Trooper, SideSpec::Red), 6);
    assert_eq!(count(EntityType::Ugv, SideSpec::Blue), 1);
    assert_eq!(count(EntityType::Vidar, SideSpec::Blue), 2);
    assert_eq!(count(EntityType::Car, SideSpec::Neutral), 2);
    let red = f.entities.iter().find(|e| e.name == "red").expect("red");
    assert_eq!(red.start, None, "red troopers are placed by the mission");
    // The legs are 1 to 2 km, and every place is a junction of the drive graph.
    let p = &f.places;
    for (a, b) in [(p.start, p.safehouse), (p.safehouse, p.extraction)] {
        let d = dist(a, b);
        assert!((1000.0..=2000.0).contains(&d), "{a:?} to {b:?}: {d} m");
    }
    let drive = &v.site.map.drive;
    for q in [p.start, p.safehouse, p.extraction] {
        let n = drive.nearest_node(q).expect("a junction");
        let at = drive.pos(n).expect("its position");
        assert!(
            dist(q, at) < 0.1,
            "{q:?} is {} m from a junction",
            dist(q, at)
        );
    }
}

#[test]
fn presets_then_overrides_give_each_type_its_level() {
    use EntityType::*;
    use Level::*;
    let f: ScenarioFile = toml::from_str(&minimal("")).expect("parses");
    assert_eq!(f.fidelity.level, Preset::Discrete);
    for t in EntityType::ALL {
        assert_eq!(f.fidelity.level_of(t), Discrete, "{t}");
    }
    let table = [
        (
            Preset::Interpolated,
            [
                Interpolated,
                Interpolated,
                Interpolated,
                Directed,
                Directed,
                Directed,
                Kinematic,
                Discrete,
                Discrete,
            ],
        ),
        (
            Preset::Physical,
            [
                Physical, Physical, Physical, Directed, Directed, Directed, Kinematic, Dynamic,
                Dynamic,
            ],
        ),
    ];
    for (preset, levels) in table {
        let mut fidelity = f.fidelity.clone();
        fidelity.level = preset;
        for (t, want) in [Truck, Car, Ugv, Trooper, Vip, Hvt, Procerus, Vidar, Skeldar]
            .into_iter()
            .zip(levels)
        {
            assert_eq!(fidelity.level_of(t), want, "{preset:?} {t}");
            assert!(t.levels().contains(&want));
        }
    }
    let text =
        minimal("[fidelity]\nlevel = \"physical\"\ntrooper = \"discrete\"\nvidar = \"discrete\"\n");
    let f: ScenarioFile = toml::from_str(&text).expect("parses");
    assert_eq!(
        f.fidelity.level_of(Vip),
        Discrete,
        "the trooper key sets the VIP"
    );
    assert_eq!(f.fidelity.level_of(Vidar), Discrete);
    assert_eq!(f.fidelity.level_of(Skeldar), Dynamic);
    assert_eq!(f.fidelity.level_of(Truck), Physical);
}

#[test]
fn partial_tables_keep_the_other_defaults() {
    let text = minimal(
        "[channel]\nloss = 0.2\n\n[sensors.air]\nrange_m = 900\nfov_deg = 360\np0 = 1\nfalloff = 0\nmisidentification = 0\n",
    );
    let f: ScenarioFile = toml::from_str(&text).expect("parses");
    assert_eq!(f.channel.loss, 0.2);
    assert_eq!(
        (f.channel.delay_ms, f.channel.jitter_ms, f.channel.range_m),
        (20.0, 30.0, 3000.0)
    );
    assert_eq!(f.sensors.air.range_m, 900.0);
    assert_eq!(
        (
            f.sensors.period_s,
            f.sensors.ground.range_m,
            f.sensors.ground.fov_deg
        ),
        (1.0, 300.0, 120.0)
    );
    let m = &f.mission;
    assert_eq!(
        [
            m.pickup_s,
            m.hvt_appear_s,
            m.capture_range_m,
            m.attack_range_m,
            m.attack_aim_s,
            m.hit_probability,
            m.cover_radius_m
        ],
        [30.0, 600.0, 15.0, 150.0, 15.0, 0.3, 200.0]
    );
    assert_eq!(m.hvt_pursuers, 2);
    assert_eq!(
        (
            f.patrol.step_s,
            f.patrol.attack_steps,
            f.patrol.horizon,
            f.patrol.iterations
        ),
        (20.0, 3, 2, 5)
    );
    assert_eq!(
        (f.pursuit.budget, f.pursuit.think_us_per_iteration),
        (500, 20.0)
    );
    assert_eq!(f.repair.strategy, RepairStrategy::RepeatedLazy);
    assert_eq!(
        (f.formation.program.clone(), f.formation.spacing_m),
        (None, 5.0)
    );
    assert_eq!(f.record.sample_s, 1.0);
    assert_eq!(f.entities[1].count, 2);
    assert_eq!(f.entities[0].count, 1, "count defaults to 1");
    assert_eq!(f.entities[1].names(), ["blue-1", "blue-2"]);
    assert_eq!(f.entities[0].side.side(), Side::Blue);
    let air = f.sensors.air.vision();
    assert!((air.half_fov - std::f64::consts::PI).abs() < 1e-12);
}

#[test]
fn levels_are_lower_case_in_files() {
    #[derive(serde::Deserialize, serde::Serialize)]
    struct L {
        level: Level,
    }
    let l: L = toml::from_str("level = \"kinematic\"").expect("lower case");
    assert_eq!(l.level, Level::Kinematic);
    assert!(toml::from_str::<L>("level = \"Kinematic\"").is_err());
    assert_eq!(
        toml::to_string(&l).expect("serializes").trim(),
        "level = \"kinematic\""
    );
}

#[test]
fn every_problem_is_reported_at_its_place() {
    let text = minimal(
        "altitude_m = 50\n\n[[entity]]\nname = \"vidar\"\ntype = \"vidar\"\nside = \"blue\"\n\n\
         [[entity]]\nname = \"blue\"\ntype = \"car\"\nside = \"neutral\"\n\n\
         [channel]\nloss = 1.5\njitter_ms = -1\n\n[fidelity]\nprocerus = \"dynamic\"\n",
    );
    let path = write("many.toml", &text);
    let d = ScenarioFile::load(&path).expect_err("six problems");
    assert_eq!(
        places(&d),
        ["22:14", "26:8", "30:8", "35:8", "36:13", "39:12"],
        "{d}"
    );
    let lines: Vec<String> = d.to_string().lines().map(String::from).collect();
    let file = path.display().to_string();
    assert_eq!(
        lines[0],
        format!(
            "{file}:22:14: entity `vip` is a vip with `altitude_m` (expected no `altitude_m` for a ground entity (only procerus, vidar, skeldar fly))"
        )
    );
    assert!(
        lines[1].contains("entity `vidar` is a vidar without `altitude_m`"),
        "{}",
        lines[1]
    );
    assert!(
        lines[2].starts_with(&format!("{file}:30:8: duplicate entity name `blue`")),
        "{}",
        lines[2]
    );
    assert!(
        lines[3]
            .ends_with("invalid value 1.5 for `channel.loss` (expected a probability in [0, 1])")
    );
    assert!(lines[4].ends_with(
        "invalid value -1 for `channel.jitter_ms` (expected milliseconds in [0, 1000000])"
    ));
    assert!(lines[5].ends_with(
        "unknown fidelity level `dynamic` for `procerus` (expected one of `discrete`, `kinematic`)"
    ));
    // The rendered form shows the line under the message.
    assert!(
        d.render().contains("35 | loss = 1.5\n   |        ^^^"),
        "{}",
        d.render()
    );
}

#[test]
fn type_errors_in_several_tables_are_all_reported() {
    let text = minimal("colour = \"red\"\n\n[mission]\npickup = 3\n\n[channel]\nloss = \"high\"\n");
    let path = write("types.toml", &text);
    let d = ScenarioFile::load(&path).expect_err("three problems");
    // `colour` lands in the last [[entity]]: an unknown field of the entity.
    assert_eq!(places(&d), ["22:1", "25:1", "28:8"], "{d}");
    assert!(d.0[0].message.contains("unknown field `colour`"));
    assert!(
        d.0[1]
            .expected
            .as_deref()
            .is_some_and(|e| e.contains("`pickup_s`"))
    );
    assert_eq!(d.0[2].message, "invalid type: string \"high\"");
    assert_eq!(d.0[2].expected.as_deref(), Some("a number"));
}

#[test]
fn places_and_starts_are_checked_against_the_site() {
    let town = TownMap::load(map_path(), &MapConfig::default()).expect("the town");
    let inside = town
        .buildings
        .iter()
        .map(|b| b.footprint.centroid())
        .zip(&town.buildings)
        .find(|(c, b)| b.footprint.contains(*c) && b.footprint.area() > 200.0)
        .map(|(c, _)| c)
        .expect("a building with its centroid inside");
    let extra = format!(
        "start = [{}, {}]\n\n[[entity]]\nname = \"uav\"\ntype = \"procerus\"\nside = \"blue\"\n\
         altitude_m = 100\nstart = [{}, {}]\n",
        inside[0], inside[1], inside[0], inside[1]
    );
    let text = minimal(&extra).replace(
        "extraction = [717.2, 844.6]",
        "extraction = [717.2, 5000, 3]",
    );
    let path = write("site.toml", &text);
    assert!(
        ScenarioFile::load(&path).is_err(),
        "the 3-number point is found without the site"
    );
    let d = ScenarioFile::validate(&path).expect_err("three problems");
    assert_eq!(places(&d), ["5:77", "5:77", "22:9"], "{}", d.render());
    assert_eq!(d.0[0].message, "3 numbers for `places.extraction`");
    assert!(
        d.to_string()
            .contains("`places.extraction` [717.2, 5000.0] lies outside the town"),
        "{d}"
    );
    assert!(
        d.0[2].message.contains("`start` of entity `vip`"),
        "{}",
        d.0[2].message
    );
    assert!(
        d.0[2].message.contains("lies inside building #"),
        "{}",
        d.0[2].message
    );
    assert!(
        d.0[2]
            .expected
            .as_deref()
            .is_some_and(|e| e.contains("e.g. ["))
    );
    // The aircraft above the same building is fine.
    assert!(!d.to_string().contains("entity `uav`"));
}

#[test]
fn missing_files_and_unreadable_scenarios() {
    let text = minimal("").replace("kotka.osm.pbf", "nowhere.osm.pbf");
    let path = write("missing.toml", &text);
    let d = ScenarioFile::validate(&path).expect_err("no map");
    assert_eq!(places(&d), ["4:16"]);
    assert!(
        d.0[0]
            .message
            .contains("nowhere.osm.pbf` not found for `site.map`")
    );
    let none = Path::new("/nonexistent/scenario.toml");
    let d = ScenarioFile::load(none).expect_err("no file");
    assert_eq!(d.0[0].position, None);
    assert!(
        d.to_string()
            .starts_with("/nonexistent/scenario.toml: cannot read the scenario")
    );
}

#[test]
fn the_mission_needs_its_team() {
    let text = minimal("count = 2\n\n[[entity]]\nname = \"h\"\ntype = \"hvt\"\nside = \"blue\"\n")
        .replace("type = \"truck\"", "type = \"car\"")
        .replace(
            "type = \"trooper\"\nside = \"blue\"",
            "type = \"trooper\"\nside = \"red\"",
        );
    let path = write("team.toml", &text);
    let d = ScenarioFile::load(&path).expect_err("no truck, no blue trooper, two VIPs");
    let text = d.to_string();
    assert!(text.contains(":7:1: the mission has no truck"), "{text}");
    assert!(
        text.contains(":7:1: the mission has no blue trooper"),
        "{text}"
    );
    assert!(
        text.contains(":22:9: more than 1 VIP (entity `vip`)"),
        "{text}"
    );
    assert!(
        text.contains(":27:8: the hvt `h` is on side `blue` (expected side = \"red\" for the hvt)"),
        "{text}"
    );
    assert_eq!(d.len(), 4, "{text}");
}

/// A file that is not a scenario (here thousands of broken lines) gets the first
/// `MAX_PROBLEMS` problems and a count of the rest, not one line per problem.
#[test]
fn a_file_with_thousands_of_problems_reports_the_first_hundred() {
    use vitro_evac::scenario::ScenarioFile;
    use vitro_tactical::scenario::MAX_PROBLEMS;
    let text = "name = \"x\"\n".to_owned() + &"key = = 1\n".repeat(5000);
    let e = ScenarioFile::validate_text("/nonexistent/many.toml", &text).unwrap_err();
    assert_eq!(e.0.len(), MAX_PROBLEMS + 1, "{}", e.report());
    let more =
        e.0.iter()
            .find(|d| d.position.is_none())
            .expect("a count of the rest");
    let n: usize = more.message.split(' ').next().unwrap().parse().unwrap();
    assert!(n >= 4900, "{}", more.message);
    assert!(
        more.message
            .ends_with("more problems not shown (the first 100 found are)")
    );
}
