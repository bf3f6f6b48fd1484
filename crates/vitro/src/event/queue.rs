//! The pending-event set: a priority queue ordered by (time, scheduling sequence).
//!
//! Events at equal time pop in the order they were pushed (FIFO), always. Payloads are stored
//! inline in a slab (no box per event); cancellation is O(1) through the [`EventId`] handle.
//!
//! # How it works
//!
//! Entries are keyed by the 128-bit `(time << 64) | seq`, so equal times pop in push order.
//! They live in three tiers (module `calendar`): the current *day* (a span of `2^k`
//! nanoseconds, about the mean gap between events) in a short list sorted by key, largest
//! first; the next days, up to a horizon a few mean hold times ahead, unsorted in a ring of
//! day buckets (a calendar queue, Brown 1988); and the events beyond the horizon in a monotone
//! radix heap. A push is an append to its tier (an insertion for the current day); a pop takes
//! the day list's last entry and, when the day is over, sorts the next non-empty day (found in
//! a two-level bitmap) into the list and moves the far events the window now covers from the
//! radix heap to the ring. The day width and count follow the observed gaps and hold
//! distances, revised at most once per `len` pops (a revision is O(len)). A crowded day
//! becomes a sorted run read from a moving head (events due at one instant arrive in key
//! order: O(1) each), and a binary heap once a push breaks the order: O(log n) per event,
//! never a linear scan.
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
mod today;

use crate::time::SimTime;
use calendar::Calendar;
use radix::{Entry, InvalidState};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
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
    /// Shuffled ties: the generator and the rest of the current batch of equal-time events
    /// (fired from the end); `None`: first pushed, first out.
    ties: Option<Box<Ties>>,
}

