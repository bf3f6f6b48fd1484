//! The contract net reacts: sectors are shared out over the radio, a lost UAV's sectors are
//! called again and won by the others, a dead radio awards nothing, a tasked area is called.

mod common;

use common::{build, run_to, scenario, set, station, uavs};
use std::collections::BTreeSet;
use toml::Value;

#[test]
fn every_sector_is_awarded_over_a_working_radio() {
    let mut t = scenario();
    set(&mut t, "channel.loss", Value::Float(0.0));
    let mut op = build(&t, 3);
    run_to(&mut op, 120);
    let st = station(&op);
    assert!(!st.sectors.is_empty());
    assert!(
        st.sectors
            .values()
            .all(|s| s.holder.is_some() && s.confirmed.is_some())
    );
    assert_eq!(st.stats.awards as usize, st.sectors.len());
    // The station's picture is what the UAVs hold: each sector held by exactly one.
    let mut held = BTreeSet::new();
    for (_, u) in uavs(&op) {
        for s in u.sectors.keys() {
            assert!(held.insert(*s), "sector {s} held twice");
        }
    }
    assert_eq!(held.len(), st.sectors.len());
    // The load is shared: every UAV holds some.
    assert!(uavs(&op).iter().all(|(_, u)| !u.sectors.is_empty()));
}

#[test]
fn a_lost_uavs_sectors_go_to_the_others() {
    let mut t = scenario();
    set(&mut t, "channel.loss", Value::Float(0.0));
    t.remove("area");
    let lost_at = 200;
    let mut loss = toml::Table::new();
    loss.insert("uav".into(), Value::String("uav-2".into()));
    loss.insert("at_s".into(), Value::Float(lost_at as f64));
    t.insert("loss".into(), Value::Array(vec![Value::Table(loss)]));
    let mut op = build(&t, 5);
    run_to(&mut op, lost_at - 1);
    let uav2 = op
        .members
        .iter()
        .find(|m| m.name == "uav-2")
        .map(|m| m.id)
        .unwrap();
    let had: Vec<u32> = uavs(&op)
        .into_iter()
        .find(|(n, _)| n == "uav-2")
        .map(|(_, u)| u.sectors.keys().copied().collect())
        .unwrap();
    assert!(!had.is_empty(), "uav-2 held sectors before its loss");
    let before = station(&op).stats.reallocations;
    // Lost: silent from then on; the station presumes it lost after 30 s of silence.
    run_to(&mut op, lost_at + 90);
    assert_eq!(op.metrics().uavs_lost, 1);
    let st = station(&op);
    assert!(st.presumed_lost.contains(&uav2));
    assert!(st.stats.reallocations >= before + had.len() as u64);
    for s in &had {
        let holder = st.sectors[s].holder;
        assert!(
            holder.is_some() && holder != Some(uav2),
            "sector {s}: {holder:?}"
        );
    }
    // The others hold them now, and fly them.
    let others: BTreeSet<u32> = uavs(&op)
        .iter()
        .filter(|(n, _)| n != "uav-2")
        .flat_map(|(_, u)| u.sectors.keys().copied())
        .collect();
    assert!(had.iter().all(|s| others.contains(s)));
}

#[test]
fn a_dead_radio_awards_nothing() {
    let mut t = scenario();
    set(&mut t, "channel.loss", Value::Float(1.0));
    let mut op = build(&t, 5);
    run_to(&mut op, 300);
    let m = op.metrics();
    assert_eq!(m.awards, 0, "no proposal ever reaches the station");
    // Every call ends without a proposal (the last one may still be open).
    assert!(m.calls > 0 && m.calls_failed + 1 >= m.calls, "{m:?}");
    assert_eq!(m.messages_lost, m.messages_sent);
    assert!(uavs(&op).iter().all(|(_, u)| u.sectors.is_empty()));
    // Without sectors, each UAV searches the whole area on its own.
    assert!(uavs(&op).iter().all(|(_, u)| !u.route.is_empty()));
}

#[test]
fn radio_loss_changes_the_allocation() {
    let winners = |loss: f64| {
        let mut t = scenario();
        set(&mut t, "channel.loss", Value::Float(loss));
        let mut op = build(&t, 9);
        run_to(&mut op, 200);
        let st = station(&op);
        let m = op.metrics();
        let holders: Vec<_> = st.sectors.values().map(|s| s.holder).collect();
        (holders, m.calls, m.calls_failed)
    };
    let (clean, calls0, failed0) = winners(0.0);
    let (lossy, calls6, failed6) = winners(0.6);
    assert_eq!(failed0, 0);
    assert!(
        failed6 > 0 && calls6 > calls0,
        "{calls6} calls, {failed6} failed"
    );
    assert_ne!(clean, lossy);
}

#[test]
fn a_tasked_area_is_cut_into_sectors_and_awarded() {
    let mut t = scenario();
    set(&mut t, "channel.loss", Value::Float(0.0));
    t.remove("loss");
    let mut area = toml::Table::new();
    area.insert("appear_s".into(), Value::Float(60.0));
    let corners = [300.0, 300.0, 900.0, 900.0].map(Value::Float);
    area.insert("area".into(), Value::Array(corners.to_vec()));
    t.insert("area".into(), Value::Array(vec![Value::Table(area)]));
    let mut op = build(&t, 5);
    run_to(&mut op, 59);
    let n = station(&op).sectors.len();
    run_to(&mut op, 150);
    let st = station(&op);
    assert_eq!(
        st.sectors.len(),
        n + 4,
        "a 600 m square in 400 m sectors: 2 x 2"
    );
    assert!(st.sectors.values().all(|s| s.holder.is_some()));
}

#[test]
fn random_failures_come_from_the_seed_and_are_noticed() {
    let failing = |seed| {
        let mut t = scenario();
        t.remove("loss");
        set(&mut t, "failures.rate_per_h", Value::Float(4.0));
        set(&mut t, "end.time_s", Value::Float(900.0));
        let mut op = build(&t, seed);
        op.run();
        op
    };
    let (a, b) = (failing(21), failing(21));
    assert_eq!(a.lost, b.lost, "the same failures for the same seed");
    assert!(
        !a.lost.is_empty(),
        "about 63 % of the UAVs fail within 15 min at 4 per hour"
    );
    assert_ne!(a.lost, failing(22).lost);
    // Every UAV that failed more than `lost_after_s` before the end was presumed lost.
    let st = station(&a);
    for (id, t) in &a.lost {
        if t.as_secs_f64() < 900.0 - 40.0 {
            assert!(st.presumed_lost.contains(id), "{id:?} lost at {t:?}");
        }
    }
}
