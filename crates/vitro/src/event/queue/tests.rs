use super::radix::*;
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

impl RadixHeap {
    /// Checks the bucket invariant and the cached counts.
    fn check(&self) {
        let mut len = 0;
        let mut chunks = 0;
        for b in 0..BUCKETS {
            for e in self.bucket(b) {
                assert!(e.key() >= self.last);
                assert_eq!(bucket_of(e.key(), self.last), b);
                len += 1;
            }
            for (i, (_, entries)) in self.chunks_of(b).enumerate() {
                assert!(
                    i == 0 || entries.len() == CHUNK,
                    "only the head may be partial"
                );
                chunks += 1;
            }
            let marked = self.occupied[b / 64] >> (b % 64) & 1 == 1;
            assert_eq!(marked, self.bucket(b).next().is_some());
        }
        assert_eq!(len, self.len);
        let mut c = self.free_chunks;
        while c != NIL {
            chunks += 1;
            c = self.chunks[c as usize].next;
        }
        assert_eq!(chunks, self.chunks.len(), "every chunk is in one list");
        for (w, &bits) in self.occupied.iter().enumerate() {
            assert_eq!(self.summary >> w & 1 == 1, bits != 0);
        }
    }
}

#[test]
fn buckets_order_keys() {
    // Bucket numbers grow with the key, for keys above a common `last`.
    let last = (7u128 << 64) | 1000;
    let mut keys: Vec<u128> = vec![last, last + 1, last + 15, last + 16, last + 17];
    keys.extend((0..128).map(|bit| last | (1 << bit)));
    keys.extend([(8 << 64) | 3, (9 << 64), u128::MAX]);
    keys.sort_unstable();
    keys.dedup();
    let buckets: Vec<usize> = keys.iter().map(|&k| bucket_of(k, last)).collect();
    assert!(buckets.windows(2).all(|w| w[0] <= w[1]), "{buckets:?}");
    assert!(buckets.iter().all(|&b| b < BUCKETS));
    assert_eq!(bucket_of(0, 0), 0);
    assert_eq!(bucket_of(u128::MAX, 0), BUCKETS - 1);
}

#[test]
fn radix_heap_sorts_monotone_keys() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut h = RadixHeap::new(0, 0);
    let mut reference = std::collections::BTreeSet::new();
    let mut seq = 0;
    let mut now = 0u64;
    for _ in 0..20_000 {
        if rng.random_bool(0.55) {
            // Times cluster (many ties) or jump far (high buckets).
            let time = now
                + match rng.random_range(0..3) {
                    0 => 0,
                    1 => rng.random_range(0..16),
                    _ => rng.random_range(0..1 << 40),
                };
            let e = Entry { time, seq, slot: 0 };
            seq += 1;
            h.push(e);
            reference.insert(e.key());
        } else if let Some(pos) = h.min_pos() {
            let e = h.take_min(pos);
            assert_eq!(Some(e.key()), reference.pop_first());
            now = e.time;
        } else {
            assert!(reference.is_empty());
        }
        if seq % 64 == 0 {
            h.check();
        }
    }
    while let Some(pos) = h.min_pos() {
        assert_eq!(Some(h.take_min(pos).key()), reference.pop_first());
    }
    assert!(reference.is_empty());
    h.check();
}

fn entry(time: u64, seq: u64) -> Entry {
    Entry { time, seq, slot: 0 }
}

#[test]
fn big_bucket_spans_chunks_and_retains() {
    let mut h = RadixHeap::new(0, 0);
    // All in one bucket: same highest differing digit (time bit 40) and digit value.
    for seq in 0..(5 * CHUNK as u64 + 3) {
        h.push(entry((1 << 40) + 1000 - seq, seq));
    }
    let b = h.lowest().unwrap();
    assert_eq!(h.bucket(b).count(), h.len);
    assert_eq!(h.chunks.len(), 6);
    h.check();
    h.retain_in(b, |e| e.seq % 3 == 0);
    h.check();
    assert_eq!(h.len, (5 * CHUNK + 3).div_ceil(3));
    let mut popped = Vec::new();
    while let Some(p) = h.min_pos() {
        popped.push(h.take_min(p).seq);
        h.check();
    }
    // Later seqs have earlier times here.
    let mut want: Vec<u64> = (0..(5 * CHUNK as u64 + 3)).filter(|s| s % 3 == 0).collect();
    want.reverse();
    assert_eq!(popped, want);
    assert_eq!(h.len, 0);
}

