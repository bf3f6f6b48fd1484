//! The event queue against a reference model: a sorted list of (time, seq, payload).
//!
//! Random sequences of pushes (at equal times, at far-apart times, in the past), cancellations
//! (of pending, fired, cancelled and forged handles), pops, peeks and postcard round trips.
//! After a round trip the restored queue runs alongside the original and must answer every
//! operation exactly as it does, handles included. With shuffled ties
//! ([`EventQueue::shuffle_ties`]) the model knows the current batch of equal-time events and
//! accepts any of its live events, in any order, but nothing outside it; the restored copy
//! must still fire exactly what the original fires.

use proptest::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
use vitro::event::{EventId, EventQueue, Popped, ScheduleError};
use vitro::time::SimTime;

/// Offsets from `now` for pushes: ties, near neighbours, and jumps into every digit range of
/// the key (the radix heap's buckets), up to the end of time.
const OFFSETS: [u64; 12] = [
    0,
    0,
    1,
    2,
    15,
    16,
    1_000,
    1 << 20,
    1_000_000_007,
    1 << 40,
    1 << 62,
    u64::MAX,
];

#[derive(Clone, Debug)]
enum Op {
    /// Push at `now + OFFSETS[i] + jitter` (saturating).
    Push(usize, u64),
    /// Push before `now` (an error, unless now is zero: then it lands at zero).
    PushPast(u64),
    /// Cancel a handle the queue issued earlier (pending, fired or cancelled).
    Cancel(prop::sample::Index),
    /// Cancel a handle the queue never issued: a future sequence number, or an issued sequence
    /// number with another slot.
    CancelForged(bool, u64, u32),
    /// Ask whether an issued handle is pending.
    IsPending(prop::sample::Index),
    Pop,
    Peek,
    /// Replace the shadow copy by a postcard round trip of the queue.
    RoundTrip,
    /// Compare `pending_sorted` with the model.
    Inspect,
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        8 => (0..OFFSETS.len(), 0u64..4).prop_map(|(i, j)| Op::Push(i, j)),
        1 => (1u64..1_000_000).prop_map(Op::PushPast),
        2 => any::<prop::sample::Index>().prop_map(Op::Cancel),
        1 => (any::<bool>(), 0u64..8, 0u32..64).prop_map(|(f, s, l)| Op::CancelForged(f, s, l)),
        1 => any::<prop::sample::Index>().prop_map(Op::IsPending),
        6 => Just(Op::Pop),
        2 => Just(Op::Peek),
        1 => Just(Op::RoundTrip),
        1 => Just(Op::Inspect),
    ]
}

/// What became of an issued event, in the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fate {
    Pending,
    Fired,
    Cancelled,
}

/// The reference: pending events sorted by (time, seq), and every issued handle's fate.
#[derive(Default)]
struct Model {
    now: u64,
    next_seq: u64,
    pending: Vec<(u64, u64, u32)>,
    fate: BTreeMap<u64, Fate>,
    /// Shuffled ties: the current batch (sequence numbers of live events at `now` that fire,
    /// in some order, before anything else).
    batch: BTreeSet<u64>,
}

