//! The current day's entries of the calendar (module `calendar`): a short sorted list, a
//! sorted run when events crowd into one instant, or a binary heap.

use super::radix::Entry;

/// Most entries `today` keeps as a sorted list; beyond, it turns into a run or a heap.
pub(super) const SORTED_MAX: usize = 32;

/// How [`Today`] holds its entries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Mode {
    /// Sorted, largest key first: a pop takes the last entry.
    #[default]
    List,
    /// `v[head..]` sorted, smallest key first: a pop takes the entry at `head`; a push of a
    /// key above every other is an append.
    Run,
    /// A binary min-heap.
    Heap,
}

/// Today's entries. A day holds a handful of entries: they are kept sorted, largest key
/// first, so that a pop takes the last one (no sift, no branch that depends on the keys) and
/// a push is an insertion from the end. When events crowd into one day (more than
/// [`SORTED_MAX`]) it becomes a *run*, the entries in ascending order read from a moving
/// head: events due at one instant (a thousand agents' timers at the same second) arrive in
/// ascending order, as their sequence numbers do, so each push is an append and each pop a
/// read, O(1). The first push that would break the order turns the run into a binary
/// min-heap (an ascending list is one already): O(log n) per operation from then on, never
/// a linear insertion per event. It is a sorted list again once the day is empty.
#[derive(Clone, Debug, Default)]
pub(super) struct Today {
    v: Vec<Entry>,
    /// Where the run starts (0 unless `mode` is [`Mode::Run`]).
    head: usize,
    mode: Mode,
    /// Room for [`bin_by_time`](Self::bin_by_time)'s output (kept, to allocate once).
    scratch: Vec<Entry>,
}

/// Bins of the counting pass that orders a new day before its insertion sort: `2^BIN_BITS`.
pub(super) const BIN_BITS: u32 = 6;
const BINS: usize = 1 << BIN_BITS;
const _: () = assert!(SORTED_MAX < u8::MAX as usize, "bin offsets are bytes");
const _: () = assert!(BINS.is_multiple_of(8), "bins go eight to a word");

/// Turns the bins' counts into where each bin starts when the bins go largest first: bin `b`
/// gets the sum of the counts of the bins above it. Eight bins at once, as the bytes of a word
/// (a multiplication by `0x0101…01` sums each byte with the bytes below it; the sums stay
/// below 256: at most [`SORTED_MAX`] entries).
#[inline(always)]
fn bins_to_offsets(at: &mut [u8; BINS]) {
    const ONES: u64 = 0x0101_0101_0101_0101;
    let mut above = 0u64;
    for w in at.chunks_exact_mut(8).rev() {
        let counts = u64::from_le_bytes([w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7]]);
        // Byte i: the counts of bytes 0..=i; the top byte: the word's total.
        let upto = counts.wrapping_mul(ONES);
        let total = upto >> 56;
        // Byte i: the counts of bytes above i in this word, plus every higher word's.
        let starts = (total * ONES - upto) + above * ONES;
        w.copy_from_slice(&starts.to_le_bytes());
        above += total;
    }
}

/// A run drops the entries it has taken once they are this many and at least half of it.
const RUN_COMPACT: usize = 64;