#[test]
fn chunk_memory_follows_the_entries() {
    // A hold model on the bare heap: 20 000 entries, exponential-like spread, many rounds.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut h = RadixHeap::new(0, 0);
    let n = 20_000u64;
    let mut seq = 0;
    for _ in 0..n {
        h.push(entry(rng.random_range(0..1 << 30), seq));
        seq += 1;
    }
    for _ in 0..10 * n {
        let p = h.min_pos().unwrap();
        let e = h.take_min(p);
        let dt = (rng.random_range(1u64..1 << 20)).pow(2) >> 10;
        h.push(entry(e.time + dt, seq));
        seq += 1;
    }
    h.check();
    let full = n as usize / CHUNK;
    assert!(
        h.chunks.len() <= full + full / 2 + BUCKETS / 4,
        "{} chunks for {} entries",
        h.chunks.len(),
        h.len
    );
}

#[test]
fn equal_time_is_fifo() {
    let mut q = EventQueue::new();
    for i in 0..100 {
        q.push(SimTime::from_secs(5), i).unwrap();
    }
    q.push(SimTime::from_secs(1), -1).unwrap();
    assert_eq!(q.pop().unwrap().payload, -1);
    for i in 0..100 {
        assert_eq!(q.pop().unwrap().payload, i);
    }
    assert!(q.pop().is_none());
}

#[test]
fn cancel_and_past() {
    let mut q = EventQueue::new();
    let a = q.push(SimTime::from_secs(1), 'a').unwrap();
    let b = q.push(SimTime::from_secs(2), 'b').unwrap();
    assert!(q.cancel(a));
    assert!(!q.cancel(a));
    assert_eq!(q.len(), 1);
    let p = q.pop().unwrap();
    assert_eq!((p.payload, p.id), ('b', b));
    assert!(!q.cancel(b), "fired events cannot be cancelled");
    assert_eq!(
        q.push(SimTime::from_secs(1), 'c'),
        Err(ScheduleError::InThePast {
            at: SimTime::from_secs(1),
            now: SimTime::from_secs(2)
        })
    );
    // A reused slot does not resurrect an old handle.
    let c = q.push(SimTime::from_secs(3), 'c').unwrap();
    assert!(!q.cancel(a));
    assert!(q.is_pending(c));
}

#[test]
fn stale_entry_of_a_reused_slot_is_skipped() {
    let mut q = EventQueue::new();
    let a = q.push(SimTime::from_secs(1), 'a').unwrap();
    assert!(q.cancel(a));
    // Takes a's slot; a's entry (time 1) is still in the heap, now stale.
    let b = q.push(SimTime::from_secs(5), 'b').unwrap();
    assert_eq!(b.slot, a.slot);
    assert_eq!(q.peek_time(), Some(SimTime::from_secs(5)));
    let p = q.pop().unwrap();
    assert_eq!((p.id, p.payload), (b, 'b'));
    assert!(q.pop().is_none());
    assert!(q.heap.iter().next().is_none(), "the stale entry is gone");
}

#[test]
fn cancel_drops_the_payload_at_once() {
    let token = std::rc::Rc::new(());
    let mut q = EventQueue::new();
    let id = q.push(SimTime::from_secs(9), token.clone()).unwrap();
    assert_eq!(std::rc::Rc::strong_count(&token), 2);
    assert!(q.cancel(id));
    assert_eq!(std::rc::Rc::strong_count(&token), 1);
}