impl Model {
    fn push(&mut self, at: u64, payload: u32) -> Result<u64, ()> {
        if at < self.now {
            return Err(());
        }
        let seq = self.next_seq;
        self.next_seq += 1;
        let i = self
            .pending
            .partition_point(|&(t, s, _)| (t, s) < (at, seq));
        self.pending.insert(i, (at, seq, payload));
        self.fate.insert(seq, Fate::Pending);
        Ok(seq)
    }
    fn cancel(&mut self, seq: u64) -> bool {
        if self.fate.get(&seq) != Some(&Fate::Pending) {
            return false;
        }
        self.fate.insert(seq, Fate::Cancelled);
        self.pending.retain(|&(_, s, _)| s != seq);
        self.batch.remove(&seq);
        true
    }
    /// Shuffled ties: the batch the next pop draws from (made from every pending event at
    /// the earliest time when the last batch is done).
    fn current_batch(&mut self) -> &BTreeSet<u64> {
        if self.batch.is_empty()
            && let Some(&(t, _, _)) = self.pending.first()
        {
            self.batch = self
                .pending
                .iter()
                .take_while(|&&(u, _, _)| u == t)
                .map(|&(_, s, _)| s)
                .collect();
        }
        &self.batch
    }
    /// Shuffled ties: checks that `seq` may fire now and fires it.
    fn pop_tied(&mut self, seq: u64) -> Result<(u64, u32), String> {
        if !self.current_batch().contains(&seq) {
            return Err(format!(
                "event {seq} fired outside the batch {:?}",
                self.batch
            ));
        }
        self.batch.remove(&seq);
        let i = self
            .pending
            .iter()
            .position(|&(_, s, _)| s == seq)
            .ok_or("a batch event is pending")?;
        let (t, _, p) = self.pending.remove(i);
        self.now = t;
        self.fate.insert(seq, Fate::Fired);
        Ok((t, p))
    }
    fn pop(&mut self) -> Option<(u64, u64, u32)> {
        if self.pending.is_empty() {
            return None;
        }
        let first = self.pending.remove(0);
        self.now = first.0;
        self.fate.insert(first.1, Fate::Fired);
        Some(first)
    }
    fn peek(&self) -> Option<u64> {
        if !self.batch.is_empty() {
            return Some(self.now);
        }
        self.pending.first().map(|p| p.0)
    }
}

/// An [`EventId`] made up from its fields: (sequence number, slot).
fn forged(seq: u64, slot: u32) -> EventId {
    postcard::from_bytes(&postcard::to_stdvec(&(seq, slot)).expect("encode"))
        .expect("an EventId is its (seq, slot)")
}

/// The fields of an [`EventId`]: (sequence number, slot).
fn fields(id: EventId) -> (u64, u32) {
    postcard::from_bytes(&postcard::to_stdvec(&id).expect("encode")).expect("decode")
}