impl Today {
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.v.len() - self.head
    }

    #[inline(always)]
    pub(super) fn peek(&self) -> Option<&Entry> {
        match self.mode {
            Mode::List => self.v.last(),
            Mode::Run => self.v.get(self.head),
            Mode::Heap => self.v.first(),
        }
    }

    pub(super) fn iter(&self) -> impl Iterator<Item = &Entry> {
        self.v[self.head..].iter()
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: Entry) {
        match self.mode {
            Mode::List if self.v.len() < SORTED_MAX => {
                // Insertion from the end (the smallest keys).
                let k = e.key();
                let mut i = self.v.len();
                self.v.push(e);
                let v = &mut self.v[..];
                while i > 0 && v[i - 1].key() < k {
                    v[i] = v[i - 1];
                    i -= 1;
                }
                v[i] = e;
            }
            Mode::List => {
                self.become_run();
                self.run_push(e);
            }
            Mode::Run => self.run_push(e),
            Mode::Heap => self.heap_push(e),
        }
    }

    /// Appends entries in no order; [`settle`](Self::settle) must follow before any other use.
    #[inline(always)]
    pub(super) fn extend(&mut self, es: &[Entry]) {
        self.compact();
        self.v.extend_from_slice(es);
    }

    /// Restores the order after [`extend`](Self::extend): while the list is short, a counting
    /// pass on bits `bin_shift..bin_shift + BIN_BITS` of the times, then an insertion sort;
    /// else a run (the entries sorted in ascending order).
    ///
    /// The counting pass helps when the entries are of one day (their times equal from bit
    /// `bin_shift + BIN_BITS` up); the insertion sort makes the order right in any case.
    #[inline]
    pub(super) fn settle(&mut self, bin_shift: u32) {
        if self.mode == Mode::List && self.v.len() <= SORTED_MAX {
            if self.v.len() > 2 {
                self.bin_by_time(bin_shift);
            }
            // Nearly in order after the counting pass: most entries stay where they are, so
            // the loop's exit is predicted (sorting a day of random times in one insertion
            // sort mispredicted about once per entry).
            let v = &mut self.v[..];
            for i in 1..v.len() {
                let e = v[i];
                let k = e.key();
                let mut j = i;
                while j > 0 && v[j - 1].key() < k {
                    v[j] = v[j - 1];
                    j -= 1;
                }
                v[j] = e;
            }
        } else {
            self.v.sort_unstable_by_key(Entry::key);
            self.mode = Mode::Run;
        }
    }

    /// Orders the entries by bin, `(time >> bin_shift) % BINS`, largest first, keeping their
    /// order within a bin: a counting sort, with no branch that depends on the times.
    fn bin_by_time(&mut self, bin_shift: u32) {
        let bin = |e: &Entry| (e.time >> bin_shift) as usize % BINS;
        // Counts, then where each bin's next entry goes (bins descending).
        let mut at = [0u8; BINS];
        for e in &self.v {
            at[bin(e)] += 1;
        }
        bins_to_offsets(&mut at);
        self.scratch.clear();
        self.scratch.resize(self.v.len(), Entry::ZERO);
        for e in &self.v {
            let b = &mut at[bin(e)];
            self.scratch[usize::from(*b)] = *e;
            *b += 1;
        }
        std::mem::swap(&mut self.v, &mut self.scratch);
    }

    /// Turns the sorted list into a run: the same entries, ascending.
    #[cold]
    #[inline(never)]
    fn become_run(&mut self) {
        self.v.reverse();
        self.mode = Mode::Run;
    }

    /// A push onto the run: an append if `e` is above every entry, else the run becomes a
    /// heap (ascending order is heap order) and takes `e` as one.
    #[inline]
    fn run_push(&mut self, e: Entry) {
        if self.v.last().is_none_or(|last| last.key() < e.key()) {
            self.v.push(e);
        } else {
            self.compact();
            self.mode = Mode::Heap;
            self.heap_push(e);
        }
    }

    /// Drops the entries a run has taken.
    fn compact(&mut self) {
        if self.head > 0 {
            self.v.drain(..self.head);
            self.head = 0;
        }
    }

    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<Entry> {
        match self.mode {
            Mode::List => self.v.pop(),
            Mode::Run => {
                let e = *self.v.get(self.head)?;
                self.head += 1;
                if self.head == self.v.len() {
                    self.v.clear();
                    self.head = 0;
                    self.mode = Mode::List;
                } else if self.head >= RUN_COMPACT && 2 * self.head >= self.v.len() {
                    self.compact();
                }
                Some(e)
            }
            Mode::Heap => {
                let top = self.heap_pop();
                if self.v.is_empty() {
                    self.mode = Mode::List;
                }
                top
            }
        }
    }

    #[inline]
    fn heap_push(&mut self, e: Entry) {
        let mut i = self.v.len();
        self.v.push(e);
        let k = e.key();
        let v = &mut self.v[..];
        while i > 0 {
            let parent = (i - 1) / 2;
            if v[parent].key() <= k {
                break;
            }
            v[i] = v[parent];
            i = parent;
        }
        v[i] = e;
    }

    #[inline]
    fn heap_pop(&mut self) -> Option<Entry> {
        let last = self.v.pop()?;
        let Some(&top) = self.v.first() else {
            return Some(last);
        };
        // Sift `last` down from the root.
        let v = &mut self.v[..];
        let n = v.len();
        let k = last.key();
        let mut i = 0;
        loop {
            let mut child = 2 * i + 1;
            if child >= n {
                break;
            }
            if child + 1 < n && v[child + 1].key() < v[child].key() {
                child += 1;
            }
            if k <= v[child].key() {
                break;
            }
            v[i] = v[child];
            i = child;
        }
        v[i] = last;
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(time: u64, seq: u64) -> Entry {
        Entry { time, seq, slot: 0 }
    }

    /// A 64-bit linear congruential generator from `seed`: the top `bits` bits of each state.
    fn lcg(seed: u64, bits: u32) -> impl FnMut() -> u64 {
        let mut x = seed;
        move || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            x >> (64 - bits)
        }
    }

    /// Pops everything, checking the order against `reference` (sorted keys).
    fn drain(t: &mut Today, reference: &mut std::collections::BTreeSet<u128>) {
        while let Some(&e) = t.peek() {
            assert_eq!(t.pop(), Some(e));
            assert_eq!(Some(e.key()), reference.pop_first());
        }
        assert!(reference.is_empty());
        assert_eq!(t.mode, Mode::List, "an empty day is a sorted list again");
    }

    #[test]
    fn a_short_day_is_a_sorted_list_and_a_crowded_one_a_run_or_a_heap() {
        let mut rand = lcg(7, 10);
        for n in [1, 5, SORTED_MAX, SORTED_MAX + 1, 3 * SORTED_MAX] {
            // Filled in bulk (a day taken from the ring), then pushes and pops interleaved.
            let mut t = Today::default();
            let mut reference = std::collections::BTreeSet::new();
            let bulk: Vec<Entry> = (0..n as u64).map(|s| entry(rand(), s)).collect();
            t.extend(&bulk);
            t.settle(0);
            reference.extend(bulk.iter().map(Entry::key));
            let want = if n > SORTED_MAX {
                Mode::Run
            } else {
                Mode::List
            };
            assert_eq!(t.mode, want, "{n} entries");
            for s in 0..4 * n as u64 {
                if s % 3 == 2 {
                    let e = *t.peek().unwrap();
                    assert_eq!(t.pop(), Some(e));
                    assert_eq!(Some(e.key()), reference.pop_first());
                } else {
                    let e = entry(rand(), 1000 + s);
                    t.push(e);
                    reference.insert(e.key());
                }
                assert_eq!(t.len(), reference.len());
            }
            drain(&mut t, &mut reference);
        }
    }

    #[test]
    fn bin_offsets_are_the_counts_of_the_bins_above() {
        let mut rand = lcg(5, 6);
        for round in 0..200 {
            let mut counts = [0u8; BINS];
            // Up to SORTED_MAX entries, spread at random (or crowded into the top two bins).
            let n = round % (SORTED_MAX + 1);
            for i in 0..n {
                let b = if round % 7 == 0 {
                    BINS - 1 - i % 2
                } else {
                    rand() as usize
                };
                counts[b] += 1;
            }
            let mut at = counts;
            bins_to_offsets(&mut at);
            for b in 0..BINS {
                let above: usize = counts[b + 1..].iter().map(|&c| usize::from(c)).sum();
                assert_eq!(usize::from(at[b]), above, "bin {b} of {counts:?}");
            }
        }
    }

    #[test]
    fn a_day_is_binned_by_time_then_sorted() {
        let mut rand = lcg(11, 23); // a time within a day of 2^23 ns
        let (shift, day) = (23, 977u64);
        let bin_shift = shift - BIN_BITS;
        for n in [3, 8, 17, SORTED_MAX] {
            let mut t = Today::default();
            let bulk: Vec<Entry> = (0..n as u64)
                .map(|s| entry((day << shift) | rand(), s))
                .collect();
            t.extend(&bulk);
            t.bin_by_time(bin_shift);
            // Bins descending, and within a bin the order the entries came in.
            let bins: Vec<u64> = t.v.iter().map(|e| e.time >> bin_shift).collect();
            assert!(bins.windows(2).all(|w| w[0] >= w[1]), "{bins:?}");
            for w in t.v.windows(2) {
                if w[0].time >> bin_shift == w[1].time >> bin_shift {
                    assert!(w[0].seq < w[1].seq);
                }
            }
            let mut t = Today::default();
            t.extend(&bulk);
            t.settle(bin_shift);
            let mut reference: std::collections::BTreeSet<u128> =
                bulk.iter().map(Entry::key).collect();
            assert_eq!(t.mode, Mode::List);
            drain(&mut t, &mut reference);
        }
    }

    #[test]
    fn pushes_at_one_instant_beyond_the_bound_make_a_run() {
        let mut t = Today::default();
        let mut reference = std::collections::BTreeSet::new();
        // Every push at one instant: later sequence numbers, larger keys.
        for s in 0..=SORTED_MAX as u64 {
            assert_eq!(t.mode, Mode::List, "{s} entries");
            t.push(entry(5, s));
            reference.insert(entry(5, s).key());
        }
        assert_eq!(t.mode, Mode::Run);
        drain(&mut t, &mut reference);
    }

    #[test]
    fn a_run_takes_appends_in_place_and_an_earlier_key_makes_it_a_heap() {
        let mut t = Today::default();
        let mut reference = std::collections::BTreeSet::new();
        let bulk: Vec<Entry> = (0..100).rev().map(|s| entry(5, s)).collect();
        t.extend(&bulk);
        t.settle(0);
        reference.extend(bulk.iter().map(Entry::key));
        // A stream of events at one instant: each fired one schedules the next, for long.
        for s in 100..10_000 {
            let e = *t.peek().unwrap();
            assert_eq!(t.pop(), Some(e));
            assert_eq!(Some(e.key()), reference.pop_first());
            t.push(entry(5, s));
            reference.insert(entry(5, s).key());
            assert_eq!(t.mode, Mode::Run);
            // What it has taken is dropped: memory follows the entries, not the pops.
            assert!(
                t.v.len() <= 2 * RUN_COMPACT.max(t.len()),
                "{} held",
                t.v.len()
            );
        }
        // An event before the last one (a later instant is already there): a heap now.
        t.push(entry(6, 20_000));
        reference.insert(entry(6, 20_000).key());
        t.push(entry(5, 20_001));
        reference.insert(entry(5, 20_001).key());
        assert_eq!(t.mode, Mode::Heap);
        assert_eq!(t.len(), reference.len());
        drain(&mut t, &mut reference);
    }
}
