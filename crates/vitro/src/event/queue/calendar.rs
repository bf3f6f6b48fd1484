//! The near-future tiers in front of the radix heap: a calendar of time buckets ("days") and
//! a short sorted list for the current day.
//!
//! Time is cut into days of `2^shift` nanoseconds. The entries of the current day sit in
//! `today`, a short list sorted on (time, seq) (a sorted run or a binary min-heap when events
//! crowd into one day). The entries of the next `days - 1` days sit unsorted in a ring of buckets (chunk
//! lists, one per day), and every later entry waits in the radix heap (`far`). A push is an
//! append to one of the three (an insertion for today). A pop takes today's minimum, the
//! list's last entry; when today is over, the next non-empty day (found in a two-level bitmap) is
//! sorted into `today`, and the far entries that the advancing window now covers move to
//! the ring. With the day width near the mean gap between events, a day holds a handful of
//! entries: a pop or a push is a few sequential memory accesses.
//!
//! Nothing ever degrades to a linear scan per operation: a crowded day is a run (every event
//! at the same instant: O(1) per event) or a binary heap, O(log n) per event; far-away events
//! go through the radix heap (at most 16 moves each). The day width and the number of days
//! are chosen from what the queue observes (mean gap between pops, mean distance of pushes
//! ahead of now) and revised at most once per `max(len, 64)` pops; a revision rebuilds the
//! tiers in O(len).

use super::radix::{BUCKETS, CHUNK, Entry, Head, NIL, RadixHeap};
use super::today::{BIN_BITS, Today};

/// Most days in the ring (the bitmap is 64 words and a one-word summary).
pub(super) const MAX_DAYS: usize = 4096;
/// Fewest days in the ring.
const MIN_DAYS: usize = 64;
/// Pending events per day: the ring has `len / EVENTS_PER_DAY` days (rounded to a power of two,
/// within the bounds above). The days are also made wide enough for the ring to span
/// [`SPAN_FACTOR`] mean hold distances, so a day of a steady queue holds about
/// `SPAN_FACTOR * EVENTS_PER_DAY` events (16.7 measured on the hold benchmark). On the hold
/// benchmark at 10^3 pending (cachegrind, per event), 4 makes 2.0 first-level misses and 0.64
/// mispredicted branches, against 2.3 and 1.0 with 2 (days of 8 events spread the same
/// entries over more chunks' cache lines); 8 makes days longer than a sorted list holds
/// (`today::SORTED_MAX`), sorted as a run: 1.6 mispredicts. (Without today's counting pass
/// before its insertion sort, 2 beats 1 and 4.)
const EVENTS_PER_DAY: usize = 4;
/// The ring should cover this many times the mean distance of pushes ahead of now (4 beats
/// 2, 8 and 16 on the hold benchmark: few events go through the far heap, days stay small).
const SPAN_FACTOR: u64 = 4;
/// Day width before anything was observed: about a millisecond.
const INITIAL_SHIFT: u32 = 20;

/// What the queue observed since the last revision of the day width.
#[derive(Clone, Debug, Default)]
struct Observed {
    /// Pops.
    pops: u64,
    /// Pushes.
    pushes: u64,
    /// Sum of how far ahead of now the pushes were (saturating).
    ahead: u64,
    /// The time of the first pop counted.
    since: u64,
}