/// The state of shuffled ties ([`EventQueue::shuffle_ties`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Ties {
    rng: ChaCha8Rng,
    /// The current batch, in reverse firing order (cancelled entries are skipped).
    batch: Vec<Entry>,
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
        let ties = self.ties.as_ref().map(|t| Ties {
            rng: t.rng.clone(),
            batch: t
                .batch
                .iter()
                .filter(|e| is_live(&self.slots, e))
                .copied()
                .collect(),
        });
        let mut st = s.serialize_struct("EventQueue", 6)?;
        st.serialize_field("now", &self.now)?;
        st.serialize_field("next_seq", &self.next_seq)?;
        st.serialize_field("events", &events)?;
        st.serialize_field("slots", &self.slots)?;
        st.serialize_field("free_head", &self.free_head)?;
        st.serialize_field("ties", &ties)?;
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
    ties: Option<Ties>,
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
        // The current batch of shuffled ties: at the current time, each its slot's event.
        for e in s.ties.iter().flat_map(|t| &t.batch) {
            if e.time != s.now.as_nanos() || e.seq >= s.next_seq {
                return Err(InvalidState("tied event out of range"));
            }
            if !is_live(&s.slots, e) || std::mem::replace(&mut covered[e.slot as usize], true) {
                return Err(InvalidState("tied event does not match its slot"));
            }
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
        let batch = s.ties.as_ref().map_or(0, |t| t.batch.len());
        Ok(EventQueue {
            now: s.now,
            next_seq: s.next_seq,
            pending: heap.len() + batch,
            heap,
            slots: s.slots,
            free_head: s.free_head,
            ties: s.ties.map(Box::new),
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
            ties: None,
        }
    }

    /// From now on, events due at the same time fire in a random order drawn from a
    /// generator seeded with `seed` (instead of first pushed, first out): each time the queue
    /// reaches a new batch of equal-time events it shuffles the whole batch; events pushed
    /// for the current time while a batch fires make the next batch. A check that an outcome
    /// is not an artefact of the order agents were registered or scheduled in (MASON's
    /// shuffled ordering).
    ///
    /// ```
    /// use vitro::event::EventQueue;
    /// use vitro::time::SimTime;
    /// let order = |seed| {
    ///     let mut q = EventQueue::new();
    ///     q.shuffle_ties(seed);
    ///     for i in 0..8 { q.push(SimTime::from_secs(1), i).unwrap(); }
    ///     q.push(SimTime::from_secs(2), 8).unwrap();
    ///     std::iter::from_fn(|| q.pop().map(|p| p.payload)).collect::<Vec<_>>()
    /// };
    /// let a = order(1);
    /// assert_eq!(a, order(1));                  // the same seed, the same order
    /// assert_ne!(a[..8], [0, 1, 2, 3, 4, 5, 6, 7]); // not the push order
    /// assert_eq!(a[8], 8);                      // later events still fire later
    /// ```
    pub fn shuffle_ties(&mut self, seed: u64) {
        self.ties = Some(Box::new(Ties {
            rng: ChaCha8Rng::seed_from_u64(seed),
            batch: Vec::new(),
        }));
    }

    /// True if equal-time events fire in a shuffled order ([`shuffle_ties`](Self::shuffle_ties)).
    pub fn ties_shuffled(&self) -> bool {
        self.ties.is_some()
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
            // The old value is matched, not dropped: nothing to check for a drop.
            let Slot::Free { next_free } = std::mem::replace(cell, pending) else {
                unreachable!("the free list links only free slots")
            };
            self.free_head = next_free;
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

    /// The payload of a pending event; `None` if it already fired or was cancelled.
    pub fn get(&self, id: EventId) -> Option<&T> {
        match self.slots.get(id.slot as usize) {
            Some(Slot::Pending { seq, payload, .. }) if *seq == id.seq => Some(payload),
            _ => None,
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
        if let Some(t) = &mut self.ties {
            let slots = &self.slots;
            while t.batch.last().is_some_and(|e| !is_live(slots, e)) {
                t.batch.pop();
            }
            if !t.batch.is_empty() {
                return Some(self.now);
            }
        }
        let slots = &self.slots;
        let taken = self.heap.days_taken;
        let t = self.heap.peek(|e| is_live(slots, e))?.time;
        if self.heap.days_taken != taken {
            for e in self.heap.today() {
                // The day's events are read in the next pops: their slots, scattered over
                // the slab, start loading now (hold at 10^3 pending: +2-3 %).
                let slot = slots.as_ptr().wrapping_add(e.slot as usize);
                crate::hint::prefetch(slot, size_of::<Slot<T>>());
            }
        }
        Some(SimTime::from_nanos(t))
    }

    /// The next entry of the batch of shuffled ties, making a new batch (every live entry
    /// at the earliest time, shuffled) when the last is done.
    fn next_tied(&mut self) -> Option<Entry> {
        self.peek_time()?;
        let Some(ties) = self.ties.as_mut() else {
            return self.heap.pop_peeked();
        };
        if ties.batch.is_empty() {
            let first = self.heap.pop_peeked()?;
            ties.batch.push(first);
            loop {
                let slots = &self.slots;
                match self.heap.peek(|e| is_live(slots, e)) {
                    Some(e) if e.time == first.time => {}
                    _ => break,
                }
                ties.batch.extend(self.heap.pop_peeked());
            }
            // Fisher-Yates, from the end (the batch fires from its end).
            for i in (1..ties.batch.len()).rev() {
                let j = ties.rng.random_range(0..=i);
                ties.batch.swap(i, j);
            }
        }
        ties.batch.pop()
    }

    /// Removes the earliest pending event and advances [`now`](Self::now) to its time.
    #[inline]
    pub fn pop(&mut self) -> Option<Popped<T>> {
        let e = if self.ties.is_some() {
            self.next_tied()?
        } else {
            self.peek_time()?;
            self.heap.pop_peeked()?
        };
        Some(self.take(e))
    }

    /// [`pop`](Self::pop) right after [`peek_time`](Self::peek_time) returned a time, with
    /// nothing pushed, popped or cancelled in between: the same event, without looking for
    /// it again.
    #[inline]
    pub(crate) fn pop_peeked(&mut self) -> Option<Popped<T>> {
        if self.ties.is_some() {
            return self.pop();
        }
        let e = self.heap.pop_peeked()?;
        Some(self.take(e))
    }

    /// Frees the slot of the live entry `e` and returns its event, now current.
    #[inline(always)]
    fn take(&mut self, e: Entry) -> Popped<T> {
        let Slot::Pending { seq, payload } = self.free(e.slot) else {
            unreachable!("a live entry's slot is pending")
        };
        self.pending -= 1;
        self.now = SimTime::from_nanos(e.time);
        Popped {
            time: self.now,
            id: EventId { seq, slot: e.slot },
            payload,
        }
    }

    /// The pending events in firing order (for snapshots and inspection): with shuffled
    /// ties, the rest of the current batch first, in the order it fires.
    pub fn pending_sorted(&self) -> Vec<(SimTime, EventId, &T)> {
        let event = |e: &Entry| match &self.slots[e.slot as usize] {
            Slot::Pending { seq, payload } if *seq == e.seq => Some((
                SimTime::from_nanos(e.time),
                EventId {
                    seq: e.seq,
                    slot: e.slot,
                },
                payload,
            )),
            _ => None,
        };
        let mut v: Vec<_> = self.heap.iter().filter_map(event).collect();
        v.sort_unstable_by_key(|(t, id, _)| (*t, id.seq));
        match &self.ties {
            Some(t) if !t.batch.is_empty() => {
                t.batch.iter().rev().filter_map(event).chain(v).collect()
            }
            _ => v,
        }
    }
}

#[cfg(test)]
mod tests;
