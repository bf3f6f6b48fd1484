//! The other allocation methods: sequential auctions over the radio and the station's
//! central plan (a vehicle routing problem) share every sector out, take over a lost
//! UAV's sectors, depend on the radio, charge the search in simulated time, and are chosen
//! by the scenario alone.

mod common;

use common::{build, path, run_to, scenario, set, station, uavs};
use std::collections::BTreeSet;
use toml::Value;
use vitro::time::SimTime;
use vitro_mission::{Mission as _, MissionError};
use vitro_surveillance::Surveillance;

const METHODS: [&str; 2] = ["auction", "central"];

fn with(method: &str, loss: f64) -> toml::Table {
    let mut t = scenario();
    set(&mut t, "allocation.method", Value::String(method.into()));
    set(&mut t, "channel.loss", Value::Float(loss));
    t
}

#[test]
fn each_method_shares_every_sector_out_over_a_working_radio() {
    for method in METHODS {
        let mut op = build(&with(method, 0.0), 3);
        run_to(&mut op, 120);
        let st = station(&op);
        assert!(!st.sectors.is_empty());
        assert!(
            (st.sectors.values()).all(|s| s.holder.is_some() && s.confirmed.is_some()),
            "{method}: every sector held and confirmed"
        );
        let mut held = BTreeSet::new();
        for (_, u) in uavs(&op) {
            for s in u.sectors.keys() {
                assert!(held.insert(*s), "{method}: sector {s} held twice");
            }
            assert!(!u.sectors.is_empty(), "{method}: every UAV holds some");
        }
        assert_eq!(held.len(), st.sectors.len(), "{method}");
        let m = op.metrics();
        assert_eq!(m.cnet_messages, 0, "{method}: no contract net");
        assert!(m.allocation_messages > 0, "{method}");
        assert_eq!(m.calls_failed, 0, "{method}");
    }
}

#[test]
fn the_central_plan_shares_the_sectors_evenly_and_takes_simulated_time() {
    let mut t = with("central", 0.0);
    t.remove("area");
    t.remove("loss");
    // 500 iterations at 20 ms: the tours leave the station 10 s after the start.
    set(&mut t, "allocation.iteration_ms", Value::Float(20.0));
    let mut op = build(&t, 4);
    run_to(&mut op, 9);
    assert!(station(&op).sectors.values().all(|s| s.holder.is_none()));
    run_to(&mut op, 60);
    let st = station(&op);
    let ten = SimTime::from_secs(10);
    assert!(st.sectors.values().all(|s| s.assigned == Some(ten)));
    assert_eq!(st.stats.calls, 1, "one plan for the whole area");
    let loads: Vec<usize> = uavs(&op).iter().map(|(_, u)| u.sectors.len()).collect();
    let per = st.sectors.len().div_ceil(loads.len());
    assert!(loads.iter().all(|&n| n <= per && n > 0), "{loads:?}");
}

#[test]
fn a_lost_uavs_sectors_go_to_the_others() {
    for method in METHODS {
        let mut t = with(method, 0.0);
        t.remove("area");
        let mut loss = toml::Table::new();
        loss.insert("uav".into(), Value::String("uav-2".into()));
        loss.insert("at_s".into(), Value::Float(200.0));
        t.insert("loss".into(), Value::Array(vec![Value::Table(loss)]));
        let mut op = build(&t, 5);
        run_to(&mut op, 199);
        let had: Vec<u32> = (uavs(&op).into_iter())
            .find(|(n, _)| n == "uav-2")
            .map(|(_, u)| u.sectors.keys().copied().collect())
            .unwrap();
        assert!(!had.is_empty(), "{method}");
        run_to(&mut op, 400);
        let st = station(&op);
        let uav2 = op.members.iter().find(|m| m.name == "uav-2").unwrap().id;
        assert_eq!(st.stats.presumed_lost, 1, "{method}");
        for s in &had {
            let holder = st.sectors[s].holder;
            assert!(holder.is_some() && holder != Some(uav2), "{method}: {s}");
        }
        assert!(st.stats.reallocations >= had.len() as u64, "{method}");
    }
}

#[test]
fn a_dead_radio_gives_no_uav_a_sector() {
    for method in METHODS {
        let mut op = build(&with(method, 1.0), 5);
        run_to(&mut op, 300);
        let m = op.metrics();
        assert!(uavs(&op).iter().all(|(_, u)| u.sectors.is_empty()));
        assert!(m.calls_failed > 0, "{method}: {m:?}");
    }
    // Without bids the auction awards nothing; the central plan is sent, never confirmed.
    let m = build(&with("auction", 1.0), 5).metrics();
    assert_eq!(m.awards, 0);
}

#[test]
fn the_method_is_the_scenarios_and_each_run_is_deterministic() {
    let hash = |method: &str| {
        let mut op = build(&with(method, 0.05), 11);
        run_to(&mut op, 600);
        op.sim.trace_hash()
    };
    let a = hash("auction");
    let c = hash("central");
    let n = hash("contract-net");
    assert_eq!(a, hash("auction"));
    assert_eq!(c, hash("central"));
    assert!(a != c && a != n && c != n);
    // Leaving the key out is the contract net.
    let mut op = build(
        &{
            let mut t = scenario();
            set(&mut t, "channel.loss", Value::Float(0.05));
            t
        },
        11,
    );
    run_to(&mut op, 600);
    assert_eq!(op.sim.trace_hash(), n);
}

#[test]
fn a_bad_method_or_budget_is_located() {
    let text = std::fs::read_to_string(path()).unwrap();
    let bad = text.replacen("method = \"contract-net\"", "method = \"telepathy\"", 1);
    let Err(MissionError::Scenario(e)) = Surveillance.validate(&path(), &bad) else {
        panic!("an unknown method is bad input");
    };
    let line = bad
        .lines()
        .position(|l| l.starts_with("method = "))
        .unwrap()
        + 1;
    assert!(e.contains(&format!("surveillance.toml:{line}:")), "{e}");
    assert!(e.contains("telepathy") && e.contains("contract-net"), "{e}");

    let bad = text.replacen("budget = 500 ", "budget = 0 ", 1);
    let Err(MissionError::Scenario(e)) = Surveillance.validate(&path(), &bad) else {
        panic!("a budget of 0 is bad input");
    };
    let line = bad
        .lines()
        .position(|l| l.starts_with("budget = "))
        .unwrap()
        + 1;
    assert!(
        e.contains(&format!(
            "surveillance.toml:{line}:10: invalid value 0 for `allocation.budget`"
        )),
        "{e}"
    );
}
