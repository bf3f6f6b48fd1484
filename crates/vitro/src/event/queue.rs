//! The pending-event set: a priority queue ordered by (time, scheduling sequence).
//!
//! Events at equal time pop in the order they were pushed (FIFO), always. Payloads are stored
//! inline in a slab (no box per event); cancellation is O(1) through the [`EventId`] handle.
//!
//! # How it works
//!
//! Entries are keyed by the 128-bit `(time << 64) | seq`, so equal times pop in push order.
//! They live in three tiers (module `calendar`): the current *day* (a span of `2^k`
//! nanoseconds, about the mean gap between events) in a small binary heap; the next days,
//! up to a horizon a few mean hold times ahead, unsorted in a ring of day buckets (a calendar
//! queue, Brown 1988); and the events beyond the horizon in a monotone radix heap. A push is an
//! append to its tier; a pop takes the heap's minimum and, when the day is over, heapifies the
//! next non-empty day (found in a two-level bitmap) and moves the far events the window now
//! covers from the radix heap to the ring. The day width and count follow the observed gaps
//! and hold distances, revised at most once per `len` pops (a revision is O(len)). A crowded
//! instant costs O(log n) per event in the day heap, never a linear scan.
//!
//! Simulated time never goes back: an event is never scheduled before the last popped one, and
//! every new event gets a larger sequence number than any before it. So the keys leave the queue in
//! increasing order, and the far tier is a *monotone radix heap* on them. An entry sits in the
//! bucket named by the highest byte in which its key differs from the last popped key, and by its
//! own value of that byte (16 positions × 256 values); every key of a bucket is below every key of
//! a higher bucket. A push is a `leading_zeros` and an append. A pop takes the minimum of the
//! lowest non-empty bucket (found in a two-level bitmap) and spreads the rest of that bucket over
//! lower buckets. An entry moves at most 16 times in its life, in practice once or twice, and
//! each move is a sequential copy of 24 bytes: no sift, no unpredictable branch per heap level, no cache miss per
//! level once the queue outgrows the cache.
//!
//! Buckets, the radix heap's and the ring's days, are lists of fixed-size chunks drawn from one
//! pool, so memory follows the number of entries rather than the largest size every bucket
//! ever reached.
//!
//! Payloads live in a slab, apart from the 24-byte entries `(time, seq, slot)` that move
//! between buckets. Cancelling frees the slab slot at once (dropping the payload); the entry
//! left in a bucket is recognised as stale (its slot is free or holds another sequence number)
//! and discarded when it reaches the front. A reused slot therefore never resurrects an old
//! handle.
//!
//! Slot reuse depends only on the order of `push`, `pop` and `cancel` calls, never on how the
//! entries are spread over the buckets, so a queue restored from its serialized form hands out
//! the same [`EventId`]s as the original from then on. The serialized state is checked when it
//! is read back: a corrupt snapshot is an error, not a panic later.

mod calendar;
mod radix;

use crate::time::SimTime;
use calendar::Calendar;
use radix::{Entry, InvalidState};
use serde::{Deserialize, Serialize};

/// Handle of a scheduled event: its scheduling sequence number and its storage slot.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct EventId {
    seq: u64,
    slot: u32,
}

impl EventId {
    /// The scheduling sequence number: unique per queue, increasing in scheduling order.
    pub fn seq(self) -> u64 {
        self.seq
    }
}

/// Why an event could not be scheduled.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ScheduleError {
    /// The requested time is earlier than the current simulated time.
    #[error("cannot schedule an event at {at}: simulated time is already {now}")]
    InThePast {
        /// The requested time.
        at: SimTime,
        /// The queue's current time.
        now: SimTime,
    },
}

/// An event taken out of the queue.
#[derive(Debug, Clone, PartialEq)]
pub struct Popped<T> {
    /// When it fires.
    pub time: SimTime,
    /// Its handle (sequence number).
    pub id: EventId,
    /// Its payload.
    pub payload: T,
}

/// A slab slot: free (a link of the free list) or holding a pending event's payload.
#[derive(Clone, Debug, Serialize, Deserialize)]
enum Slot<T> {
    Free { next_free: u32 },
    Pending { seq: u64, payload: T },
}

/// End of the free list; also the bound on the number of slots.
const NO_FREE: u32 = u32::MAX;

/// True if `e` is the live entry of its slot (not cancelled, not superseded).
#[inline(always)]
fn is_live<T>(slots: &[Slot<T>], e: &Entry) -> bool {
    matches!(slots.get(e.slot as usize), Some(Slot::Pending { seq, .. }) if *seq == e.seq)
}

