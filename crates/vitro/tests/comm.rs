//! The simulated network: loss rate, delay and jitter bounds, bandwidth serialisation, range
//! limits, undeliverable messages, multicast and broadcast order, message counts.

use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use vitro::comm::{DeliveryError, MessageCounts};
use vitro::prelude::*;

/// Agents that send on command and log what they receive and what bounces.
struct Net;

#[derive(Default)]
struct World {
    pos: BTreeMap<EntityId, [f64; 3]>,
}

#[derive(Clone, Debug, Serialize)]
enum Cmd {
    /// Send `n` messages (bodies 0..n) of `size` bytes to `to`.
    Send {
        to: Address,
        n: u64,
        size: u32,
    },
    Join(GroupId),
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Got {
    body: u64,
    from: EntityId,
    sent: SimTime,
    at: SimTime,
}

#[derive(Default)]
struct Node {
    got: Vec<Got>,
    bounced: Vec<(SimTime, Address, DeliveryError)>,
}

impl Model for Net {
    type Env = World;
    type Event = Cmd;
    type Msg = u64;
    type Agent = Node;
    fn locate(env: &World, who: EntityId, _now: SimTime) -> Option<[f64; 3]> {
        env.pos.get(&who).copied()
    }
}

impl Agent<Net> for Node {
    fn handle(&mut self, input: Input<'_, Net>, cx: &mut Context<'_, Net>) {
        match input {
            Input::Event(&Cmd::Send { to, n, size }) => {
                for i in 0..n {
                    cx.send(Outgoing::new(to, i).size(size));
                }
            }
            Input::Event(&Cmd::Join(g)) => cx.join(g),
            Input::Message(e) => self.got.push(Got {
                body: e.body,
                from: e.from,
                sent: e.sent_at,
                at: cx.now(),
            }),
            Input::Undeliverable(e, err) => self.bounced.push((cx.now(), e.to, err)),
            Input::Timer(_) => {}
        }
    }
}

/// A simulation of `n` agents on a default link `link`.
fn setup(n: usize, link: LinkParams, seed: u64) -> (Simulation<Net>, Vec<EntityId>) {
    let mut sim = Simulation::<Net>::new(World::default(), seed);
    sim.network_mut().set_default_link(link);
    let ids = (0..n)
        .map(|i| sim.add_agent(format!("a{i}"), Node::default()).unwrap())
        .collect();
    (sim, ids)
}

fn send(sim: &mut Simulation<Net>, at: SimTime, from: EntityId, to: Address, n: u64, size: u32) {
    sim.schedule(at, Target::Entity(from), Cmd::Send { to, n, size })
        .unwrap();
}

fn got(sim: &Simulation<Net>, who: EntityId) -> &[Got] {
    &sim.agent(who).unwrap().got
}

fn counts(sim: &Simulation<Net>, who: EntityId) -> MessageCounts {
    sim.network().counts(who, Protocol::Plain)
}

/// Every copy sent is received, lost or bounced, and each agent's `received` is what it got.
fn assert_counts_balance(sim: &Simulation<Net>, ids: &[EntityId]) {
    let total = ids.iter().fold(MessageCounts::default(), |mut t, &id| {
        let c = counts(sim, id);
        assert_eq!(c.received, got(sim, id).len() as u64, "received by {id}");
        assert_eq!(c.bounced, sim.agent(id).unwrap().bounced.len() as u64);
        t.sent += c.sent;
        t.received += c.received;
        t.lost += c.lost;
        t.bounced += c.bounced;
        t
    });
    assert_eq!(total.sent, total.received + total.lost + total.bounced);
}

#[test]
fn loss_rate_matches_the_configured_one() {
    const N: u64 = 100_000;
    for loss in [0.0, 0.3, 0.9] {
        let link = LinkParams {
            loss,
            ..LinkParams::default()
        };
        let (mut sim, ids) = setup(2, link, 11);
        send(
            &mut sim,
            SimTime::ZERO,
            ids[0],
            Address::Agent(ids[1]),
            N,
            16,
        );
        assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
        let c = counts(&sim, ids[0]);
        assert_eq!(c.sent, N);
        assert_eq!(c.lost + got(&sim, ids[1]).len() as u64, N);
        let measured = c.lost as f64 / N as f64;
        assert!(
            (measured - loss).abs() <= 0.01,
            "loss {loss}: measured {measured}"
        );
        assert_counts_balance(&sim, &ids);
    }
}

#[test]
fn delay_and_jitter_stay_in_bounds() {
    let delay = SimDuration::from_millis(10);
    let jitter = SimDuration::from_millis(5);
    let link = LinkParams {
        delay,
        jitter,
        ..LinkParams::default()
    };
    let (mut sim, ids) = setup(2, link, 3);
    send(
        &mut sim,
        SimTime::ZERO,
        ids[0],
        Address::Agent(ids[1]),
        10_000,
        64,
    );
    send(
        &mut sim,
        SimTime::from_secs(1),
        ids[0],
        Address::Agent(ids[1]),
        10_000,
        64,
    );
    sim.run_until(SimTime::MAX);
    let lat: Vec<SimDuration> = got(&sim, ids[1]).iter().map(|g| g.at - g.sent).collect();
    assert_eq!(lat.len(), 20_000);
    assert!(lat.iter().all(|&l| l >= delay && l <= delay + jitter));
    // The whole interval is used, uniformly.
    let min = lat.iter().min().unwrap().as_secs_f64();
    let max = lat.iter().max().unwrap().as_secs_f64();
    let mean = lat.iter().map(|l| l.as_secs_f64()).sum::<f64>() / lat.len() as f64;
    assert!(min < 0.010_05 && max > 0.014_95, "[{min}, {max}]");
    assert!((mean - 0.0125).abs() < 0.0001, "mean {mean}");
}

#[test]
fn bandwidth_serialises_a_senders_messages() {
    let delay = SimDuration::from_millis(1);
    let link = LinkParams {
        delay,
        bandwidth_bps: Some(1e6),
        ..LinkParams::default()
    };
    let (mut sim, ids) = setup(3, link, 5);
    let (n, size) = (50u64, 1000u32);
    send(
        &mut sim,
        SimTime::ZERO,
        ids[0],
        Address::Agent(ids[2]),
        n,
        size,
    );
    // A second sender has its own transmitter.
    send(
        &mut sim,
        SimTime::ZERO,
        ids[1],
        Address::Agent(ids[2]),
        1,
        size,
    );
    sim.run_until(SimTime::MAX);
    let per = SimDuration::from_millis(8); // 1000 B · 8 / 1 Mbit/s
    let from0: Vec<&Got> = got(&sim, ids[2])
        .iter()
        .filter(|g| g.from == ids[0])
        .collect();
    assert_eq!(from0.len(), n as usize);
    for (k, g) in from0.iter().enumerate() {
        assert_eq!(g.body, k as u64, "in order");
        assert_eq!(g.at, SimTime::ZERO + per * (k as u64 + 1) + delay);
    }
    let last = from0.last().unwrap().at;
    assert!(last >= SimTime::from_secs_f64(n as f64 * size as f64 * 8.0 / 1e6));
    let from1 = got(&sim, ids[2]).iter().find(|g| g.from == ids[1]).unwrap();
    assert_eq!(from1.at, SimTime::ZERO + per + delay);

    // A rate that does not divide evenly: 3 bytes at 24 bit/s take at least 1 s, not 1 s - 1 ns.
    let link = LinkParams {
        delay: SimDuration::ZERO,
        bandwidth_bps: Some(24.0),
        ..LinkParams::default()
    };
    let (mut sim, ids) = setup(2, link, 5);
    send(
        &mut sim,
        SimTime::ZERO,
        ids[0],
        Address::Agent(ids[1]),
        3,
        1,
    );
    sim.run_until(SimTime::MAX);
    assert!(got(&sim, ids[1]).last().unwrap().at >= SimTime::from_secs(1));
}

#[test]
fn range_limit_bounces_out_of_range_messages() {
    let delay = SimDuration::from_millis(2);
    let link = LinkParams {
        delay,
        range_m: Some(100.0),
        ..LinkParams::default()
    };
    let (mut sim, ids) = setup(5, link, 1);
    let pos = &mut sim.env_mut().pos;
    pos.insert(ids[0], [0.0, 0.0, 0.0]);
    pos.insert(ids[1], [60.0, 0.0, 0.0]);
    pos.insert(ids[2], [0.0, 80.0, 60.0]); // exactly 100 m: in range
    pos.insert(ids[3], [150.0, 0.0, 0.0]);
    // ids[4] has no position.
    for &r in &ids[1..] {
        send(&mut sim, SimTime::ZERO, ids[0], Address::Agent(r), 1, 64);
    }
    sim.run_until(SimTime::MAX);
    assert_eq!(got(&sim, ids[1]).len(), 1);
    assert_eq!(got(&sim, ids[2]).len(), 1);
    assert!(got(&sim, ids[3]).is_empty() && got(&sim, ids[4]).is_empty());
    let bounced = &sim.agent(ids[0]).unwrap().bounced;
    assert_eq!(
        bounced,
        &[
            (
                SimTime::ZERO + delay,
                Address::Agent(ids[3]),
                DeliveryError::OutOfRange {
                    receiver: ids[3],
                    distance_m: 150.0,
                    range_m: 100.0
                }
            ),
            (
                SimTime::ZERO + delay,
                Address::Agent(ids[4]),
                DeliveryError::NoPosition(ids[4])
            ),
        ]
    );
    assert_eq!(bounced[0].2.receiver(), Some(ids[3]));
    let c = counts(&sim, ids[0]);
    assert_eq!((c.sent, c.bounced, c.lost), (4, 2, 0));
    assert_counts_balance(&sim, &ids);
}

#[test]
fn unknown_receiver_bounces() {
    let (mut sim, ids) = setup(2, LinkParams::default(), 1);
    let rock = sim.add_entity("rock").unwrap(); // an entity without an agent
    let nobody = EntityId(99);
    send(
        &mut sim,
        SimTime::ZERO,
        ids[0],
        Address::Agent(nobody),
        1,
        64,
    );
    send(&mut sim, SimTime::ZERO, ids[0], Address::Agent(rock), 1, 64);
    sim.run_until(SimTime::MAX);
    let errors: Vec<DeliveryError> = sim
        .agent(ids[0])
        .unwrap()
        .bounced
        .iter()
        .map(|b| b.2)
        .collect();
    assert_eq!(
        errors,
        [
            DeliveryError::UnknownReceiver(nobody),
            DeliveryError::UnknownReceiver(rock)
        ]
    );
    let c = counts(&sim, ids[0]);
    assert_eq!((c.sent, c.bounced), (2, 2));
    assert_counts_balance(&sim, &ids);
}

#[test]
fn multicast_reaches_members_and_broadcast_everyone_but_the_sender() {
    let (mut sim, ids) = setup(5, LinkParams::default(), 1);
    let log: Arc<Mutex<Vec<(SimTime, EntityId, EntityId)>>> = Arc::default();
    let l = log.clone();
    sim.add_listener(move |f| {
        if let Input::Message(e) = f.input {
            l.lock().unwrap().push((f.time, e.from, e.receiver));
        }
    });
    let g = GroupId(7);
    for &m in &[ids[4], ids[1], ids[3]] {
        sim.schedule(SimTime::ZERO, Target::Entity(m), Cmd::Join(g))
            .unwrap();
    }
    let t1 = SimTime::from_secs(1);
    let t2 = SimTime::from_secs(2);
    let t3 = SimTime::from_secs(3);
    send(&mut sim, t1, ids[1], Address::Group(g), 1, 64); // a member: the others get it
    send(&mut sim, t2, ids[0], Address::Group(g), 1, 64); // not a member: all members
    send(&mut sim, t3, ids[2], Address::Broadcast, 1, 64);
    send(&mut sim, t3, ids[0], Address::Group(GroupId(9)), 1, 64); // empty group
    sim.run_until(SimTime::MAX);
    let d = LinkParams::default().delay;
    let expected = vec![
        (t1 + d, ids[1], ids[3]),
        (t1 + d, ids[1], ids[4]),
        (t2 + d, ids[0], ids[1]),
        (t2 + d, ids[0], ids[3]),
        (t2 + d, ids[0], ids[4]),
        (t3 + d, ids[2], ids[0]),
        (t3 + d, ids[2], ids[1]),
        (t3 + d, ids[2], ids[3]),
        (t3 + d, ids[2], ids[4]),
    ];
    assert_eq!(*log.lock().unwrap(), expected);
    let bounced = &sim.agent(ids[0]).unwrap().bounced;
    assert_eq!(
        bounced,
        &[(
            t3 + d,
            Address::Group(GroupId(9)),
            DeliveryError::EmptyGroup(GroupId(9))
        )]
    );
    let sent: Vec<u64> = ids.iter().map(|&id| counts(&sim, id).sent).collect();
    let received: Vec<u64> = ids.iter().map(|&id| counts(&sim, id).received).collect();
    assert_eq!(sent, [4, 2, 4, 0, 0]);
    assert_eq!(received, [1, 2, 0, 3, 3]);
    assert_counts_balance(&sim, &ids);
}

#[test]
fn counts_balance_and_runs_are_reproducible() {
    let run = |seed| {
        let link = LinkParams {
            loss: 0.2,
            jitter: SimDuration::from_millis(3),
            ..LinkParams::default()
        };
        let (mut sim, ids) = setup(4, link, seed);
        send(&mut sim, SimTime::ZERO, ids[0], Address::Broadcast, 100, 64);
        send(
            &mut sim,
            SimTime::ZERO,
            ids[1],
            Address::Agent(ids[0]),
            50,
            64,
        );
        send(
            &mut sim,
            SimTime::ZERO,
            ids[2],
            Address::Agent(EntityId(42)),
            5,
            64,
        );
        sim.run_until(SimTime::MAX);
        assert_counts_balance(&sim, &ids);
        // Only the plain protocol was used.
        assert!(
            sim.network()
                .all_counts()
                .all(|(_, p, _)| p == Protocol::Plain)
        );
        assert_eq!(sim.network().total_sent(), 300 + 50 + 5);
        sim.trace_hash()
    };
    assert_eq!(run(8), run(8));
    assert_ne!(run(8), run(9));
}
