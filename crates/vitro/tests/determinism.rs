//! Determinism: same seed, same trace hash, whatever a controlling thread does; snapshot and
//! restore continue the run exactly; named random streams are independent of other entities.

mod common;

use common::{Ev, gossip};
use rand::{Rng, SeedableRng};
use std::time::Duration;
use vitro::prelude::*;

const END: SimTime = SimTime::from_secs(30);

fn reference_hash(seed: u64) -> (u64, u64) {
    let mut sim = gossip(12, seed);
    assert_eq!(sim.run_until(END), StopReason::Time);
    (sim.trace_hash(), sim.events_fired())
}

#[test]
fn same_seed_same_hash_different_seed_different_hash() {
    let a = reference_hash(5);
    assert!(
        a.1 > 500,
        "the model is busy enough to test anything: {} events",
        a.1
    );
    assert_eq!(a, reference_hash(5));
    assert_ne!(a.0, reference_hash(6).0);
}

#[test]
fn twenty_runs_under_a_meddling_controller_give_the_same_hash() {
    let (expected, events) = reference_hash(11);
    let mut meddler = rand_chacha::ChaCha8Rng::seed_from_u64(0xC0FFEE);
    for run in 0..20 {
        let mut sim = gossip(12, 11);
        let control = sim.control();
        // Start paced and paused half the time.
        control
            .set_speed(meddler.random_range(200.0..1000.0))
            .expect("in range");
        if run % 2 == 0 {
            control.pause();
        }
        let worker = std::thread::spawn(move || {
            let reason = sim.run_until(END);
            (reason, sim.trace_hash(), sim.events_fired())
        });
        let mut actions = 0;
        while !worker.is_finished() {
            actions += 1;
            if actions > 60 {
                // Let it finish.
                control.resume();
                control.unpaced();
            } else {
                match meddler.random_range(0..6) {
                    0 => control.pause(),
                    1 => control.resume(),
                    2 => control.step(meddler.random_range(1..50)),
                    3 => control
                        .set_speed(meddler.random_range(0.1..=1000.0))
                        .expect("in range"),
                    4 => control.unpaced(),
                    _ => {
                        let _ = (
                            control.sim_time(),
                            control.events_fired(),
                            control.is_paused(),
                        );
                    }
                }
            }
            std::thread::sleep(Duration::from_micros(meddler.random_range(0..3000)));
        }
        let (reason, hash, fired) = worker.join().expect("no panic in the run");
        assert_eq!(reason, StopReason::Time);
        assert_eq!((hash, fired), (expected, events), "run {run}");
    }
}

#[test]
fn snapshot_at_half_time_then_restore_gives_the_uninterrupted_hash() {
    let (expected, _) = reference_hash(21);
    let mut sim = gossip(12, 21);
    sim.run_until(SimTime::from_secs(15));
    let path = std::env::temp_dir().join(format!("vitro-snapshot-{}.bin", std::process::id()));
    let file = std::fs::File::create(&path).expect("temp file");
    sim.save_snapshot(std::io::BufWriter::new(file))
        .expect("saved");
    drop(sim);
    let file = std::fs::File::open(&path).expect("temp file");
    let mut restored =
        Simulation::<common::GossipModel>::load_snapshot(std::io::BufReader::new(file))
            .expect("loaded");
    let _ = std::fs::remove_file(&path);
    assert_eq!(restored.now().as_secs_f64().floor(), 14.0);
    restored.run_until(END);
    assert_eq!(restored.trace_hash(), expected);
}

#[test]
fn a_corrupt_snapshot_is_an_error_not_a_panic() {
    let mut sim = gossip(3, 1);
    sim.run_until(SimTime::from_secs(2));
    let mut bytes = Vec::new();
    sim.save_snapshot(&mut bytes).expect("saved");
    assert!(matches!(
        Simulation::<common::GossipModel>::load_snapshot(&b"not a snapshot at all"[..]),
        Err(vitro::sim::SnapshotError::BadHeader)
    ));
    let truncated = &bytes[..bytes.len() / 2];
    assert!(Simulation::<common::GossipModel>::load_snapshot(truncated).is_err());
    for i in (16..bytes.len()).step_by(7) {
        let mut b = bytes.clone();
        b[i] ^= 0xFF;
        // Corruption may or may not decode; it must never panic.
        let _ = Simulation::<common::GossipModel>::load_snapshot(&b[..]);
    }
}

#[test]
fn adding_an_entity_does_not_change_anothers_random_numbers() {
    // Agent 0's tick times depend only on its own stream: compare its first ticks in a
    // simulation of 3 agents and of 4.
    fn first_ticks(n: u32) -> Vec<SimTime> {
        let mut sim = gossip(n, 99);
        sim.network_mut().set_default_link(LinkParams {
            loss: 1.0,
            ..LinkParams::default()
        });
        let times = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let t2 = times.clone();
        sim.add_listener(move |f| {
            if f.target == Target::Entity(EntityId(0)) && matches!(f.input, Input::Event(Ev::Tick))
            {
                t2.lock().expect("lock").push(f.time);
            }
        });
        sim.run_until(SimTime::from_secs(20));
        times.lock().expect("lock").clone()
    }
    let a = first_ticks(3);
    assert!(a.len() > 5);
    assert_eq!(a, first_ticks(4));
}