/// Runs `ops` on a queue, the model, and (after the first round trip) a restored copy;
/// with `shuffle`, on a queue whose ties are shuffled from that seed.
fn run(ops: &[Op], shuffle: Option<u64>) -> Result<(), TestCaseError> {
    let mut q: EventQueue<u32> = EventQueue::new();
    if let Some(seed) = shuffle {
        q.shuffle_ties(seed);
    }
    let mut model = Model::default();
    let mut shadow: Option<EventQueue<u32>> = None;
    let mut issued: Vec<EventId> = Vec::new();

    for (n, op) in ops.iter().enumerate() {
        let payload = n as u32;
        match op {
            Op::Push(i, jitter) => {
                let at = model
                    .now
                    .saturating_add(OFFSETS[*i])
                    .saturating_add(*jitter);
                let got = q.push(SimTime::from_nanos(at), payload);
                let want = model.push(at, payload);
                let id = got
                    .clone()
                    .map_err(|e| TestCaseError::fail(e.to_string()))?;
                prop_assert_eq!(Ok(id.seq()), want);
                issued.push(id);
                if let Some(r) = &mut shadow {
                    prop_assert_eq!(r.push(SimTime::from_nanos(at), payload), got);
                }
            }
            Op::PushPast(back) => {
                let at = model.now.saturating_sub(*back);
                let got = q.push(SimTime::from_nanos(at), payload);
                match model.push(at, payload) {
                    Ok(seq) => {
                        let id = got
                            .clone()
                            .map_err(|e| TestCaseError::fail(e.to_string()))?;
                        prop_assert_eq!(id.seq(), seq);
                        issued.push(id);
                    }
                    Err(()) => prop_assert_eq!(
                        got.clone(),
                        Err(ScheduleError::InThePast {
                            at: SimTime::from_nanos(at),
                            now: SimTime::from_nanos(model.now),
                        })
                    ),
                }
                if let Some(r) = &mut shadow {
                    prop_assert_eq!(r.push(SimTime::from_nanos(at), payload), got);
                }
            }
            Op::Cancel(index) => {
                if issued.is_empty() {
                    continue;
                }
                let id = issued[index.index(issued.len())];
                let got = q.cancel(id);
                prop_assert_eq!(got, model.cancel(id.seq()));
                prop_assert!(!q.is_pending(id));
                if let Some(r) = &mut shadow {
                    prop_assert_eq!(r.cancel(id), got);
                }
            }
            Op::CancelForged(future, k, slot) => {
                let id = if !future && !issued.is_empty() {
                    // A real sequence number in another slot.
                    let (seq, real_slot) = fields(issued[(*k as usize) % issued.len()]);
                    forged(seq, real_slot.wrapping_add(1 + slot))
                } else {
                    // A sequence number not issued yet.
                    forged(model.next_seq + k, *slot)
                };
                prop_assert!(!issued.contains(&id));
                prop_assert!(!q.is_pending(id));
                prop_assert!(!q.cancel(id));
                if let Some(r) = &mut shadow {
                    prop_assert!(!r.cancel(id));
                }
            }
            Op::IsPending(index) => {
                if issued.is_empty() {
                    continue;
                }
                let id = issued[index.index(issued.len())];
                let want = model.fate.get(&id.seq()) == Some(&Fate::Pending);
                prop_assert_eq!(q.is_pending(id), want);
                if let Some(r) = &shadow {
                    prop_assert_eq!(r.is_pending(id), want);
                }
            }
            Op::Pop if shuffle.is_some() => {
                let got = q.pop();
                match &got {
                    None => prop_assert!(model.pending.is_empty()),
                    Some(popped) => {
                        let (t, p) = model
                            .pop_tied(popped.id.seq())
                            .map_err(TestCaseError::fail)?;
                        prop_assert_eq!(popped.time, SimTime::from_nanos(t));
                        prop_assert_eq!(popped.payload, p);
                        prop_assert!(issued.contains(&popped.id));
                    }
                }
                if let Some(r) = &mut shadow {
                    let again: Option<Popped<u32>> = r.pop();
                    prop_assert_eq!(again, got);
                }
            }
            Op::Pop => {
                let got = q.pop();
                match model.pop() {
                    None => prop_assert!(got.is_none()),
                    Some((t, seq, p)) => {
                        let popped = got.clone().ok_or_else(|| TestCaseError::fail("no pop"))?;
                        prop_assert_eq!(popped.time, SimTime::from_nanos(t));
                        prop_assert_eq!(popped.id.seq(), seq);
                        prop_assert_eq!(popped.payload, p);
                        // The handle is the one the push returned, slot included.
                        prop_assert!(issued.contains(&popped.id));
                    }
                }
                if let Some(r) = &mut shadow {
                    let again: Option<Popped<u32>> = r.pop();
                    prop_assert_eq!(again, got);
                }
            }
            Op::Peek => {
                let got = q.peek_time();
                prop_assert_eq!(got, model.peek().map(SimTime::from_nanos));
                if let Some(r) = &mut shadow {
                    prop_assert_eq!(r.peek_time(), got);
                }
            }
            Op::RoundTrip => {
                let bytes =
                    postcard::to_stdvec(&q).map_err(|e| TestCaseError::fail(e.to_string()))?;
                let r: EventQueue<u32> =
                    postcard::from_bytes(&bytes).map_err(|e| TestCaseError::fail(e.to_string()))?;
                shadow = Some(r);
            }
            Op::Inspect => {
                let mut got: Vec<(u64, u64, u32)> = q
                    .pending_sorted()
                    .into_iter()
                    .map(|(t, id, &p)| (t.as_nanos(), id.seq(), p))
                    .collect();
                // In firing order: the rest of the current batch of ties first.
                let first: BTreeSet<u64> =
                    got.iter().take(model.batch.len()).map(|e| e.1).collect();
                prop_assert_eq!(&first, &model.batch);
                got.sort_unstable_by_key(|&(t, s, _)| (t, s));
                prop_assert_eq!(&got, &model.pending);
            }
        }
        prop_assert_eq!(q.len(), model.pending.len());
        prop_assert_eq!(q.is_empty(), model.pending.is_empty());
        prop_assert_eq!(q.now(), SimTime::from_nanos(model.now));
        prop_assert_eq!(q.next_seq(), model.next_seq);
        if let Some(r) = &shadow {
            prop_assert_eq!(r.len(), q.len());
            prop_assert_eq!(r.now(), q.now());
            prop_assert_eq!(r.next_seq(), q.next_seq());
        }
    }
    // Drain: everything left comes out in model order, from both queues alike.
    if shuffle.is_some() {
        while let Some(popped) = q.pop() {
            let (t, p) = model
                .pop_tied(popped.id.seq())
                .map_err(TestCaseError::fail)?;
            prop_assert_eq!((popped.time, popped.payload), (SimTime::from_nanos(t), p));
            if let Some(r) = &mut shadow {
                prop_assert_eq!(r.pop(), Some(popped));
            }
        }
        prop_assert!(model.pending.is_empty());
        return Ok(());
    }
    while let Some((t, seq, p)) = model.pop() {
        let popped = q
            .pop()
            .ok_or_else(|| TestCaseError::fail("queue ran dry early"))?;
        prop_assert_eq!(
            (popped.time, popped.id.seq(), popped.payload),
            (SimTime::from_nanos(t), seq, p)
        );
        if let Some(r) = &mut shadow {
            prop_assert_eq!(r.pop(), Some(popped));
        }
    }
    prop_assert_eq!(q.pop(), None);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn queue_matches_the_model(ops in prop::collection::vec(op(), 1..300)) {
        run(&ops, None)?;
    }

    #[test]
    fn a_queue_with_shuffled_ties_matches_the_model(
        seed in any::<u64>(),
        ops in prop::collection::vec(op(), 1..300),
    ) {
        run(&ops, Some(seed))?;
    }
}

