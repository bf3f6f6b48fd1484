//! The cross-level check on the real town, and its extension points.

use std::collections::BTreeSet;
use vitro_check::scenario::{Drive, trip};
use vitro_check::{CheckReport, Property, Registry, Run, Verdict, check_levels, property};
use vitro_site::map::Mode;
use vitro_site::site::Site;
use vitro_tactical::entity::Level;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::GroundKind;

fn rows_of<'a>(r: &'a CheckReport, entity: &str, level: Level) -> Vec<&'a str> {
    r.rows
        .iter()
        .filter(|x| x.entity == entity && x.level == level)
        .map(|x| x.property.as_str())
        .collect()
}

#[test]
fn every_property_holds_at_every_level_on_the_real_town() {
    let report = check_levels().unwrap();
    let failing: Vec<_> = report.rows.iter().filter(|r| !r.pass).collect();
    assert!(report.pass, "{failing:#?}\n{}", report.table());
    // Every entity at every level was run and arrived.
    let pairs: BTreeSet<(String, Level)> = report
        .rows
        .iter()
        .map(|r| (r.entity.clone(), r.level))
        .collect();
    assert_eq!(pairs.len(), 3 * 3 + 3 * 2 + 2 + 2 * 2);
    for (e, l) in &pairs {
        assert!(rows_of(&report, e, *l).contains(&"arrives"), "{e} {l}");
    }
    // Each property applies where it should.
    assert!(rows_of(&report, "cargo_truck", Level::Physical).contains(&"never forbidden"));
    assert!(rows_of(&report, "red_trooper", Level::Directed).contains(&"never forbidden"));
    assert!(rows_of(&report, "skeldar", Level::Dynamic).contains(&"holds altitude"));
    assert!(rows_of(&report, "procerus", Level::Kinematic).contains(&"above min speed"));
    assert!(!rows_of(&report, "car", Level::Discrete).contains(&"arrival near estimate"));
    assert!(rows_of(&report, "mdars", Level::Physical).contains(&"arrival near estimate"));
    // Speeds for each family's levels.
    assert_eq!(report.speeds.len(), 9);
    assert!(report.speeds.iter().all(|s| s.speed > 0.0 && s.runs > 0));
    let json = serde_json::to_string(&report).unwrap();
    assert!(json.contains("\"property\":\"holds altitude\""));
}

/// A user's property: arrival within a deadline.
struct Deadline(f64);

impl Property for Deadline {
    fn name(&self) -> &str {
        "deadline"
    }
    fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
        let t = run.arrival?;
        Some(Verdict {
            pass: t <= self.0,
            value: t,
            limit: format!("<= {} s", self.0),
        })
    }
}

#[test]
fn users_add_scenarios_and_properties() {
    let setup = Setup::default_town().unwrap();
    let (a, b) = trip(&setup, Mode::Drive).unwrap();
    let mut reg = Registry::new();
    // The truck's trip back, checked against the standard properties and a deadline that
    // only the discrete level meets.
    reg.add_scenario(Box::new(Drive {
        kind: GroundKind::CargoTruck,
        from: b,
        to: a,
    }));
    for p in property::standard() {
        reg.add_property(p);
    }
    let d = reg.run(&setup).unwrap();
    let t_discrete = d
        .rows
        .iter()
        .find(|r| r.level == Level::Discrete && r.property == "arrives")
        .map(|r| r.value)
        .unwrap();
    assert!(d.pass, "{}", d.table());
    reg.add_property(Box::new(Deadline(t_discrete + 0.5)));
    let r = reg.run(&setup).unwrap();
    assert!(!r.pass);
    let deadline: Vec<(Level, bool)> = r
        .rows
        .iter()
        .filter(|x| x.property == "deadline")
        .map(|x| (x.level, x.pass))
        .collect();
    assert_eq!(
        deadline,
        [
            (Level::Discrete, true),
            (Level::Interpolated, false),
            (Level::Physical, false)
        ]
    );
    assert!(r.table().contains("SOME PROPERTIES FAIL"));
}
