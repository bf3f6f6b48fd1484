//! The HVT hunt in the default mission: each player of the pursuit game (the hunt lead and
//! the HVT) takes one turn at a time, at most one per `MIN_TURN` (10 s), and the hunt
//! starts once the HVT is reported; once the VIP is out the whole escort joins it, and a
//! lead that falls silent is replaced.

mod common;

use common::{commander, trooper};
use vitro::entity::EntityId;
use vitro::time::{SimDuration, SimTime};
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_evac::agents::commander::Phase;
use vitro_evac::agents::trooper::Task;
use vitro_evac::scenario::{PursuitLead, ScenarioFile};
use vitro_tactical::condition::Status;
use vitro_tactical::scenario::{FidelitySpec, Preset};

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
                // The lead plays the default search (`lead = "determinized"`, `algorithm = "mcts"`).
                assert!(i.text.contains("(MCTS, turn "), "{}", i.text);
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
            let walk = m.brief.roads.of(vitro_site::map::Mode::Walk);
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

fn status(m: &EvacRun, id: EntityId) -> Option<Status> {
    m.sim.env().conditions.get(id).map(|c| c.status)
}

/// The lead's turn count, if `id` leads a hunt.
fn turns_led(m: &EvacRun, id: EntityId) -> Option<u32> {
    trooper(m, id).hunt.as_ref().map(|h| h.turns)
}

#[test]
fn the_escort_joins_the_hunt_once_the_vip_is_out() {
    // Seed 2: the hunt starts early and outlasts the escort.
    let mut m = Mission::at_fidelity(SCENARIO, Some(2), Preset::Discrete).expect("builds");
    m.end = SimTime::from_secs(1500);
    let k = m.brief.mission.hvt_pursuers as usize;
    let mut before = None;
    let mut t = SimTime::ZERO;
    loop {
        t += SimDuration::from_secs(1);
        assert!(m.advance(t), "the run ended before the VIP was out");
        let c = commander(&m);
        if c.phase == Phase::Done {
            break;
        }
        assert!(
            c.hunters.len() <= k,
            "{:?} before the VIP is out",
            c.hunters
        );
        if let Some(&lead) = c.hunters.first() {
            before = turns_led(&m, lead).or(before);
        }
    }
    let before = before.expect("a hunt was on before the VIP was out");
    assert_eq!(status(&m, m.brief.vip), Some(Status::Extracted));
    // A slot whose call found nobody (lost messages) is called again after RECALL_S.
    m.advance(t + SimDuration::from_secs(60 + vitro_evac::agents::tender::RECALL_S as u64));
    let c = commander(&m);
    // Up: on its feet (the umpire's view). A trooper down where nobody saw it makes no bid
    // for a hunt slot (contract net), so it is not sent.
    let up: Vec<EntityId> = (m.brief.team.iter().copied())
        .filter(|&id| status(&m, id) == Some(Status::Active))
        .collect();
    assert!(up.len() > k, "{up:?}");
    assert_eq!(c.hunters.len(), up.len(), "{:?} hunt, {up:?} up", c.hunters);
    for &id in &up {
        assert!(c.hunters.contains(&id));
        assert_eq!(status(&m, id), Some(Status::Active), "{id:?} off the truck");
        assert!(
            matches!(trooper(&m, id).task, Task::Hunt(_)),
            "{id:?} hunts"
        );
    }
    // The same lead, its belief and turn count kept (a new hunt would restart at turn 0).
    let after = turns_led(&m, c.hunters[0]).expect("the lead still leads");
    assert!(after >= before, "turns {before} -> {after}");
}

#[test]
fn a_silent_hunt_lead_is_replaced() {
    let mut m = Mission::at_fidelity(SCENARIO, Some(2), Preset::Discrete).expect("builds");
    m.end = SimTime::from_secs(1500);
    let mut t = SimTime::ZERO;
    let lead = loop {
        t += SimDuration::from_secs(1);
        assert!(m.advance(t), "the run ended before a hunt");
        let c = commander(&m);
        if let Some(&lead) = c.hunters.first()
            && turns_led(&m, lead).is_some_and(|n| n >= 2)
        {
            break lead;
        }
    };
    // The lead falls where no teammate sees it: only its silence on the radio tells.
    m.sim
        .env_mut()
        .conditions
        .update(lead, |c| c.status = Status::Down);
    let down_at = t;
    let mut next = None;
    while next.is_none() && m.advance(t) {
        t += SimDuration::from_secs(1);
        let c = commander(&m);
        next = (c.hunters.first().copied())
            .filter(|&l| l != lead && turns_led(&m, l).is_some_and(|n| n >= 1));
    }
    let next = next.expect("another pursuer leads the hunt");
    let took = (t - down_at).as_secs_f64();
    println!(
        "lead {lead:?} down at {:.0} s, {next:?} leads {took:.0} s later (seen down: {})",
        down_at.as_secs_f64(),
        commander(&m).fallen.contains(&lead)
    );
    let limit = 2.0 * 3.0 * m.brief.turn_s + 120.0;
    assert!(
        took <= limit,
        "{next:?} leads {took:.0} s after the lead fell"
    );
    assert!(matches!(trooper(&m, next).task, Task::Hunt(_)));
}

#[test]
fn the_game_search_leads_the_hunt_when_asked() {
    // `[pursuit] lead = "game"`: the lead plays MO-ISMCTS (the evader's decisions in its
    // tree) on the same board, turn by turn, and orders the team like the default search.
    let mut v = ScenarioFile::validate(SCENARIO).expect("valid");
    v.loaded.file.fidelity = FidelitySpec {
        level: Preset::Discrete,
        ..FidelitySpec::default()
    };
    v.loaded.file.pursuit.lead = PursuitLead::Game;
    let mut m = vitro_evac::Mission::build(v, Some(2)).expect("builds");
    m.end = SimTime::from_secs(1500);
    let mut turns = 0;
    let mut t = SimTime::ZERO;
    while m.advance(t) {
        for i in &m.frame().intentions {
            if i.text.starts_with("lead the HVT hunt") {
                assert!(i.text.contains("(MO-ISMCTS, turn "), "{}", i.text);
                turns = turns.max(turn_in(&i.text).unwrap_or(0));
            }
        }
        t += SimDuration::from_secs(1);
    }
    assert!(turns >= 3, "the game lead took {turns} turns");
}