/// The three tiers: today's list, the ring of days, the far radix heap.
///
/// Invariants: `today` holds the entries with time below `today_end`; ring bucket `d % days`
/// holds the entries of day `d` for `cur_day < d < cur_day + days` (time below `horizon`);
/// `far` holds the entries from `horizon` on. Bucket `cur_day % days` is empty.
#[derive(Clone, Debug)]
pub(super) struct Calendar {
    /// Log2 of the day width in nanoseconds.
    shift: u32,
    /// Days in the ring (a power of two).
    days: usize,
    /// The current day.
    cur_day: u64,
    /// Start of the next day: entries before it are in `today`.
    today_end: u128,
    /// End of the ring's window: entries from here on are in `far`.
    horizon: u128,
    today: Today,
    /// Days moved into `today` so far (a new day's entries are about to be read).
    pub(super) days_taken: u64,
    /// Bit `d % 64` of word `d / 64` is set iff ring bucket `d` is not empty.
    occupied: [u64; MAX_DAYS / 64],
    /// Bit `w` is set iff word `w` of `occupied` is not zero.
    summary: u64,
    /// The far entries; its chunk lists from [`BUCKETS`] on are the ring's days (one pool of
    /// chunks for both, so entries moving from far to near reuse the chunks they leave).
    far: RadixHeap,
    /// The time of far's minimum ([`NO_TIME`] when empty).
    far_min: u128,
    /// Entries in all tiers (stale ones included).
    len: usize,
    /// Entries at the last revision.
    len_at_revision: usize,
    observed: Observed,
}

/// Beyond every time.
const NO_TIME: u128 = u128::MAX;

/// The start of day `day + plus` (beyond the end of time for the last days).
#[inline(always)]
fn day_start(day: u64, plus: u64, shift: u32) -> u128 {
    (u128::from(day) + u128::from(plus)) << shift
}

impl Calendar {
    /// Empty tiers for keys from `now` on.
    pub(super) fn new(now: u64) -> Self {
        Self::with_layout(now, INITIAL_SHIFT, MIN_DAYS)
    }

    fn with_layout(now: u64, shift: u32, days: usize) -> Self {
        debug_assert!(days.is_power_of_two() && (MIN_DAYS..=MAX_DAYS).contains(&days));
        let cur_day = now >> shift;
        let horizon = day_start(cur_day, days as u64, shift);
        Calendar {
            shift,
            days,
            cur_day,
            today_end: day_start(cur_day, 1, shift),
            horizon,
            today: Today::default(),
            days_taken: 0,
            occupied: [0; MAX_DAYS / 64],
            summary: 0,
            // Keys from the horizon on (the first key of the last day if it is beyond time).
            far: RadixHeap::new(horizon.min(u128::from(u64::MAX)) << 64, MAX_DAYS),
            far_min: NO_TIME,
            len: 0,
            len_at_revision: 0,
            observed: Observed {
                since: now,
                ..Observed::default()
            },
        }
    }

    /// Number of entries (stale ones included).
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Adds an entry; its time must not be below the last popped one's.
    #[inline(always)]
    pub(super) fn push(&mut self, e: Entry, now: u64) {
        self.observed.pushes += 1;
        self.observed.ahead = self.observed.ahead.saturating_add(e.time - now);
        self.len += 1;
        self.place(e);
    }

    /// Puts an entry in its tier.
    #[inline(always)]
    fn place(&mut self, e: Entry) {
        let t = u128::from(e.time);
        if t < self.today_end {
            self.today.push(e);
        } else if t < self.horizon {
            self.append((e.time >> self.shift) as usize & (self.days - 1), e);
        } else {
            self.far_min = self.far_min.min(t);
            self.far.push(e);
        }
    }

    /// Stores `e` in ring bucket `b`.
    #[inline(always)]
    fn append(&mut self, b: usize, e: Entry) {
        self.far.store(BUCKETS + b, e);
        self.occupied[b / 64] |= 1 << (b % 64);
        self.summary |= 1 << (b / 64);
    }

    /// Moves the entries of ring bucket `b` into `today`. The bucket keeps its head chunk.
    fn take_bucket(&mut self, b: usize) {
        let Head { chunk: head, len } = self.far.heads[BUCKETS + b];
        if head == NIL {
            return;
        }
        self.far.heads[BUCKETS + b].len = 0;
        let w = &mut self.occupied[b / 64];
        *w &= !(1 << (b % 64));
        if *w == 0 {
            self.summary &= !(1 << (b / 64));
        }
        let (mut c, mut n) = (head, len);
        while c != NIL {
            let chunk = &mut self.far.chunks[c as usize];
            self.today.extend(&chunk.entries[..n as usize]);
            let next = std::mem::replace(&mut chunk.next, NIL);
            if c != head {
                self.far.free_chunk(c);
            }
            (c, n) = (next, CHUNK as u32);
        }
        self.today.settle(self.shift.saturating_sub(BIN_BITS));
        self.days_taken = self.days_taken.wrapping_add(1);
    }

