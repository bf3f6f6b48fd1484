//! The HVT hunt in the default mission: each player of the pursuit game (the hunt lead and
//! the HVT) takes one turn at a time, at most one per `MIN_TURN` (10 s), and the hunt
//! starts once the HVT is reported.

use vitro::time::SimTime;
use vitro_tactical::evac::Mission;
use vitro_tactical::scenario::Preset;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// The turn number an intention text states: "... turn N ...".
fn turn_in(text: &str) -> Option<u32> {
    let rest = &text[text.find("turn ")? + 5..];
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

#[test]
fn hunt_players_take_one_turn_at_a_time() {
    // Seed 2: the hunt starts early and lasts (no capture within the window).
    let mut m = Mission::at_fidelity(SCENARIO, Some(2), Preset::Discrete).expect("builds");
    m.end = SimTime::from_secs(1500);
    let mut last: Vec<Option<(u32, f64)>> = vec![None; 2];
    let mut turns = [0u32; 2];
    let mut t = SimTime::ZERO;
    while m.advance(t) {
        let now = m.sim.now().as_secs_f64();
        let f = m.frame();
        for i in &f.intentions {
            let who = if i.text.starts_with("evade") {
                0
            } else if i.text.starts_with("lead the HVT hunt") {
                1
            } else {
                continue;
            };
            let Some(n) = turn_in(&i.text) else { continue };
            if let Some((before, at)) = last[who]
                && n > before
            {
                // One new turn per look at most (looks are 1 s apart), and never two turns
                // within 10 s (thinking time aside).
                assert_eq!(n, before + 1, "{}: turns {before} -> {n} at {now}", i.text);
                assert!(
                    now - at >= 9.0,
                    "{}: turns {before} -> {n}, {at} -> {now}",
                    i.text
                );
            }
            if last[who].is_none_or(|(b, _)| n > b) {
                last[who] = Some((n, now));
            }
            turns[who] = n;
        }
        t += vitro::time::SimDuration::from_secs(1);
    }
    assert!(
        turns[0] >= 5 && turns[1] >= 3,
        "turns (HVT, lead): {turns:?}"
    );
    // Moves along the walk graph take about a minute: far fewer turns than seconds / 10.
    assert!(turns[0] < 60, "HVT turns {}", turns[0]);
}

#[test]
fn aircraft_join_the_hunt_once_the_convoy_is_done() {
    let mut m = Mission::at_fidelity(SCENARIO, Some(2), Preset::Discrete).expect("builds");
    m.end = SimTime::from_secs(1500);
    let support = "support the HVT hunt";
    let mut joined_at = None;
    let mut t = SimTime::ZERO;
    while m.advance(t) {
        let f = m.frame();
        let truck_out = f
            .intentions
            .iter()
            .any(|i| i.text.starts_with("at the extraction point"));
        for i in f.intentions.iter().filter(|i| i.text.starts_with(support)) {
            // Not before the truck is at the extraction point.
            assert!(truck_out, "{} at {:?} before the convoy is done", i.text, t);
            joined_at.get_or_insert(t);
            // An orbit of four points round a walk-graph node (the lead's search point).
            assert_eq!(i.path.len(), 4);
            let c = [
                i.path.iter().map(|p| p[0]).sum::<f64>() / 4.0,
                i.path.iter().map(|p| p[1]).sum::<f64>() / 4.0,
            ];
            let town = m.brief.site.to_town(c);
            let walk = m.brief.roads.of(vitro_tactical::map::Mode::Walk);
            let node = walk.nearest_connected(town).expect("a walk node");
            let at = walk.graph.node(node).expect("the node").pos;
            assert!(libm::hypot(at[0] - town[0], at[1] - town[1]) < 1.0, "{c:?}");
        }
        t += vitro::time::SimDuration::from_secs(5);
    }
    let aircraft = m
        .frame()
        .intentions
        .iter()
        .filter(|i| i.text.starts_with(support))
        .count();
    assert!(
        joined_at.is_some() && aircraft >= 3,
        "{aircraft} aircraft, from {joined_at:?}"
    );
}
