//! Rounds: every member once per firing, in a fresh seeded order; joins and leaves; the trace
//! hash sees the order; a snapshot mid-run continues it exactly.

use rand::Rng;
use serde::{Deserialize, Serialize};
use std::sync::{Arc, Mutex};
use vitro::prelude::*;
use vitro::sim::RoundId;

/// Environment: the activations in the order they happened (time, who).
#[derive(Default, Serialize, Deserialize)]
struct Log {
    seen: Vec<(SimTime, EntityId)>,
}

struct M;
impl Model for M {
    type Env = Log;
    type Event = ();
    type Msg = ();
    type Agent = Member;
}

/// Writes down one activation.
struct Note;
impl Actuator<Log, ()> for Note {
    type Command = ();
    type Error = std::convert::Infallible;
    fn actuate(
        &self,
        w: &mut Log,
        me: EntityId,
        _: (),
        fx: &mut Effects<'_, ()>,
    ) -> Result<(), Self::Error> {
        w.seen.push((fx.now(), me));
        Ok(())
    }
}

/// A member: notes each activation, draws from its small stream, leaves after `stay`
/// activations (if set).
#[derive(Serialize, Deserialize)]
struct Member {
    round: RoundId,
    stay: Option<u32>,
    count: u32,
    drawn: u64,
}

impl Agent<M> for Member {
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        if let Input::Timer(5) = input {
            let Ok(()) = cx.act(&Note, ());
            self.count += 1;
            self.drawn ^= cx.small_rng("draw").random::<u64>();
            if self.stay == Some(self.count) {
                assert!(cx.leave_round(self.round));
            }
        }
    }
}

const SEC: SimDuration = SimDuration::from_secs(1);

fn world(n: u32, seed: u64) -> (Simulation<M>, RoundId) {
    let mut sim = Simulation::<M>::new(Log::default(), seed);
    let round = sim.add_round(SimTime::ZERO, SEC, 5).expect("at time zero");
    for i in 0..n {
        let m = Member {
            round,
            stay: None,
            count: 0,
            drawn: 0,
        };
        let id = sim.add_agent(format!("m{i}"), m).expect("unique");
        assert!(sim.join_round(round, id));
        assert!(!sim.join_round(round, id), "a member joins once");
    }
    (sim, round)
}

/// The activation order of each firing.
fn firings(sim: &Simulation<M>) -> Vec<Vec<u32>> {
    let mut out: Vec<(SimTime, Vec<u32>)> = Vec::new();
    for &(t, e) in &sim.env().seen {
        match out.last_mut() {
            Some((at, v)) if *at == t => v.push(e.0),
            _ => out.push((t, vec![e.0])),
        }
    }
    out.into_iter().map(|(_, v)| v).collect()
}

#[test]
fn every_member_once_per_firing_in_a_fresh_order() {
    let (mut sim, round) = world(40, 3);
    assert_eq!(sim.round_len(round), 40);
    sim.run_until(SimTime::from_secs(9));
    let f = firings(&sim);
    assert_eq!(f.len(), 10);
    assert_eq!(sim.events_fired(), 10, "one event per firing");
    for order in &f {
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..40).collect::<Vec<_>>());
    }
    // 40! orders: two equal ones (or the joining order) would be a broken shuffle.
    for (i, a) in f.iter().enumerate() {
        assert_ne!(*a, (0..40).collect::<Vec<_>>());
        assert!(f[i + 1..].iter().all(|b| b != a));
    }
    // Each member is first about as often as any other: over 400 firings of 4 members
    // each is first 100 ± 30 times (a 3.3-sigma band of Binomial(400, 1/4)).
    let (mut sim, _) = world(4, 5);
    sim.run_until(SimTime::from_secs(399));
    let mut first = [0u32; 4];
    for order in firings(&sim) {
        first[order[0] as usize] += 1;
    }
    assert!(first.iter().all(|&c| (70..=130).contains(&c)), "{first:?}");
}

#[test]
fn the_hash_follows_the_seed_and_the_order() {
    let hash = |seed| {
        let (mut sim, _) = world(30, seed);
        sim.run_until(SimTime::from_secs(20));
        (sim.trace_hash(), firings(&sim))
    };
    let (a, fa) = hash(1);
    let (b, fb) = hash(1);
    assert_eq!((a, &fa), (b, &fb));
    let (c, fc) = hash(2);
    assert_ne!(a, c);
    assert_ne!(fa, fc);
}

#[test]
fn members_leave_and_join_and_an_empty_round_goes_idle() {
    let (mut sim, round) = world(0, 9);
    let stay = |k| Member {
        round,
        stay: Some(k),
        count: 0,
        drawn: 0,
    };
    let a = sim.add_agent("a", stay(3)).expect("unique");
    let b = sim.add_agent("b", stay(5)).expect("unique");
    sim.join_round(round, a);
    sim.join_round(round, b);
    // Both leave (after 3 and 5 activations): the round then has no event left.
    assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
    assert_eq!(sim.agent(a).map(|m| m.count), Some(3));
    assert_eq!(sim.agent(b).map(|m| m.count), Some(5));
    assert_eq!(sim.now(), SimTime::from_secs(4));
    assert_eq!(sim.round_len(round), 0);
    assert!(!sim.leave_round(round, a), "not a member any more");
    // A join restarts it at the next instant of its period.
    sim.schedule(SimTime::from_nanos(6_500_000_000), Target::Env, ())
        .expect("ahead");
    sim.run_until(SimTime::from_nanos(6_500_000_000));
    let c = sim.add_agent("c", stay(2)).expect("unique");
    sim.join_round(round, c);
    assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
    let seen: Vec<(SimTime, EntityId)> = sim.env().seen.iter().copied().skip(8).collect();
    assert_eq!(
        seen,
        [(SimTime::from_secs(7), c), (SimTime::from_secs(8), c)]
    );
}

#[test]
fn a_snapshot_mid_run_continues_the_rounds_exactly() {
    let end = SimTime::from_secs(30);
    let (mut whole, _) = world(25, 4);
    whole.run_until(end);
    let (mut first, _) = world(25, 4);
    first.run_until(SimTime::from_nanos(12_500_000_000));
    let mut bytes = Vec::new();
    first.save_snapshot(&mut bytes).expect("saved");
    let mut rest = Simulation::<M>::load_snapshot(&bytes[..]).expect("loaded");
    rest.run_until(end);
    assert_eq!(rest.trace_hash(), whole.trace_hash());
    assert_eq!(rest.env().seen, whole.env().seen);
    let drawn = |s: &Simulation<M>| {
        s.entities()
            .ids()
            .map(|e| s.agent(e).map_or(0, |m| m.drawn))
            .collect::<Vec<_>>()
    };
    assert_eq!(drawn(&rest), drawn(&whole));
}

#[test]
fn listeners_see_every_activation() {
    let (mut sim, _) = world(7, 2);
    let heard = Arc::new(Mutex::new(Vec::new()));
    let h = heard.clone();
    sim.add_listener(move |f| {
        if let (Target::Entity(e), Input::Timer(5)) = (f.target, &f.input) {
            h.lock().expect("not poisoned").push((f.time, e));
        }
    });
    sim.run_until(SimTime::from_secs(3));
    assert_eq!(*heard.lock().expect("not poisoned"), sim.env().seen);
}