#[test]
fn peek_then_push_earlier_is_fine() {
    // peek_time does not advance the heap: an event may still go before the peeked one.
    let mut q = EventQueue::new();
    q.push(SimTime::from_secs(10), 10).unwrap();
    q.pop().unwrap();
    q.push(SimTime::from_secs(20), 20).unwrap();
    assert_eq!(q.peek_time(), Some(SimTime::from_secs(20)));
    q.push(SimTime::from_secs(10), 11).unwrap();
    q.push(SimTime::from_secs(15), 15).unwrap();
    let order: Vec<i32> = std::iter::from_fn(|| q.pop().map(|p| p.payload)).collect();
    assert_eq!(order, [11, 15, 20]);
}

#[test]
fn pending_sorted_skips_cancelled() {
    let mut q = EventQueue::new();
    let ids: Vec<_> = [3, 1, 2, 1]
        .iter()
        .map(|&s| q.push(SimTime::from_secs(s), s).unwrap())
        .collect();
    q.cancel(ids[2]);
    let v: Vec<_> = q
        .pending_sorted()
        .into_iter()
        .map(|(t, id, &p)| (t.as_nanos() / 1_000_000_000, id.seq(), p))
        .collect();
    assert_eq!(v, [(1, 1, 1), (1, 3, 1), (3, 0, 3)]);
}

fn round_trip(q: &EventQueue<u32>) -> Result<EventQueue<u32>, postcard::Error> {
    postcard::from_bytes(&postcard::to_stdvec(q).unwrap())
}

#[test]
fn serde_round_trip_continues_identically() {
    let mut q = EventQueue::new();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut ids = Vec::new();
    for i in 0..500 {
        let t = q.now().as_nanos() + rng.random_range(0..1000);
        ids.push(q.push(SimTime::from_nanos(t), i).unwrap());
        if i % 3 == 0 {
            q.pop();
        }
        if i % 7 == 0 {
            q.cancel(ids[rng.random_range(0..ids.len())]);
        }
    }
    let mut r = round_trip(&q).unwrap();
    assert_eq!(r.len(), q.len());
    for i in 0..2000u32 {
        if i % 2 == 0 {
            let t = SimTime::from_nanos(q.now().as_nanos() + u64::from(i % 50));
            assert_eq!(q.push(t, i), r.push(t, i));
        }
        if i % 11 == 0 {
            let id = ids[i as usize % ids.len()];
            assert_eq!(q.cancel(id), r.cancel(id));
        }
        assert_eq!(q.peek_time(), r.peek_time());
        assert_eq!(q.pop(), r.pop());
    }
}

type State = (SimTime, u64, Vec<Entry>, Vec<Slot<u32>>, u32, Option<Ties>);

fn decode(state: &State) -> Result<EventQueue<u32>, postcard::Error> {
    postcard::from_bytes(&postcard::to_stdvec(state).unwrap())
}

#[test]
fn serialized_form_is_canonical() {
    let mut q: EventQueue<u32> = EventQueue::new();
    let a = q.push(SimTime::from_secs(1), 1).unwrap();
    q.push(SimTime::from_secs(2), 2).unwrap();
    q.cancel(a);
    let state: State = (
        SimTime::ZERO,
        2,
        vec![Entry {
            time: 2_000_000_000,
            seq: 1,
            slot: 1,
        }],
        vec![
            Slot::Free { next_free: NO_FREE },
            Slot::Pending { seq: 1, payload: 2 },
        ],
        0,
        None,
    );
    // The stale entry of the cancelled event is not written.
    let bytes = postcard::to_stdvec(&q).unwrap();
    assert_eq!(bytes, postcard::to_stdvec(&state).unwrap());
    // Reading and writing again gives the same bytes, though the buckets differ inside.
    let r = decode(&state).unwrap();
    assert_eq!(postcard::to_stdvec(&r).unwrap(), bytes);
}

