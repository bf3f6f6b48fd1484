//! The radix heap under the event queue: entries keyed by (time, sequence), in buckets by the
//! highest digit in which a key differs from the last one popped, each bucket a chain of
//! fixed-size chunks.

use serde::{Deserialize, Serialize};

/// A scheduled event as the radix heap holds it: its key and the slab slot of its payload.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(super) struct Entry {
    pub(super) time: u64,
    pub(super) seq: u64,
    pub(super) slot: u32,
}

impl Entry {
    /// A placeholder for unused chunk space.
    pub(super) const ZERO: Entry = Entry {
        time: 0,
        seq: 0,
        slot: 0,
    };

    /// The ordering key: time, then sequence.
    #[inline(always)]
    pub(super) fn key(&self) -> u128 {
        (u128::from(self.time) << 64) | u128::from(self.seq)
    }
}

/// Width of a digit of the key: entries are bucketed by their highest digit that differs from
/// `last`, and by that digit's value. Measured on the hold benchmark: 8 beats 1, 2 and 4 (fewer
/// moves per entry) at 10^3 and at 10^6 pending events.
pub(super) const DIGIT_BITS: u32 = 8;

/// Values of a digit.
pub(super) const RADIX: usize = 1 << DIGIT_BITS;

/// Buckets: one per (digit position, digit value).
pub(super) const BUCKETS: usize = (128 / DIGIT_BITS as usize) * RADIX;

/// Words of the bucket occupancy bitmap.
pub(super) const WORDS: usize = BUCKETS / 64;

/// The bucket of `key` relative to `last`: (position of the highest digit in which they differ,
/// the value of that digit in `key`), numbered so that lower buckets hold smaller keys.
/// A key equal to `last` falls in bucket `last & (RADIX - 1)`, which no other key shares.
#[inline(always)]
pub(super) fn bucket_of(key: u128, last: u128) -> usize {
    let pos = (127 - ((key ^ last) | 1).leading_zeros()) / DIGIT_BITS;
    let digit = (key >> (pos * DIGIT_BITS)) as usize & (RADIX - 1);
    pos as usize * RADIX + digit
}

/// Entries per chunk of bucket storage.
pub(super) const CHUNK: usize = 16;

/// End of a chunk list.
pub(super) const NIL: u32 = u32::MAX;

/// Why a serialized queue was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("invalid event queue state: {0}")]
pub(super) struct InvalidState(pub(super) &'static str);

/// A block of entries. A bucket is a list of chunks, so the heap's memory follows the number
/// of entries, not the largest size each bucket ever had.
#[derive(Clone, Debug)]
#[repr(C)] // `next` first: it shares a cache line with the first entries
pub(super) struct Chunk {
    /// The next chunk of the list.
    pub(super) next: u32,
    pub(super) entries: [Entry; CHUNK],
}

/// A bucket: its head chunk and how many entries that chunk holds. The other chunks of the list
/// are full. A bucket without a chunk reads as a full [`NIL`] chunk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Head {
    pub(super) chunk: u32,
    pub(super) len: u32,
}

impl Head {
    /// No chunk.
    pub(super) const NONE: Head = Head {
        chunk: NIL,
        len: CHUNK as u32,
    };
}

/// Where an entry is in the radix heap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Pos {
    pub(super) bucket: usize,
    pub(super) chunk: u32,
    pub(super) index: u32,
}

/// A monotone radix heap of entries with distinct keys, none below `last`.
///
/// Invariant: an entry with key `k` sits in bucket `bucket_of(k, last)`, and `k >= last`. All
/// keys of a bucket are below all keys of any higher bucket. An emptied bucket keeps its head
/// chunk for the next entries (small buckets empty and refill all the time).
#[derive(Clone, Debug)]
pub(super) struct RadixHeap {
    /// The key of the last minimum taken out (0 before the first).
    pub(super) last: u128,
    /// Each bucket's head.
    pub(super) heads: Vec<Head>,
    /// The chunks: each in one bucket's list or in the free list.
    pub(super) chunks: Vec<Chunk>,
    /// First chunk of the free list.
    pub(super) free_chunks: u32,
    /// Bit `b % 64` of word `b / 64` is set iff bucket `b` is not empty.
    pub(super) occupied: [u64; WORDS],
    /// Bit `w` is set iff word `w` of `occupied` is not zero.
    pub(super) summary: u64,
    /// Number of entries.
    pub(super) len: usize,
    /// Where the minimum is, when known: spares a second scan when a peek precedes a pop.
    pub(super) front: Option<Pos>,
}

