//! Interning of bitset states: dense ids, one flat arena, a hash table for duplicates.

use hashbrown::HashTable;

/// Stores each distinct state once and numbers states in order of first insertion.
#[derive(Debug, Clone)]
pub(crate) struct StateRegistry {
    words: usize,
    arena: Vec<u64>,
    table: HashTable<u32>,
}

/// A fast multiplicative hash of a state's words (for duplicate detection only).
#[inline]
fn hash_state(s: &[u64]) -> u64 {
    const K: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut h = 0u64;
    for &w in s {
        h = (h.rotate_left(5) ^ w).wrapping_mul(K);
    }
    h ^ (h >> 29)
}

impl StateRegistry {
    /// An empty registry for states of `words` words.
    pub fn new(words: usize) -> Self {
        StateRegistry {
            words,
            arena: Vec::new(),
            table: HashTable::new(),
        }
    }

    /// The state with id `id`.
    #[inline]
    pub fn get(&self, id: u32) -> &[u64] {
        let start = id as usize * self.words;
        &self.arena[start..start + self.words]
    }

    /// Number of states stored.
    pub fn len(&self) -> usize {
        self.arena.len() / self.words
    }

    /// The id of `state`, inserting it if new; the flag says whether it was new.
    pub fn insert(&mut self, state: &[u64]) -> (u32, bool) {
        let hash = hash_state(state);
        let (words, arena) = (self.words, &self.arena);
        let slice = |id: u32| &arena[id as usize * words..(id as usize + 1) * words];
        if let Some(&id) = self.table.find(hash, |&id| slice(id) == state) {
            return (id, false);
        }
        let id = self.len() as u32;
        self.arena.extend_from_slice(state);
        let (words, arena) = (self.words, &self.arena);
        self.table.insert_unique(hash, id, |&id| {
            hash_state(&arena[id as usize * words..(id as usize + 1) * words])
        });
        (id, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interns_in_insertion_order() {
        let mut r = StateRegistry::new(2);
        assert_eq!(r.insert(&[1, 2]), (0, true));
        assert_eq!(r.insert(&[3, 4]), (1, true));
        assert_eq!(r.insert(&[1, 2]), (0, false));
        assert_eq!(r.get(1), &[3, 4]);
        assert_eq!(r.len(), 2);
    }
}
