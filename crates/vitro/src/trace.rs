//! The trace hash: a stable 64-bit digest of what happened in a run.
//!
//! The hash function is Vitro's own (a fixed 64-bit mixer), so a value computed today on one
//! machine equals the one computed tomorrow on another. Values are fed through serde
//! ([`TraceHasher::digest`]), so any `Serialize` type can be traced, floats included (by bits).

mod ser;

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
        // A folded 64×64→128 multiply: one multiplication per word, full avalanche at finish.
        let m = u128::from(self.state ^ x) * u128::from(K);
        self.state = (m as u64) ^ ((m >> 64) as u64);
        self.count = self.count.wrapping_add(1);
    }

    /// Feeds bytes (length-suffixed).
    #[inline]
    pub fn write_bytes(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.write_u64(u64::from_le_bytes(w));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.write_u64(u64::from_le_bytes(w));
        }
        self.write_u64(bytes.len() as u64);
    }

    /// Feeds any serializable value: the words of its postcard encoding (eight bytes a word,
    /// the last padded with zeros, then the number of bytes), made as the value is walked,
    /// with no buffer.
    #[inline(always)]
    pub fn digest<T: Serialize + ?Sized>(&mut self, value: &T) {
        let mut s = ser::WordSer::new(self);
        // Plain data cannot fail to encode; if a type's Serialize impl refuses (or a
        // sequence has no length), the refusal itself is traced, after the words made so far.
        match value.serialize(&mut s) {
            Ok(()) => s.finish(),
            Err(ser::Refused) => self.write_u64(u64::MAX),
        }
    }

    /// The current digest.
    #[inline]
    pub fn finish(&self) -> u64 {
        mix(self.state ^ self.count.wrapping_mul(K))
    }

    /// Number of words fed so far.
    pub fn words(&self) -> u64 {
        self.count
    }
}

impl ser::Words for TraceHasher {
    #[inline(always)]
    fn word(&mut self, w: u64) {
        self.write_u64(w);
    }
}

/// A stable 64-bit hash of a string (for naming RNG streams and the like). Inlined, so that
/// the hash of a literal (a stream's purpose) folds to a constant where it is called.
#[inline]
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
        assert_eq!(h.finish(), 3271280584164529332);
    }

    /// The reference: postcard's own encoding, fed to the hasher byte by byte.
    struct HashFlavor<'a> {
        h: &'a mut TraceHasher,
        word: u64,
        len: u64,
    }

    impl postcard::ser_flavors::Flavor for HashFlavor<'_> {
        type Output = ();
        fn try_push(&mut self, byte: u8) -> postcard::Result<()> {
            let at = self.len % 8;
            self.word |= u64::from(byte) << (8 * at);
            self.len += 1;
            if at == 7 {
                self.h.write_u64(self.word);
                self.word = 0;
            }
            Ok(())
        }
        fn finalize(self) -> postcard::Result<()> {
            if !self.len.is_multiple_of(8) {
                self.h.write_u64(self.word);
            }
            self.h.write_u64(self.len);
            Ok(())
        }
    }

    /// `value`'s digest the way it was made before the word serializer: postcard's bytes.
    fn reference<T: Serialize + ?Sized>(value: &T) -> TraceHasher {
        let mut h = TraceHasher::default();
        let flavor = HashFlavor {
            h: &mut h,
            word: 0,
            len: 0,
        };
        if postcard::serialize_with_flavor(value, flavor).is_err() {
            h.write_u64(u64::MAX);
        }
        h
    }

    fn same<T: Serialize + ?Sized + std::fmt::Debug>(value: &T) {
        let mut fast = TraceHasher::default();
        fast.digest(value);
        let slow = reference(value);
        assert_eq!(
            (fast.finish(), fast.words()),
            (slow.finish(), slow.words()),
            "{value:?}"
        );
    }

    #[test]
    fn the_words_are_postcards_bytes() {
        use std::collections::BTreeMap;
        #[derive(Serialize, Debug)]
        enum E {
            Unit,
            New(i16),
            Tuple(u8, i128, u128),
            Struct { a: Option<f32>, b: char, c: () },
        }
        #[derive(Serialize, Debug)]
        struct Unit;
        #[derive(Serialize, Debug, Clone, Copy)]
        struct Wrap(u16);
        /// A sequence whose length is not known up front: postcard refuses it.
        struct NoLen;
        impl Serialize for NoLen {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                use serde::ser::SerializeSeq;
                let mut q = s.serialize_seq(None)?;
                q.serialize_element(&1u8)?;
                q.end()
            }
        }
        impl std::fmt::Debug for NoLen {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("NoLen")
            }
        }
        /// A value that reports an error half-way.
        #[derive(Debug)]
        struct Fails;
        impl Serialize for Fails {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                use serde::ser::{Error, SerializeTuple};
                let mut t = s.serialize_tuple(2)?;
                t.serialize_element(&u64::MAX)?;
                t.serialize_element(&"twelve bytes")?;
                Err(S::Error::custom("no"))
            }
        }
        /// A value written through `collect_str`.
        #[derive(Debug)]
        struct Shown(f64);
        impl Serialize for Shown {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.collect_str(&format_args!("value {:.3} and more", self.0))
            }
        }
        let mut ints: Vec<u64> = vec![0, 1, 127, 128, 255, 16383, 16384, u64::MAX];
        for k in 0..64 {
            ints.extend([1u64 << k, (1u64 << k) - 1, (1u64 << k) + 1]);
        }
        // And values with every bit pattern below their top bit (a 64-bit LCG, cut to each width).
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        for k in 1..=64 {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ints.push(x >> (64 - k));
        }
        for &n in &ints {
            same(&n);
            same(&(
                n as u32,
                n as u16,
                n as i64,
                (n as i64).wrapping_neg(),
                n as i32,
                n as i16,
                n as i8,
            ));
            same(&(n as u8, n, true, n as f64));
            same(&(
                (u128::from(n) << 64) | u128::from(n),
                -(i128::from(n) << 60),
            ));
        }
        for i in 0..40u8 {
            let text = "abcdefghijklmnopqrstuvwxyz0123456789ABCDE"[..usize::from(i)].to_string();
            let bytes: Vec<u8> = (0..i).collect();
            same(&(
                i,
                text.as_str(),
                serde_bytes_like(&bytes),
                bytes.clone(),
                'é',
                'x',
            ));
            same(&(text.as_str(), i, Some(f32::from(i)), None::<u8>, i));
        }
        let mut map = BTreeMap::new();
        map.insert("k".to_string(), vec![E::Unit, E::New(-3)]);
        map.insert(
            "long key of many bytes".to_string(),
            vec![E::Tuple(7, -1 << 100, u128::MAX)],
        );
        same(&map);
        same(&E::Struct {
            a: Some(1.5),
            b: '🦀',
            c: (),
        });
        same(&(Unit, Wrap(300), [Wrap(1); 3], ()));
        same(&(3u8, NoLen));
        same(&(3u8, Fails));
        same(&(1u8, Shown(2.0f64.sqrt())));
        same(&Shown(1e300));
    }

    /// A byte slice that serializes as bytes (`serialize_bytes`), not as a sequence.
    fn serde_bytes_like(b: &[u8]) -> impl Serialize + std::fmt::Debug + '_ {
        struct B<'a>(&'a [u8]);
        impl Serialize for B<'_> {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_bytes(self.0)
            }
        }
        impl std::fmt::Debug for B<'_> {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{:?}", self.0)
            }
        }
        B(b)
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
