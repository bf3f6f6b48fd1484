//! The trace hash: a stable 64-bit digest of what happened in a run.
//!
//! The hash function is Vitro's own (a fixed 64-bit mixer), so a value computed today on one
//! machine equals the one computed tomorrow on another. Values are fed through serde
//! ([`TraceHasher::digest`]), so any `Serialize` type can be traced, floats included (by bits).

use serde::{Deserialize, Serialize};

const K: u64 = 0x9E37_79B9_7F4A_7C15;

/// A stable streaming hasher (not for hash tables: for traces and state digests).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TraceHasher {
    state: u64,
    count: u64,
}

impl Default for TraceHasher {
    fn default() -> Self {
        TraceHasher {
            state: 0x243F_6A88_85A3_08D3,
            count: 0,
        }
    }
}

#[inline]
fn mix(mut x: u64) -> u64 {
    // splitmix64 finaliser.
    x ^= x >> 30;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

impl TraceHasher {
    /// Feeds one word.
    #[inline]
    pub fn write_u64(&mut self, x: u64) {
        self.state = mix(self.state.rotate_left(23) ^ x.wrapping_mul(K));
        self.count = self.count.wrapping_add(1);
    }

    /// Feeds bytes (length-prefixed).
    pub fn write_bytes(&mut self, bytes: &[u8]) {
        self.write_u64(bytes.len() as u64);
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.write_u64(u64::from_le_bytes(c.try_into().expect("chunk of 8")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.write_u64(u64::from_le_bytes(w));
        }
    }

    /// Feeds any serializable value (its postcard encoding).
    pub fn digest<T: Serialize + ?Sized>(&mut self, value: &T) {
        let mut buf = [0u8; 256];
        match postcard::to_slice(value, &mut buf) {
            Ok(bytes) => self.write_bytes(bytes),
            Err(_) => match postcard::to_stdvec(value) {
                Ok(v) => self.write_bytes(&v),
                // Serialization of plain data does not fail; if a type refuses, trace that fact.
                Err(_) => self.write_u64(u64::MAX),
            },
        }
    }

    /// The current digest.
    pub fn finish(&self) -> u64 {
        mix(self.state ^ self.count.wrapping_mul(K))
    }

    /// Number of words fed so far.
    pub fn words(&self) -> u64 {
        self.count
    }
}

/// A stable 64-bit hash of a string (for naming RNG streams and the like).
pub fn stable_str_hash(s: &str) -> u64 {
    let mut h = TraceHasher::default();
    h.write_bytes(s.as_bytes());
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stable_values() {
        // Frozen: if this changes, every recorded trace hash changes.
        let mut h = TraceHasher::default();
        h.write_u64(1);
        h.digest(&(2.5f64, "x", [1u32, 2]));
        assert_eq!(h.finish(), 9415886728096355934);
    }

    #[test]
    fn order_matters() {
        let mut a = TraceHasher::default();
        let mut b = TraceHasher::default();
        a.write_u64(1);
        a.write_u64(2);
        b.write_u64(2);
        b.write_u64(1);
        assert_ne!(a.finish(), b.finish());
    }
}
