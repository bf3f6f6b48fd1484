//! The current day's entries of the calendar (module `calendar`): a short sorted list, or a
//! binary heap when events crowd into one day.

use super::radix::Entry;

/// Most entries `today` keeps as a sorted list; beyond, it turns into a binary heap.
pub(super) const SORTED_MAX: usize = 32;

/// Today's entries. A day holds a handful of entries: they are kept sorted, largest key
/// first, so that a pop takes the last one (no sift, no branch that depends on the keys) and
/// a push is an insertion from the end. When events crowd into one day (more than
/// [`SORTED_MAX`]), the list becomes a binary min-heap (an ascending list is one already):
/// O(log n) per operation, never a linear insertion per event. It is a sorted list again
/// once the day is empty.
#[derive(Clone, Debug, Default)]
pub(super) struct Today {
    v: Vec<Entry>,
    /// `v` is a binary min-heap (else it is sorted, largest key first).
    heap: bool,
}

impl Today {
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.v.len()
    }

    #[inline(always)]
    pub(super) fn peek(&self) -> Option<&Entry> {
        if self.heap {
            self.v.first()
        } else {
            self.v.last()
        }
    }

    pub(super) fn iter(&self) -> impl Iterator<Item = &Entry> {
        self.v.iter()
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: Entry) {
        if self.heap {
            self.heap_push(e);
        } else if self.v.len() < SORTED_MAX {
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
        } else {
            self.become_heap();
            self.heap_push(e);
        }
    }

    /// Appends entries in no order; [`settle`](Self::settle) must follow before any other use.
    #[inline(always)]
    pub(super) fn extend(&mut self, es: &[Entry]) {
        self.v.extend_from_slice(es);
    }

    /// Restores the order after [`extend`](Self::extend): an insertion sort while the list is
    /// short, else a heap (the list sorted in ascending order).
    #[inline]
    pub(super) fn settle(&mut self) {
        if !self.heap && self.v.len() <= SORTED_MAX {
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
            self.heap = true;
        }
    }

    /// Turns the sorted list into a min-heap: ascending order is heap order.
    #[cold]
    #[inline(never)]
    fn become_heap(&mut self) {
        self.v.reverse();
        self.heap = true;
    }

    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<Entry> {
        if self.heap {
            let top = self.heap_pop();
            self.heap = !self.v.is_empty();
            top
        } else {
            self.v.pop()
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

    /// Pops everything, checking the order against `reference` (sorted keys).
    fn drain(t: &mut Today, reference: &mut std::collections::BTreeSet<u128>) {
        while let Some(&e) = t.peek() {
            assert_eq!(t.pop(), Some(e));
            assert_eq!(Some(e.key()), reference.pop_first());
        }
        assert!(reference.is_empty());
        assert!(!t.heap, "an empty day is a sorted list again");
    }

    #[test]
    fn a_short_day_is_a_sorted_list_and_a_crowded_one_a_heap() {
        let mut x = 7u64;
        let mut rand = move || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            x >> 54
        };
        for n in [1, 5, SORTED_MAX, SORTED_MAX + 1, 3 * SORTED_MAX] {
            // Filled in bulk (a day taken from the ring), then pushes and pops interleaved.
            let mut t = Today::default();
            let mut reference = std::collections::BTreeSet::new();
            let bulk: Vec<Entry> = (0..n as u64).map(|s| entry(rand(), s)).collect();
            t.extend(&bulk);
            t.settle();
            reference.extend(bulk.iter().map(Entry::key));
            assert_eq!(t.heap, n > SORTED_MAX, "{n} entries");
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
    fn pushes_beyond_the_bound_turn_the_list_into_a_heap() {
        let mut t = Today::default();
        let mut reference = std::collections::BTreeSet::new();
        // Every push at one instant: later sequence numbers, larger keys.
        for s in 0..=SORTED_MAX as u64 {
            assert!(!t.heap, "{s} entries");
            t.push(entry(5, s));
            reference.insert(entry(5, s).key());
        }
        assert!(t.heap);
        drain(&mut t, &mut reference);
    }
}
