//! The hunt's pursuers are allocated by contract net: the truck calls for proposals for each
//! pursuer slot, the troopers bid from their own state, the best bids win; a hunt lead lost
//! where nobody sees it (its moves stop) has its slot called again and awarded to another
//! trooper.

mod common;

use common::{commander, trooper};
use vitro::entity::EntityId;
use vitro::time::{SimDuration, SimTime};
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_evac::agents::commander::Phase;
use vitro_evac::agents::trooper::Task;
use vitro_tactical::condition::Status;
use vitro_tactical::scenario::Preset;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// Seed 2 at the discrete level: the hunt starts early, before the VIP is out, and lasts.
fn mission() -> EvacRun {
    let mut m = Mission::at_fidelity(SCENARIO, Some(2), Preset::Discrete).expect("builds");
    m.end = SimTime::from_secs(1500);
    m
}

/// Runs `m` second by second until `done` holds (false if the run ended first).
fn until(m: &mut EvacRun, t: &mut SimTime, mut done: impl FnMut(&EvacRun) -> bool) -> bool {
    loop {
        *t += SimDuration::from_secs(1);
        if !m.advance(*t) {
            return false;
        }
        if done(m) {
            return true;
        }
    }
}

#[test]
fn the_hunt_slots_are_awarded_by_contract_net() {
    let mut m = mission();
    let k = m.brief.mission.hvt_pursuers as usize;
    let mut t = SimTime::ZERO;
    let full = until(&mut m, &mut t, |m| {
        let c = commander(m);
        c.hunters.len() == k && c.phase != Phase::Out && c.phase != Phase::Back
    });
    assert!(full, "the run ended before {k} pursuers hunted");
    let c = commander(&m);
    // One call per slot, each awarded: the hunters are exactly the winners.
    assert!(c.tender.calls >= k as u64, "{} calls", c.tender.calls);
    assert!(c.tender.awards >= k as u64, "{} awards", c.tender.awards);
    assert_eq!(c.tender.open(), 0);
    let hunters = c.hunters.clone();
    until(&mut m, &mut t, |m| {
        (hunters.iter()).all(|&h| matches!(trooper(m, h).task, Task::Hunt(_)))
    });
    // Every hunter won its slot; the winners were told (an accept may be lost on the radio,
    // the pursuit order is repeated).
    let c = commander(&m);
    assert!(hunters.iter().all(|&h| c.tender.holds(h)), "{hunters:?}");
    let told = (hunters.iter()).filter(|&&h| trooper(&m, h).contract.is_some());
    assert!(told.count() >= 1);
    for &h in &hunters {
        assert!(matches!(trooper(&m, h).task, Task::Hunt(_)), "{h:?} hunts");
    }
    // The troopers not chosen hold no contract.
    for &id in m.brief.team.iter().filter(|id| !hunters.contains(id)) {
        assert!(trooper(&m, id).contract.is_none(), "{id:?}");
    }
    let metrics = m.metrics();
    assert_eq!(metrics.cnet_calls, commander(&m).tender.calls);
    assert_eq!(metrics.cnet_awards, commander(&m).tender.awards);
}

#[test]
fn a_hunt_lead_lost_unseen_is_replaced_by_contract_net() {
    let mut m = mission();
    let k = m.brief.mission.hvt_pursuers as usize;
    let mut t = SimTime::ZERO;
    // A hunt under way: k pursuers, the lead has played a few turns.
    let on = until(&mut m, &mut t, |m| {
        let c = commander(m);
        c.hunters.len() == k
            && (c.hunters.first())
                .and_then(|&l| trooper(m, l).hunt.as_ref())
                .is_some_and(|h| h.turns >= 2)
    });
    assert!(on, "the run ended before the hunt was on");
    let before = commander(&m).tender.counts();
    let hunters = commander(&m).hunters.clone();
    // The lead falls where no teammate sees it: only its silence tells (no more moves for
    // the others; its body's GPS tracker goes on reporting).
    let lost: EntityId = *hunters.first().expect("a lead");
    m.sim
        .env_mut()
        .conditions
        .update(lost, |c| c.status = Status::Down);
    let down_at = t;
    let replaced = until(&mut m, &mut t, |m| {
        let c = commander(m);
        // At least k: the escort may join the hunt meanwhile (the VIP out).
        !c.hunters.contains(&lost)
            && c.hunters.len() >= k
            && (c.hunters.iter()).all(|&h| matches!(trooper(m, h).task, Task::Hunt(_)))
    });
    assert!(
        replaced,
        "the run ended before the slot was filled again (lead down at {:.0} s): {:?} hunt, tender {:?}, tasks {:?}",
        down_at.as_secs_f64(),
        commander(&m).hunters,
        commander(&m).tender.counts(),
        commander(&m)
            .hunters
            .iter()
            .map(|&h| format!("{:?}", trooper(&m, h).task))
            .collect::<Vec<_>>()
    );
    let took = (t - down_at).as_secs_f64();
    let c = commander(&m);
    let after = c.tender.counts();
    println!(
        "{lost:?} down at {:.0} s, replaced {took:.0} s later: {:?} hunt; calls/awards/reallocations {before:?} -> {after:?}",
        down_at.as_secs_f64(),
        c.hunters
    );
    assert!(after.2 > before.2, "a reallocation counted");
    assert!(
        after.0 > before.0 && after.1 > before.1,
        "a new call, awarded"
    );
    let newcomer = (c.hunters.iter()).find(|h| !hunters.contains(h));
    assert!(newcomer.is_some(), "another trooper took the slot");
    // Silence of three long turns, then the call: well within two minutes more (the
    // contract's report deadline is far longer).
    let limit = 2.0 * 3.0 * m.brief.turn_s + 120.0;
    assert!(took <= limit, "replaced {took:.0} s after the loss");
}