    /// Today's entries, in no particular order.
    pub(super) fn today(&self) -> impl Iterator<Item = &Entry> {
        self.today.iter()
    }

    /// The first non-empty ring bucket at or after `from`, wrapping around.
    #[inline(always)]
    fn next_bucket(&self, from: usize) -> Option<usize> {
        if self.summary == 0 {
            return None;
        }
        let w = from / 64;
        let bits = self.occupied[w] & (!0u64 << (from % 64));
        if bits != 0 {
            return Some(w * 64 + bits.trailing_zeros() as usize);
        }
        let higher = self.summary & ((!0u64 << w) << 1);
        let w = if higher != 0 {
            higher.trailing_zeros() as usize
        } else {
            self.summary.trailing_zeros() as usize
        };
        Some(w * 64 + self.occupied[w].trailing_zeros() as usize)
    }

    /// Makes `day` the current day (it must not be before the current one, and every entry
    /// must be from that day on): moves its ring bucket into `today` and the far entries the
    /// window now covers into the ring.
    fn advance_to(&mut self, day: u64) {
        let mask = self.days - 1;
        if day - self.cur_day < self.days as u64 {
            self.take_bucket(day as usize & mask);
        }
        self.cur_day = day;
        self.today_end = day_start(day, 1, self.shift);
        self.horizon = day_start(day, self.days as u64, self.shift);
        while self.far_min < self.horizon {
            let Some(p) = self.far.min_pos() else {
                self.far_min = NO_TIME;
                break;
            };
            let e = self.far.take_min(p);
            self.place_near(e);
            self.far_min = match self.far.min_pos() {
                Some(p) => u128::from(self.far.get(p).time),
                None => NO_TIME,
            };
        }
    }

    /// Puts an entry below the horizon in `today` or the ring.
    #[inline(always)]
    fn place_near(&mut self, e: Entry) {
        if u128::from(e.time) < self.today_end {
            self.today.push(e);
        } else {
            self.append((e.time >> self.shift) as usize & (self.days - 1), e);
        }
    }

    /// The minimum entry, after dropping the stale entries before it (`live` tells them).
    #[inline(always)]
    pub(super) fn peek(&mut self, live: impl Fn(&Entry) -> bool) -> Option<&Entry> {
        loop {
            match self.today.peek() {
                Some(e) if live(e) => break,
                Some(_) => {
                    self.today.pop();
                    self.len -= 1;
                }
                None => self.next_day()?,
            }
        }
        self.today.peek()
    }

    /// Advances to the next day with an entry, once today is empty.
    #[inline(never)]
    fn next_day(&mut self) -> Option<()> {
        let mask = self.days - 1;
        let cur = self.cur_day as usize & mask;
        let day = match self.next_bucket((cur + 1) & mask) {
            Some(b) => self.cur_day + ((b.wrapping_sub(cur)) & mask) as u64,
            None if self.far_min != NO_TIME => (self.far_min >> self.shift) as u64,
            None => return None,
        };
        self.advance_to(day);
        Some(())
    }

    /// Removes the minimum found by [`peek`](Self::peek) (which must have returned it).
    #[inline(always)]
    pub(super) fn pop_peeked(&mut self) -> Option<Entry> {
        let e = self.today.pop()?;
        self.len -= 1;
        self.observed.pops += 1;
        if self.observed.pops >= self.len_at_revision.max(MIN_DAYS) as u64 {
            self.revise(e.time);
        }
        Some(e)
    }