impl RadixHeap {
    /// An empty heap for keys from `last` on, with `extra_lists` chunk lists after its
    /// buckets for its owner's use (the calendar's days draw on the same pool of chunks).
    pub(super) fn new(last: u128, extra_lists: usize) -> Self {
        RadixHeap {
            last,
            heads: vec![Head::NONE; BUCKETS + extra_lists],
            chunks: Vec::new(),
            free_chunks: NIL,
            occupied: [0; WORDS],
            summary: 0,
            len: 0,
            front: None,
        }
    }

    /// Marks bucket `b` as not empty.
    #[inline(always)]
    pub(super) fn mark(&mut self, b: usize) {
        self.occupied[b / 64] |= 1 << (b % 64);
        self.summary |= 1 << (b / 64);
    }

    /// Marks bucket `b` as empty.
    #[inline(always)]
    pub(super) fn unmark(&mut self, b: usize) {
        let w = &mut self.occupied[b / 64];
        *w &= !(1 << (b % 64));
        if *w == 0 {
            self.summary &= !(1 << (b / 64));
        }
    }

    /// Stores `e` in bucket `b` (the caller counts it in `len`).
    #[inline(always)]
    pub(super) fn append(&mut self, b: usize, e: Entry) {
        self.store(b, e);
        self.mark(b);
    }

    /// Stores `e` in the chunk list `b` (a bucket, or one of the calendar's lists from
    /// [`BUCKETS`] on), without marking it.
    #[inline(always)]
    pub(super) fn store(&mut self, b: usize, e: Entry) {
        let head = &mut self.heads[b];
        if (head.len as usize) < CHUNK {
            let i = head.len as usize;
            head.len += 1;
            let c = head.chunk as usize;
            self.chunks[c].entries[i] = e;
        } else {
            self.store_chunk(b, e);
        }
    }

    /// Stores `e` in a new chunk at the head of list `b`.
    #[inline(never)]
    pub(super) fn store_chunk(&mut self, b: usize, e: Entry) {
        let next = self.heads[b].chunk;
        let c = if self.free_chunks != NIL {
            let c = self.free_chunks;
            let chunk = &mut self.chunks[c as usize];
            self.free_chunks = chunk.next;
            chunk.next = next;
            chunk.entries[0] = e;
            c
        } else {
            let c = self.chunks.len();
            assert!(c < NIL as usize, "event queue: too many chunks");
            let mut entries = [Entry::ZERO; CHUNK];
            entries[0] = e;
            self.chunks.push(Chunk { next, entries });
            c as u32
        };
        self.heads[b] = Head { chunk: c, len: 1 };
    }

    /// Empties the chunk lists `lists` (unmarked ones: not counted in `len`), freeing their
    /// chunks.
    pub(super) fn clear_lists(&mut self, lists: std::ops::Range<usize>) {
        for b in lists {
            let mut c = std::mem::replace(&mut self.heads[b], Head::NONE).chunk;
            while c != NIL {
                let next = self.chunks[c as usize].next;
                self.free_chunk(c);
                c = next;
            }
        }
    }

    /// Puts chunk `c` on the free list.
    #[inline(always)]
    pub(super) fn free_chunk(&mut self, c: u32) {
        self.chunks[c as usize].next = self.free_chunks;
        self.free_chunks = c;
    }

    /// Adds an entry; its key must not be below `last` and must differ from every other key.
    #[inline(always)]
    pub(super) fn push(&mut self, e: Entry) {
        debug_assert!(e.key() >= self.last, "radix heap keys must be monotone");
        let b = bucket_of(e.key(), self.last);
        if let Some(f) = self.front {
            // Entries never move on a push: the known minimum stays valid unless undercut.
            if b < f.bucket || (b == f.bucket && e.key() < self.get(f).key()) {
                self.front = None;
            }
        }
        self.append(b, e);
        self.len += 1;
    }

    /// The lowest non-empty bucket.
    #[inline(always)]
    pub(super) fn lowest(&self) -> Option<usize> {
        if self.summary == 0 {
            return None;
        }
        let w = self.summary.trailing_zeros() as usize;
        Some(w * 64 + self.occupied[w].trailing_zeros() as usize)
    }

