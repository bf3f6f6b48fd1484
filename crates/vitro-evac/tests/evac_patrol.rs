//! The Skeldar's patrol in the evacuation mission: the patrol game is made and solved for
//! the default scenario, the Skeldar moves only along the game's edges, one step at a time,
//! and its patrol is reproducible and changes with the seed; the game's attacker strikes once
//! and the umpire judges it.

use vitro::time::{SimDuration, SimTime};
use vitro_evac::Mission;
use vitro_evac::agents::air::Aircraft;
use vitro_evac::agents::patrol::PatrolUnit;
use vitro_tactical::scenario::{Preset, ScenarioFile};

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// The patrol units of the mission's Skeldars, in id order.
fn units(m: &Mission) -> Vec<PatrolUnit> {
    m.members
        .iter()
        .filter_map(|mem| {
            let a = m.sim.agent(mem.id)?.as_any().downcast_ref::<Aircraft>()?;
            a.patrol.clone()
        })
        .collect()
}

/// The Skeldar's (phase, vertex) after every patrol step until `until` seconds.
fn trace(seed: Option<u64>, until: u64) -> Vec<(usize, usize)> {
    let mut m = Mission::at_fidelity(SCENARIO, seed, Preset::Discrete).expect("builds");
    let step = SimDuration::from_secs_f64(m.brief.patrol.step_s);
    let mut out = Vec::new();
    let mut t = SimTime::from_secs_f64(m.brief.patrol.step_s / 2.0);
    while t < SimTime::from_secs(until) && m.advance(t) {
        let u = &units(&m)[0];
        if let Some(v) = u.at {
            out.push((u.phase, v));
        }
        t += step;
    }
    out
}

#[test]
fn the_default_scenario_has_a_solved_patrol_game() {
    let m = Mission::at_fidelity(SCENARIO, None, Preset::Discrete).expect("builds");
    let units = units(&m);
    assert_eq!(units.len(), 1, "one Skeldar, one patrol unit");
    let game = &units[0].game;
    let plan = &game.plan;
    assert_eq!(plan.units(), 1);
    assert!(
        plan.graph.node_count() >= 10,
        "{} checkpoints",
        plan.graph.node_count()
    );
    assert!(game.timetable.len() > 5 && plan.period >= game.timetable.len());
    assert!(game.timetable.windows(2).all(|w| w[0] <= w[1]));
    let p = game.trip_capture_probability;
    assert!(p > 0.0 && p <= 1.0, "capture probability {p}");
    assert!(plan.capture_probability <= p + 1e-9);
    for phase in 0..plan.period {
        assert!(!plan.vertices_at(0, phase).unwrap().is_empty());
        let heat: f64 = game.heat(0, phase).iter().map(|h| h.1).sum();
        assert!(
            (heat - 1.0).abs() < 1e-6,
            "phase {phase}: heat sums to {heat}"
        );
    }
    eprintln!(
        "patrol game: {} checkpoints, {} edges, period {} ({} trip steps), capture probability {:.3} (trip), {:.3} (all)",
        plan.graph.node_count(),
        plan.graph.edge_count(),
        plan.period,
        game.timetable.len(),
        p,
        plan.capture_probability
    );
}

#[test]
fn the_skeldar_flies_the_game_one_edge_a_step() {
    let steps = trace(None, 600);
    assert!(steps.len() > 20);
    let m = Mission::at_fidelity(SCENARIO, None, Preset::Discrete).expect("builds");
    let game = units(&m)[0].game.clone();
    let g = &game.plan.graph;
    for w in steps.windows(2) {
        let ((_, a), (_, b)) = (w[0], w[1]);
        assert!(a == b || g.has_edge(a, b), "{a} -> {b} is not an edge");
        assert!(w[0].0 <= w[1].0, "the phase went back: {w:?}");
    }
    // It follows the truck to the end of the trip.
    assert_eq!(
        steps.last().map(|s| s.0),
        Some(game.last_phase()),
        "{steps:?}"
    );
    eprintln!("trace: {steps:?}");
}

#[test]
fn the_patrol_is_reproducible_and_changes_with_the_seed() {
    let a = trace(Some(5), 400);
    assert_eq!(a, trace(Some(5), 400));
    let others: Vec<_> = (6..9).map(|s| trace(Some(s), 400)).collect();
    assert!(
        others.iter().any(|b| *b != a),
        "three other seeds flew the same patrol"
    );
}

#[test]
fn two_skeldars_fly_one_plan_each() {
    let text = std::fs::read_to_string(SCENARIO).expect("the default scenario");
    let two = text.replacen(
        "type = \"skeldar\"              # helicopter UAV: patrols the convoy",
        "type = \"skeldar\"\ncount = 2",
        1,
    );
    assert_ne!(two, text, "the Skeldar entity of the default scenario");
    let v = ScenarioFile::validate_text(SCENARIO, &two).expect("valid");
    let mut m = Mission::build(v, None).expect("builds");
    let us = units(&m);
    assert_eq!(us.iter().map(|u| u.unit).collect::<Vec<_>>(), [0, 1]);
    assert_eq!(us[0].game.plan.units(), 2);
    m.end = SimTime::from_secs(300);
    m.run();
    let us = units(&m);
    assert!(us.iter().all(|u| u.at.is_some() && u.phase > 5), "{us:?}");
    let p = m.metrics().patrol_capture_probability.expect("reported");
    assert!(p >= us[0].game.trip_capture_probability - 1e-12);
}

#[test]
fn the_games_attacker_strikes_once_and_the_umpire_judges_it() {
    let mut m = Mission::at_fidelity(SCENARIO, Some(3), Preset::Discrete).expect("builds");
    m.end = SimTime::from_secs(900);
    m.run();
    let x = m.metrics();
    // One attacker (patrol.attackers = 1), who sees the whole town: one attack.
    assert_eq!(x.patrol_attacks, 1, "{x:?}");
    assert!(x.patrol_attacks_stopped <= x.patrol_attacks);
    assert!(x.patrol_attacks_on_schedule <= x.patrol_attacks);
    assert!(x.patrol_stopped_on_schedule <= x.patrol_attacks_stopped);
    assert!(x.patrol_stopped_on_schedule <= x.patrol_attacks_on_schedule);
    assert!(x.patrol_attacks_misread + x.patrol_attacks_on_schedule <= x.patrol_attacks);
    let p = x
        .patrol_capture_computed
        .expect("an attack, a computed probability");
    // No attack beats the game's least capture probability over the trip.
    let least = x.patrol_capture_probability.expect("a patrol game");
    assert!(
        (least - 1e-9..=1.0).contains(&p),
        "computed {p}, least {least}"
    );
    // Without attackers: no attack, no computed probability.
    let text = std::fs::read_to_string(SCENARIO).expect("the default scenario");
    let none = text.replacen("attackers = 1 ", "attackers = 0 ", 1);
    assert_ne!(none, text);
    let v = ScenarioFile::validate_text(SCENARIO, &none).expect("valid");
    let mut m = Mission::build(v, Some(3)).expect("builds");
    m.end = SimTime::from_secs(300);
    m.run();
    let x = m.metrics();
    assert_eq!((x.patrol_attacks, x.patrol_capture_computed), (0, None));
}