    /// The layout the observations call for: (shift, days).
    fn wanted_layout(&self, now: u64) -> (u32, usize) {
        let o = &self.observed;
        let days = (self.len / EVENTS_PER_DAY)
            .next_power_of_two()
            .clamp(MIN_DAYS, MAX_DAYS);
        let gap = (now - o.since) / o.pops.max(1);
        let ahead = o.ahead / o.pushes.max(1);
        let width = gap
            .max(ahead.saturating_mul(SPAN_FACTOR) / days as u64)
            .max(1);
        // The power of two at or above the width.
        let shift = (64 - (width - 1).leading_zeros()).min(63);
        (shift, days)
    }

    /// Checks the layout against the observations and rebuilds the tiers if it is off by a
    /// factor of 4 in day width or if the number of days should change.
    #[inline(never)]
    fn revise(&mut self, now: u64) {
        let (shift, days) = self.wanted_layout(now);
        if days != self.days || shift.abs_diff(self.shift) >= 2 {
            self.rebuild(now, shift, days);
        }
        self.len_at_revision = self.len;
        self.observed = Observed {
            since: now,
            ..Observed::default()
        };
    }

    /// Lays out all entries anew, for times from `now` on.
    ///
    /// The far heap is kept when the new horizon is not below its last key (the usual case:
    /// the first revision widens the days); only the near entries are copied then.
    fn rebuild(&mut self, now: u64, shift: u32, days: usize) {
        let mut new = Self::with_layout(now, shift, days);
        let keep_far = new.horizon.min(u128::from(u64::MAX)) << 64 >= self.far.last;
        let entries: Vec<Entry> = if keep_far {
            let entries = self.near().copied().collect();
            self.far.clear_lists(BUCKETS..BUCKETS + self.days);
            new.far = std::mem::replace(&mut self.far, RadixHeap::new(0, MAX_DAYS));
            new.far_min = self.far_min;
            entries
        } else {
            self.iter().copied().collect()
        };
        new.observed = std::mem::take(&mut self.observed);
        new.len = self.len;
        new.len_at_revision = self.len;
        *self = new;
        for e in entries {
            self.place(e);
        }
        // Far entries the new window covers.
        let day = self.cur_day;
        self.advance_to(day);
    }

    /// All entries, in no particular order.
    pub(super) fn iter(&self) -> impl Iterator<Item = &Entry> {
        self.near().chain(self.far.iter())
    }