#[test]
fn corrupt_state_is_refused() {
    let good: State = (
        SimTime::ZERO,
        2,
        vec![Entry {
            time: 2_000_000_000,
            seq: 1,
            slot: 1,
        }],
        vec![
            Slot::Free { next_free: NO_FREE },
            Slot::Pending { seq: 1, payload: 2 },
        ],
        0,
        None,
    );
    assert!(decode(&good).is_ok());
    let bad = |f: &dyn Fn(&mut State)| {
        let mut s = good.clone();
        f(&mut s);
        decode(&s).is_err()
    };
    assert!(bad(&|s| s.2[0].slot = 7), "event pointing past the slab");
    assert!(bad(&|s| s.2[0].seq = 0), "event not the one its slot holds");
    assert!(bad(&|s| s.2.push(s.2[0])), "one event twice");
    assert!(bad(&|s| s.2.clear()), "pending slot without an event");
    assert!(bad(&|s| s.4 = NO_FREE), "free slot off the free list");
    assert!(bad(&|s| s.4 = 1), "free list through a pending slot");
    assert!(
        bad(&|s| s.3[0] = Slot::Free { next_free: 0 }),
        "free list cycle"
    );
    assert!(bad(&|s| s.1 = 1), "sequence number not issued yet");
    assert!(bad(&|s| s.0 = SimTime::from_secs(3)), "event before now");
}

/// The payloads of `q` in firing order.
fn drain(q: &mut EventQueue<u32>) -> Vec<u32> {
    std::iter::from_fn(|| q.pop().map(|p| p.payload)).collect()
}

#[test]
fn shuffled_ties_fire_every_event_once_in_a_seeded_order() {
    let make = |seed: u64| {
        let mut q = EventQueue::new();
        q.shuffle_ties(seed);
        for i in 0..20 {
            q.push(SimTime::from_secs(1 + u64::from(i) / 10), i)
                .unwrap();
        }
        q
    };
    let a = drain(&mut make(3));
    assert_eq!(a, drain(&mut make(3)));
    assert_ne!(a, drain(&mut make(4)));
    // Each time's batch is a permutation of its events, and the times keep their order.
    let mut first: Vec<u32> = a[..10].to_vec();
    first.sort();
    assert_eq!(first, (0..10).collect::<Vec<_>>());
    assert!(a[10..].iter().all(|&x| x >= 10));
    assert_ne!(a[..10], (0..10).collect::<Vec<_>>()[..]);
}

#[test]
fn shuffled_ties_honour_cancels_and_later_pushes() {
    let mut q = EventQueue::new();
    q.shuffle_ties(9);
    let ids: Vec<EventId> = (0..6)
        .map(|i| q.push(SimTime::from_secs(1), i).unwrap())
        .collect();
    let first = q.pop().unwrap();
    // Cancelling an event of the batch being fired: it never fires.
    let victim = ids.iter().copied().find(|&id| id != first.id).unwrap();
    assert!(q.cancel(victim));
    assert!(!q.is_pending(victim));
    // An event pushed for the current time fires after the rest of the batch.
    q.push(SimTime::from_secs(1), 99).unwrap();
    let rest = drain(&mut q);
    assert_eq!(rest.len(), 5, "{rest:?}");
    assert_eq!(rest.last(), Some(&99));
    let victim_payload: u32 = ids
        .iter()
        .zip(0..)
        .find(|(id, _)| **id == victim)
        .unwrap()
        .1;
    assert!(!rest.contains(&victim_payload) && first.payload != victim_payload);
    assert_eq!(q.len(), 0);
}

#[test]
fn a_queue_saved_inside_a_batch_of_ties_goes_on_the_same() {
    let mut q = EventQueue::new();
    q.shuffle_ties(5);
    for i in 0..12 {
        q.push(SimTime::from_secs(1 + u64::from(i) % 3), i).unwrap();
    }
    for _ in 0..2 {
        q.pop();
    }
    let bytes = postcard::to_stdvec(&q).unwrap();
    let mut r: EventQueue<u32> = postcard::from_bytes(&bytes).unwrap();
    assert_eq!(r.len(), q.len());
    assert_eq!(drain(&mut r), drain(&mut q));
}