/// A priority queue of events keyed by (time, sequence).
///
/// ```
/// use vitro::event::EventQueue;
/// use vitro::time::SimTime;
/// let mut q = EventQueue::new();
/// q.push(SimTime::from_secs(2), "late").unwrap();
/// let first = q.push(SimTime::from_secs(1), "first").unwrap();
/// q.push(SimTime::from_secs(1), "second").unwrap();
/// let p = q.pop().unwrap();
/// assert_eq!((p.time, p.id, p.payload), (SimTime::from_secs(1), first, "first"));
/// assert_eq!(q.pop().unwrap().payload, "second"); // equal times: first pushed, first out
/// assert_eq!(q.now(), SimTime::from_secs(1));
/// assert!(q.push(SimTime::ZERO, "too late").is_err());
/// ```
///
/// # Serialized form
///
/// The time, the next sequence number, the pending events' keys in firing order, and the slab
/// with its free list: nothing about the internal buckets, so equal queues serialize to equal
/// bytes. Reading it back checks every invariant and refuses a corrupt state with an error.
#[derive(Clone, Debug, Deserialize)]
#[serde(try_from = "QueueState<T>")]
pub struct EventQueue<T> {
    now: SimTime,
    next_seq: u64,
    heap: Calendar,
    slots: Vec<Slot<T>>,
    free_head: u32,
    /// Number of pending events (occupied slots).
    pending: usize,
}

impl<T: Serialize> Serialize for EventQueue<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut events: Vec<Entry> = self
            .heap
            .iter()
            .filter(|e| is_live(&self.slots, e))
            .copied()
            .collect();
        events.sort_unstable_by_key(Entry::key);
        let mut st = s.serialize_struct("EventQueue", 5)?;
        st.serialize_field("now", &self.now)?;
        st.serialize_field("next_seq", &self.next_seq)?;
        st.serialize_field("events", &events)?;
        st.serialize_field("slots", &self.slots)?;
        st.serialize_field("free_head", &self.free_head)?;
        st.end()
    }
}

/// The serialized form of [`EventQueue`], checked on the way in.
#[derive(Deserialize)]
struct QueueState<T> {
    now: SimTime,
    next_seq: u64,
    events: Vec<Entry>,
    slots: Vec<Slot<T>>,
    free_head: u32,
}

impl<T> TryFrom<QueueState<T>> for EventQueue<T> {
    type Error = InvalidState;
    fn try_from(s: QueueState<T>) -> Result<Self, InvalidState> {
        let n = s.slots.len();
        if n > NO_FREE as usize {
            return Err(InvalidState("too many slots"));
        }
        // Each event: in range, and the one its slot holds (so no two events share a slot).
        let mut heap = Calendar::new(s.now.as_nanos());
        let mut covered = vec![false; n];
        for e in s.events {
            if e.time < s.now.as_nanos() || e.seq >= s.next_seq {
                return Err(InvalidState("event out of range"));
            }
            if !is_live(&s.slots, &e) || std::mem::replace(&mut covered[e.slot as usize], true) {
                return Err(InvalidState("event does not match its slot"));
            }
            heap.push(e, s.now.as_nanos());
        }
        // Every pending slot has its event; the free list links exactly the free slots.
        let mut free = 0;
        for (slot, covered) in s.slots.iter().zip(&covered) {
            match slot {
                Slot::Pending { .. } if !covered => {
                    return Err(InvalidState("pending slot without an event"));
                }
                Slot::Pending { .. } => {}
                Slot::Free { .. } => free += 1,
            }
        }
        let mut linked = vec![false; n];
        let mut at = s.free_head;
        let mut count = 0;
        while at != NO_FREE {
            match s.slots.get(at as usize) {
                Some(Slot::Free { next_free }) if !linked[at as usize] => {
                    linked[at as usize] = true;
                    count += 1;
                    at = *next_free;
                }
                _ => return Err(InvalidState("broken free list")),
            }
        }
        if count != free {
            return Err(InvalidState("free slot missing from the free list"));
        }
        Ok(EventQueue {
            now: s.now,
            next_seq: s.next_seq,
            pending: heap.len(),
            heap,
            slots: s.slots,
            free_head: s.free_head,
        })
    }
}

impl<T> Default for EventQueue<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T> EventQueue<T> {
    /// An empty queue at time zero.
    pub fn new() -> Self {
        Self::with_capacity(0)
    }

