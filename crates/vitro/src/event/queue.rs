//! The pending-event set: a priority queue ordered by (time, scheduling sequence).
//!
//! Events at equal time pop in the order they were pushed (FIFO), always. Payloads are stored
//! inline (no box per event); cancellation is O(1) through the [`EventId`] handle.

use crate::time::SimTime;
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

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct Key {
    time: u64,
    seq: u64,
    slot: u32,
}

impl Key {
    #[inline(always)]
    fn before(&self, o: &Key) -> bool {
        (self.time, self.seq) < (o.time, o.seq)
    }
}

/// Arity of the implicit heap: a 4-ary heap halves the depth of a binary one and keeps a
/// node's children together in memory.
const D: usize = 4;

/// An implicit D-ary min-heap of keys.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(transparent)]
struct Heap(Vec<Key>);

impl Heap {
    fn with_capacity(n: usize) -> Self {
        Heap(Vec::with_capacity(n))
    }
    fn peek(&self) -> Option<&Key> {
        self.0.first()
    }
    fn iter(&self) -> impl Iterator<Item = &Key> {
        self.0.iter()
    }
    fn push(&mut self, k: Key) {
        let v = &mut self.0;
        let mut i = v.len();
        v.push(k);
        while i > 0 {
            let parent = (i - 1) / D;
            if !k.before(&v[parent]) {
                break;
            }
            v[i] = v[parent];
            i = parent;
        }
        v[i] = k;
    }
    fn pop(&mut self) -> Option<Key> {
        let v = &mut self.0;
        let last = v.pop()?;
        if v.is_empty() {
            return Some(last);
        }
        let top = v[0];
        let n = v.len();
        let mut i = 0;
        loop {
            let first = i * D + 1;
            if first >= n {
                break;
            }
            let end = (first + D).min(n);
            let mut best = first;
            for c in first + 1..end {
                if v[c].before(&v[best]) {
                    best = c;
                }
            }
            if !v[best].before(&last) {
                break;
            }
            v[i] = v[best];
            i = best;
        }
        v[i] = last;
        Some(top)
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
enum Slot<T> {
    Free { next_free: u32 },
    Pending { seq: u64, payload: T },
    Cancelled { seq: u64 },
}

/// A priority queue of events keyed by (time, sequence).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EventQueue<T> {
    heap: Heap,
    slots: Vec<Slot<T>>,
    free_head: u32,
    next_seq: u64,
    now: SimTime,
    pending: usize,
}

const NO_FREE: u32 = u32::MAX;

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

    /// An empty queue with room for `n` pending events.
    pub fn with_capacity(n: usize) -> Self {
        EventQueue {
            heap: Heap::with_capacity(n),
            slots: Vec::with_capacity(n),
            free_head: NO_FREE,
            next_seq: 0,
            now: SimTime::ZERO,
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
    pub fn push(&mut self, at: SimTime, payload: T) -> Result<EventId, ScheduleError> {
        if at < self.now {
            return Err(ScheduleError::InThePast { at, now: self.now });
        }
        let seq = self.next_seq;
        self.next_seq += 1;
        let slot = if self.free_head != NO_FREE {
            let s = self.free_head;
            self.free_head = match self.slots[s as usize] {
                Slot::Free { next_free } => next_free,
                _ => unreachable!("free list points at a used slot"),
            };
            self.slots[s as usize] = Slot::Pending { seq, payload };
            s
        } else {
            let s = u32::try_from(self.slots.len()).expect("more than 2^32-1 pending events");
            self.slots.push(Slot::Pending { seq, payload });
            s
        };
        self.heap.push(Key {
            time: at.as_nanos(),
            seq,
            slot,
        });
        self.pending += 1;
        Ok(EventId { seq, slot })
    }

    /// Cancels a pending event. Returns false if it already fired or was cancelled.
    pub fn cancel(&mut self, id: EventId) -> bool {
        match self.slots.get(id.slot as usize) {
            Some(Slot::Pending { seq, .. }) if *seq == id.seq => {
                self.slots[id.slot as usize] = Slot::Cancelled { seq: id.seq };
                self.pending -= 1;
                true
            }
            _ => false,
        }
    }

    /// True if the event is still pending.
    pub fn is_pending(&self, id: EventId) -> bool {
        matches!(self.slots.get(id.slot as usize), Some(Slot::Pending { seq, .. }) if *seq == id.seq)
    }

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

    fn drop_cancelled_top(&mut self) {
        while let Some(k) = self.heap.peek() {
            if matches!(self.slots[k.slot as usize], Slot::Cancelled { .. }) {
                let slot = k.slot;
                self.heap.pop();
                self.free(slot);
            } else {
                break;
            }
        }
    }

    /// The time of the earliest pending event.
    pub fn peek_time(&mut self) -> Option<SimTime> {
        self.drop_cancelled_top();
        self.heap.peek().map(|k| SimTime::from_nanos(k.time))
    }

    /// Removes the earliest pending event and advances [`now`](Self::now) to its time.
    pub fn pop(&mut self) -> Option<Popped<T>> {
        loop {
            let k = self.heap.pop()?;
            match self.free(k.slot) {
                Slot::Pending { seq, payload } => {
                    self.pending -= 1;
                    self.now = SimTime::from_nanos(k.time);
                    return Some(Popped {
                        time: self.now,
                        id: EventId { seq, slot: k.slot },
                        payload,
                    });
                }
                Slot::Cancelled { .. } => continue,
                Slot::Free { .. } => unreachable!("heap key points at a free slot"),
            }
        }
    }

    /// The pending events in firing order (for snapshots and inspection).
    pub fn pending_sorted(&self) -> Vec<(SimTime, EventId, &T)> {
        let mut v: Vec<_> = self
            .heap
            .iter()
            .filter_map(|k| match &self.slots[k.slot as usize] {
                Slot::Pending { seq, payload } => Some((
                    SimTime::from_nanos(k.time),
                    EventId {
                        seq: *seq,
                        slot: k.slot,
                    },
                    payload,
                )),
                _ => None,
            })
            .collect();
        v.sort_by_key(|(t, id, _)| (*t, id.seq));
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