    /// The entries of today and of the ring, in no particular order.
    fn near(&self) -> impl Iterator<Item = &Entry> {
        let ring = (0..self.days).flat_map(move |b| {
            let Head { mut chunk, mut len } = self.far.heads[BUCKETS + b];
            std::iter::from_fn(move || {
                let c = self.far.chunks.get(chunk as usize)?;
                let item = &c.entries[..len as usize];
                chunk = c.next;
                len = CHUNK as u32;
                Some(item)
            })
            .flatten()
        });
        self.today.iter().chain(ring)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(time: u64, seq: u64) -> Entry {
        Entry { time, seq, slot: 0 }
    }

    impl Calendar {
        /// Checks the tier invariants.
        fn check(&self) {
            assert!(
                self.today
                    .iter()
                    .all(|e| u128::from(e.time) < self.today_end)
            );
            for b in 0..self.days {
                let Head { mut chunk, mut len } = self.far.heads[BUCKETS + b];
                let mut n = 0;
                while let Some(c) = self.far.chunks.get(chunk as usize) {
                    for e in &c.entries[..len as usize] {
                        let day = e.time >> self.shift;
                        assert!(day > self.cur_day && u128::from(e.time) < self.horizon);
                        assert_eq!(day as usize % self.days, b);
                        n += 1;
                    }
                    chunk = c.next;
                    len = CHUNK as u32;
                }
                assert_eq!(self.occupied[b / 64] >> (b % 64) & 1 == 1, n > 0);
            }
            assert!(self.far.iter().all(|e| u128::from(e.time) >= self.horizon));
            assert_eq!(
                self.far_min,
                self.far
                    .iter()
                    .map(|e| u128::from(e.time))
                    .min()
                    .unwrap_or(NO_TIME)
            );
            assert_eq!(self.iter().count(), self.len);
        }
    }

    /// Runs `pushes` (offsets from now, by number of pops so far) against a sorted reference
    /// and returns how many entries the tiers moved or compared, roughly: the heap depth is
    /// counted through `today`'s size at each pop, plus rebuild sizes.
    fn drive(n: usize, rounds: usize, mut offset: impl FnMut(usize) -> u64) -> u64 {
        let mut c = Calendar::new(0);
        let mut reference = std::collections::BTreeSet::new();
        let mut seq = 0;
        let mut now = 0;
        let mut work = 0u64;
        for i in 0..n {
            let e = entry(offset(i), seq);
            seq += 1;
            c.push(e, now);
            reference.insert(e.key());
        }
        for i in 0..rounds {
            let rebuilds_before = c.len_at_revision;
            let e = *c.peek(|_| true).unwrap();
            let e2 = c.pop_peeked().unwrap();
            assert_eq!(e, e2);
            assert_eq!(Some(e.key()), reference.pop_first());
            now = e.time;
            work += 1 + (usize::BITS - c.today.len().leading_zeros()) as u64;
            if c.len_at_revision != rebuilds_before {
                work += c.len as u64;
            }
            let f = entry(now.saturating_add(offset(n + i)), seq);
            seq += 1;
            c.push(f, now);
            reference.insert(f.key());
            if i % 997 == 0 {
                c.check();
            }
        }
        c.check();
        while let Some(&e) = c.peek(|_| true) {
            assert_eq!(c.pop_peeked(), Some(e));
            assert_eq!(Some(e.key()), reference.pop_first());
        }
        assert!(reference.is_empty());
        work
    }

    #[test]
    fn end_of_time() {
        // Days beyond the last representable time, with the narrowest and the widest days.
        for shift in [0, INITIAL_SHIFT, 63] {
            let now = u64::MAX - 100;
            let mut c = Calendar::with_layout(now, shift, MIN_DAYS);
            let times = [u64::MAX, now, u64::MAX - 1, now + 50, u64::MAX, now];
            for (seq, &t) in times.iter().enumerate() {
                c.push(entry(t, seq as u64), now);
            }
            c.check();
            let mut want: Vec<(u64, u64)> = times
                .iter()
                .enumerate()
                .map(|(seq, &t)| (t, seq as u64))
                .collect();
            want.sort_unstable();
            let mut got = Vec::new();
            while let Some(&e) = c.peek(|_| true) {
                assert_eq!(c.pop_peeked(), Some(e));
                got.push((e.time, e.seq));
                c.check();
            }
            assert_eq!(got, want, "shift {shift}");
        }
    }

    #[test]
    fn all_at_the_same_time_is_not_quadratic() {
        let n = 20_000;
        let work = drive(n, 4 * n, |_| 0);
        assert!(work < 40 * (5 * n) as u64, "{work}");
    }

    #[test]
    fn bimodal_is_not_quadratic() {
        let n = 20_000;
        let mut x = 12345u64;
        let work = drive(n, 4 * n, |_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if x >> 63 == 0 {
                x >> 54
            } else {
                (1 << 50) + (x >> 30)
            }
        });
        assert!(work < 40 * (5 * n) as u64, "{work}");
    }

    #[test]
    fn increasing_times_are_not_quadratic() {
        let n = 20_000;
        let work = drive(n, 4 * n, |i| i as u64 * 1000);
        assert!(work < 40 * (5 * n) as u64, "{work}");
        let work = drive(n, 4 * n, |i| (i as u64) << 30);
        assert!(work < 40 * (5 * n) as u64, "{work}");
    }

    #[test]
    fn spread_changes_are_followed() {
        // Dense, then sparse by a factor of 10^6, then dense again.
        let n = 5_000;
        let mut x = 99u64;
        let mut rand = move || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            x >> 44
        };
        let work = drive(n, 20 * n, |i| match (i / (6 * n)) % 3 {
            1 => rand() * 1_000_000,
            _ => rand(),
        });
        assert!(work < 40 * (21 * n) as u64, "{work}");
    }
}