    /// The chunks of bucket `b`, each with its entries.
    pub(super) fn chunks_of(&self, b: usize) -> impl Iterator<Item = (u32, &[Entry])> {
        let Head { mut chunk, mut len } = self.heads[b];
        std::iter::from_fn(move || {
            let c = self.chunks.get(chunk as usize)?;
            let item = (chunk, &c.entries[..len as usize]);
            chunk = c.next;
            len = CHUNK as u32;
            Some(item)
        })
    }

    /// The entries of bucket `b`.
    pub(super) fn bucket(&self, b: usize) -> impl Iterator<Item = &Entry> {
        self.chunks_of(b).flat_map(|(_, entries)| entries)
    }

    /// Where the minimum is.
    #[inline(always)]
    pub(super) fn min_pos(&mut self) -> Option<Pos> {
        if self.front.is_some() {
            return self.front;
        }
        let bucket = self.lowest()?;
        let mut best = Pos {
            bucket,
            chunk: NIL,
            index: 0,
        };
        let mut best_key = u128::MAX;
        for (c, entries) in self.chunks_of(bucket) {
            for (i, e) in entries.iter().enumerate() {
                let k = e.key();
                if k <= best_key {
                    best = Pos {
                        bucket,
                        chunk: c,
                        index: i as u32,
                    };
                    best_key = k;
                }
            }
        }
        self.front = Some(best);
        self.front
    }

    /// The entry at a position returned by [`min_pos`](Self::min_pos).
    #[inline(always)]
    pub(super) fn get(&self, p: Pos) -> &Entry {
        &self.chunks[p.chunk as usize].entries[p.index as usize]
    }

    /// Takes out the minimum found at `p` by [`min_pos`](Self::min_pos), makes its key the
    /// new `last`, and spreads the rest of its bucket over the lower buckets.
    #[inline(always)]
    pub(super) fn take_min(&mut self, p: Pos) -> Entry {
        let e = *self.get(p);
        self.len -= 1;
        self.front = None;
        self.last = e.key();
        let head = self.heads[p.bucket];
        if head.len == 1 && self.chunks[head.chunk as usize].next == NIL {
            // It was alone in its bucket, which keeps its chunk.
            self.heads[p.bucket].len = 0;
            self.unmark(p.bucket);
        } else {
            self.redistribute(p);
        }
        e
    }

    /// Empties the bucket of `taken` (but for that entry, already taken out) into the lower
    /// buckets, after `last` moved into it.
    #[inline(never)]
    pub(super) fn redistribute(&mut self, taken: Pos) {
        // The entries of this bucket share their digits down to its position with `last`: they
        // now differ from it at a lower position, hence belong to lower buckets.
        let last = self.last;
        let Head { chunk: head, len } = self.heads[taken.bucket];
        self.heads[taken.bucket].len = 0;
        self.unmark(taken.bucket);
        let (mut c, mut n) = (head, len);
        while c != NIL {
            for i in 0..n {
                if c == taken.chunk && i == taken.index {
                    continue;
                }
                let x = self.chunks[c as usize].entries[i as usize];
                self.append(bucket_of(x.key(), last), x);
            }
            let next = std::mem::replace(&mut self.chunks[c as usize].next, NIL);
            if c != head {
                self.free_chunk(c);
            }
            (c, n) = (next, CHUNK as u32);
        }
    }

    /// Keeps only the entries of bucket `b` for which `keep` holds (`last` does not change).
    #[cfg(test)]
    pub(super) fn retain_in(&mut self, b: usize, mut keep: impl FnMut(&Entry) -> bool) {
        self.front = None;
        let before: Vec<Entry> = self.bucket(b).copied().collect();
        let Head { chunk: head, .. } = self.heads[b];
        let mut c = std::mem::replace(&mut self.chunks[head as usize].next, NIL);
        while c != NIL {
            let next = self.chunks[c as usize].next;
            self.free_chunk(c);
            c = next;
        }
        self.heads[b].len = 0;
        self.unmark(b);
        self.len -= before.len();
        for e in before.into_iter().filter(|e| keep(e)) {
            self.append(b, e);
            self.len += 1;
        }
    }

    /// All entries, in no particular order.
    pub(super) fn iter(&self) -> impl Iterator<Item = &Entry> {
        (0..BUCKETS).flat_map(|b| self.bucket(b))
    }
}
