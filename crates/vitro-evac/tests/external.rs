//! Units driven from outside (`vitro_evac::external`): commands move them, they know only
//! what their sensors and the radio say, a run without them is the ordinary run, and a bad
//! unit name is refused.

use vitro::time::SimTime;
use vitro_evac::external::{Command, lock, targets};
use vitro_evac::scenario::ScenarioFile;
use vitro_evac::{Mission, MissionError};

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

#[test]
fn no_external_unit_is_the_ordinary_run() {
    let until = SimTime::from_secs(120);
    let v = ScenarioFile::validate(SCENARIO).unwrap();
    let (mut none, _) = Mission::build_external(v, Some(5), &[]).unwrap();
    none.end = until;
    none.run();
    let mut plain = Mission::from_file(SCENARIO, Some(5)).unwrap();
    plain.end = until;
    plain.run();
    assert_eq!(none.sim.trace_hash(), plain.sim.trace_hash());
}

#[test]
fn a_commanded_ugv_drives_to_its_target_and_hears_the_radio() {
    let v = ScenarioFile::validate(SCENARIO).unwrap();
    assert_eq!(
        Mission::controllable(&v),
        ["mdars", "vidar-1", "vidar-2", "skeldar"]
    );
    let units = vec!["mdars".to_string()];
    let (mut m, desk) = Mission::build_external(v, Some(5), &units).unwrap();
    let id = m.members.iter().find(|x| x.name == "mdars").unwrap().id;
    let goal = targets(&m.brief)[3];
    let goal_at = m
        .brief
        .node_point(vitro_site::map::Mode::Drive, goal)
        .unwrap();
    m.advance(SimTime::from_secs(2));
    let start = lock(&desk).units[&id].knowledge.pos.unwrap();
    lock(&desk).units.get_mut(&id).unwrap().pending = Some(Command::GoTo(3));
    let mut t = 2;
    while t < 900 && !lock(&desk).units[&id].knowledge.arrived {
        t += 1;
        m.advance(SimTime::from_secs(t));
    }
    let k = lock(&desk).units[&id].knowledge.clone();
    assert!(k.arrived, "arrived by {t} s");
    assert_eq!(k.goal, Some(3));
    let pos = k.pos.unwrap();
    let d = |a: [f64; 3], b: [f64; 3]| libm::hypot(a[0] - b[0], a[1] - b[1]);
    assert!(
        d(pos, goal_at) < 30.0,
        "at the target: {pos:?} vs {goal_at:?}"
    );
    assert!(d(pos, start) > 100.0, "it moved from {start:?}");
    assert!(
        !k.heard.is_empty(),
        "the team's contact reports reach it by radio"
    );
}

#[test]
fn a_unit_that_cannot_be_driven_is_refused() {
    let v = ScenarioFile::validate(SCENARIO).unwrap();
    let e = Mission::build_external(v, None, &["truck".to_string()])
        .map(|_| ())
        .unwrap_err();
    assert!(
        matches!(&e, MissionError::Setup(m) if m.contains("\"truck\" cannot be driven from outside")),
        "{e}"
    );
}