    /// An empty queue with room for `n` pending events' payloads.
    pub fn with_capacity(n: usize) -> Self {
        EventQueue {
            now: SimTime::ZERO,
            next_seq: 0,
            heap: Calendar::new(0),
            slots: Vec::with_capacity(n),
            free_head: NO_FREE,
            pending: 0,
        }
    }

    /// The time of the last popped event (the queue's current time).
    pub fn now(&self) -> SimTime {
        self.now
    }

    /// Number of pending (not cancelled) events.
    pub fn len(&self) -> usize {
        self.pending
    }

    /// True if no event is pending.
    pub fn is_empty(&self) -> bool {
        self.pending == 0
    }

    /// The sequence number the next push will get.
    pub fn next_seq(&self) -> u64 {
        self.next_seq
    }

    /// Schedules `payload` at `at`. Fails if `at` is before [`now`](Self::now).
    ///
    /// # Panics
    ///
    /// If 2^32 - 1 events are pending at once.
    pub fn push(&mut self, at: SimTime, payload: T) -> Result<EventId, ScheduleError> {
        if at < self.now {
            return Err(ScheduleError::InThePast { at, now: self.now });
        }
        let seq = self.next_seq;
        self.next_seq += 1;
        let pending = Slot::Pending { seq, payload };
        let slot = if self.free_head != NO_FREE {
            let s = self.free_head;
            let cell = &mut self.slots[s as usize];
            let Slot::Free { next_free } = *cell else {
                unreachable!("the free list links only free slots")
            };
            self.free_head = next_free;
            *cell = pending;
            s
        } else {
            let s = self.slots.len();
            assert!(s < NO_FREE as usize, "more than 2^32 - 1 pending events");
            self.slots.push(pending);
            s as u32
        };
        self.heap.push(
            Entry {
                time: at.as_nanos(),
                seq,
                slot,
            },
            self.now.as_nanos(),
        );
        self.pending += 1;
        Ok(EventId { seq, slot })
    }

    /// Cancels a pending event, dropping its payload. Returns false if it already fired or
    /// was cancelled.
    pub fn cancel(&mut self, id: EventId) -> bool {
        if self.is_pending(id) {
            self.free(id.slot);
            self.pending -= 1;
            true
        } else {
            false
        }
    }

    /// True if the event is still pending.
    pub fn is_pending(&self, id: EventId) -> bool {
        matches!(self.slots.get(id.slot as usize), Some(Slot::Pending { seq, .. }) if *seq == id.seq)
    }

    /// Puts `slot` on the free list and returns what it held.
    fn free(&mut self, slot: u32) -> Slot<T> {
        let old = std::mem::replace(
            &mut self.slots[slot as usize],
            Slot::Free {
                next_free: self.free_head,
            },
        );
        self.free_head = slot;
        old
    }

    /// The time of the earliest pending event.
    #[inline]
    pub fn peek_time(&mut self) -> Option<SimTime> {
        let slots = &self.slots;
        let e = self.heap.peek(|e| is_live(slots, e))?;
        Some(SimTime::from_nanos(e.time))
    }

    /// Removes the earliest pending event and advances [`now`](Self::now) to its time.
    #[inline]
    pub fn pop(&mut self) -> Option<Popped<T>> {
        self.peek_time()?;
        let e = self.heap.pop_peeked()?;
        let Slot::Pending { seq, payload } = self.free(e.slot) else {
            unreachable!("a live entry's slot is pending")
        };
        self.pending -= 1;
        self.now = SimTime::from_nanos(e.time);
        Some(Popped {
            time: self.now,
            id: EventId { seq, slot: e.slot },
            payload,
        })
    }

    /// The pending events in firing order (for snapshots and inspection).
    pub fn pending_sorted(&self) -> Vec<(SimTime, EventId, &T)> {
        let mut v: Vec<_> = self
            .heap
            .iter()
            .filter_map(|e| match &self.slots[e.slot as usize] {
                Slot::Pending { seq, payload } if *seq == e.seq => Some((
                    SimTime::from_nanos(e.time),
                    EventId {
                        seq: e.seq,
                        slot: e.slot,
                    },
                    payload,
                )),
                _ => None,
            })
            .collect();
        v.sort_unstable_by_key(|(t, id, _)| (*t, id.seq));
        v
    }
}

#[cfg(test)]
mod tests {
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

    type State = (SimTime, u64, Vec<Entry>, Vec<Slot<u32>>, u32);

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
}