/// Long runs: enough pops for the queue to revise its layout (day width and count) a few
/// times, with round trips in between. A fixed number of seeded cases (not scaled by
/// `PROPTEST_CASES`: each is long).
#[test]
fn long_runs_match_the_model() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let ops = prop::collection::vec(op(), 1000..3000);
    for case in 0..16 {
        let ops = ops.new_tree(&mut runner).expect("a case").current();
        if let Err(e) = run(&ops, None) {
            panic!("case {case}: {e}");
        }
        if let Err(e) = run(&ops, Some(case)) {
            panic!("case {case}, shuffled ties: {e}");
        }
    }
}

/// Many events at one instant, interleaved with far ones: FIFO at equal times must hold across
/// bucket boundaries (sequence numbers crossing digit boundaries) and a round trip.
#[test]
fn ties_across_digit_boundaries() {
    let mut q = EventQueue::new();
    let mut ids = Vec::new();
    for i in 0..5000u32 {
        let at = if i % 7 == 0 { 1u64 << 50 } else { 1_000 };
        ids.push((at, q.push(SimTime::from_nanos(at), i).unwrap()));
    }
    for _ in 0..100 {
        q.pop().unwrap();
    }
    let mut r: EventQueue<u32> = postcard::from_bytes(&postcard::to_stdvec(&q).unwrap()).unwrap();
    ids.sort_by_key(|&(at, id)| (at, id.seq()));
    for &(at, id) in &ids[100..] {
        let p = q.pop().unwrap();
        assert_eq!((p.time.as_nanos(), p.id), (at, id));
        assert_eq!(r.pop(), Some(p));
    }
    assert!(q.pop().is_none() && r.pop().is_none());
}

/// Bytes that are not a queue are an error, not a panic.
#[test]
fn garbage_is_refused() {
    let mut q = EventQueue::new();
    for i in 0..50u32 {
        q.push(SimTime::from_nanos(u64::from(i) * 1_000_003 % 7_919), i)
            .unwrap();
    }
    q.pop();
    let bytes = postcard::to_stdvec(&q).unwrap();
    // Flip bytes one at a time: every outcome is Ok or Err, and an Ok queue still drains in order.
    for i in 0..bytes.len() {
        let mut b = bytes.clone();
        b[i] ^= 0x5a;
        if let Ok(mut r) = postcard::from_bytes::<EventQueue<u32>>(&b) {
            let mut last = (r.now(), 0);
            while let Some(p) = r.pop() {
                assert!((p.time, p.id.seq()) >= last);
                last = (p.time, p.id.seq());
            }
        }
    }
}
