//! A serde serializer that hashes a value's postcard encoding without making it.
//!
//! The bytes are postcard 1's (varints for integers, zigzag for signed ones, little-endian
//! floats, length-prefixed strings, sequences and maps, variant indexes as varints), packed
//! into little-endian 64-bit words as they come: eight bytes a word, the last one padded
//! with zeros. Instead of postcard's byte-at-a-time output, a varint or a float goes into the
//! current word as one piece; the words are the same (the tests compare them with postcard's
//! own output for many types).

use serde::ser::{self, Serialize};
use std::fmt;

/// Where the words go.
pub(super) trait Words {
    /// Takes one word.
    fn word(&mut self, w: u64);
}

/// The serializer: the bytes of the current word, how many, and how many in all.
pub(super) struct WordSer<'a, W: Words> {
    out: &'a mut W,
    acc: u64,
    /// Bytes in `acc` (0 to 7).
    fill: u32,
    len: u64,
}

/// Why a value could not be encoded (postcard's refusals: a sequence of unknown length, a
/// `Serialize` impl that reports an error).
#[derive(Debug)]
pub(super) struct Refused;

impl fmt::Display for Refused {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("the value cannot be encoded")
    }
}
impl std::error::Error for Refused {}
impl ser::Error for Refused {
    fn custom<T: fmt::Display>(_: T) -> Self {
        Refused
    }
}

type R = Result<(), Refused>;

impl<'a, W: Words> WordSer<'a, W> {
    pub(super) fn new(out: &'a mut W) -> Self {
        WordSer {
            out,
            acc: 0,
            fill: 0,
            len: 0,
        }
    }

    /// The end: the last partial word, then the number of bytes.
    #[inline]
    pub(super) fn finish(self) {
        if self.fill != 0 {
            self.out.word(self.acc);
        }
        self.out.word(self.len);
    }

    /// Appends the `n` (1 to 8) low bytes of `v` (its higher bytes are zero).
    #[inline(always)]
    fn chunk(&mut self, v: u64, n: u32) {
        let at = self.fill;
        self.acc |= v << (8 * at);
        let total = at + n;
        if total >= 8 {
            self.out.word(self.acc);
            // The bytes of `v` that did not fit (none if the word was empty).
            self.acc = if at == 0 { 0 } else { v >> (8 * (8 - at)) };
            self.fill = total - 8;
        } else {
            self.fill = total;
        }
        self.len += u64::from(n);
    }

    /// A varint (LEB128, postcard's) of `v`.
    #[inline(always)]
    fn varint(&mut self, mut v: u64) {
        if v < 0x80 {
            return self.chunk(v, 1);
        }
        let (mut packed, mut n) = (0u64, 0u32);
        while v >= 0x80 && n < 8 {
            packed |= ((v & 0x7F) | 0x80) << (8 * n);
            v >>= 7;
            n += 1;
        }
        if n < 8 {
            self.chunk(packed | (v << (8 * n)), n + 1);
        } else {
            // At most 8 bits left: one or two bytes (not a recursive call, so that the whole
            // varint inlines where a value is traced).
            self.chunk(packed, 8);
            if v < 0x80 {
                self.chunk(v, 1);
            } else {
                self.chunk((v & 0x7F) | 0x80 | ((v >> 7) << 8), 2);
            }
        }
    }

    /// A varint of a 128-bit `v`.
    fn varint128(&mut self, mut v: u128) {
        while v >= 0x80 {
            self.chunk(((v & 0x7F) | 0x80) as u64, 1);
            v >>= 7;
        }
        self.chunk(v as u64, 1);
    }

    /// Raw bytes.
    #[inline]
    fn bytes(&mut self, b: &[u8]) {
        let mut chunks = b.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.chunk(u64::from_le_bytes(w), 8);
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut v = 0u64;
            for (i, &x) in rest.iter().enumerate() {
                v |= u64::from(x) << (8 * i);
            }
            self.chunk(v, rest.len() as u32);
        }
    }
}

impl<W: Words> ser::Serializer for &mut WordSer<'_, W> {
    type Ok = ();
    type Error = Refused;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Self;
    type SerializeTupleVariant = Self;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Self;

    fn is_human_readable(&self) -> bool {
        false
    }
    #[inline(always)]
    fn serialize_bool(self, v: bool) -> R {
        self.chunk(u64::from(v), 1);
        Ok(())
    }
    #[inline]
    fn serialize_i8(self, v: i8) -> R {
        self.chunk(u64::from(v as u8), 1);
        Ok(())
    }
    #[inline]
    fn serialize_i16(self, v: i16) -> R {
        self.varint(u64::from(((v << 1) ^ (v >> 15)) as u16));
        Ok(())
    }
    #[inline(always)]
    fn serialize_i32(self, v: i32) -> R {
        self.varint(u64::from(((v << 1) ^ (v >> 31)) as u32));
        Ok(())
    }
    #[inline(always)]
    fn serialize_i64(self, v: i64) -> R {
        self.varint(((v << 1) ^ (v >> 63)) as u64);
        Ok(())
    }
    fn serialize_i128(self, v: i128) -> R {
        self.varint128(((v << 1) ^ (v >> 127)) as u128);
        Ok(())
    }
    #[inline(always)]
    fn serialize_u8(self, v: u8) -> R {
        self.chunk(u64::from(v), 1);
        Ok(())
    }
    #[inline]
    fn serialize_u16(self, v: u16) -> R {
        self.varint(u64::from(v));
        Ok(())
    }
    #[inline(always)]
    fn serialize_u32(self, v: u32) -> R {
        self.varint(u64::from(v));
        Ok(())
    }
    #[inline(always)]
    fn serialize_u64(self, v: u64) -> R {
        self.varint(v);
        Ok(())
    }
    fn serialize_u128(self, v: u128) -> R {
        self.varint128(v);
        Ok(())
    }
    #[inline]
    fn serialize_f32(self, v: f32) -> R {
        self.chunk(u64::from(v.to_bits()), 4);
        Ok(())
    }
    #[inline(always)]
    fn serialize_f64(self, v: f64) -> R {
        self.chunk(v.to_bits(), 8);
        Ok(())
    }
    fn serialize_char(self, v: char) -> R {
        let mut buf = [0u8; 4];
        self.serialize_str(v.encode_utf8(&mut buf))
    }
    #[inline]
    fn serialize_str(self, v: &str) -> R {
        self.varint(v.len() as u64);
        self.bytes(v.as_bytes());
        Ok(())
    }
    fn serialize_bytes(self, v: &[u8]) -> R {
        self.varint(v.len() as u64);
        self.bytes(v);
        Ok(())
    }
    #[inline(always)]
    fn serialize_none(self) -> R {
        self.chunk(0, 1);
        Ok(())
    }
    #[inline(always)]
    fn serialize_some<T: ?Sized + Serialize>(self, value: &T) -> R {
        self.chunk(1, 1);
        value.serialize(self)
    }
    #[inline(always)]
    fn serialize_unit(self) -> R {
        Ok(())
    }
    #[inline]
    fn serialize_unit_struct(self, _: &'static str) -> R {
        Ok(())
    }
    #[inline(always)]
    fn serialize_unit_variant(self, _: &'static str, index: u32, _: &'static str) -> R {
        self.varint(u64::from(index));
        Ok(())
    }
    #[inline(always)]
    fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, v: &T) -> R {
        v.serialize(self)
    }
    #[inline(always)]
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        index: u32,
        _: &'static str,
        v: &T,
    ) -> R {
        self.varint(u64::from(index));
        v.serialize(self)
    }
    #[inline]
    fn serialize_seq(self, len: Option<usize>) -> Result<Self, Refused> {
        self.varint(len.ok_or(Refused)? as u64);
        Ok(self)
    }
    #[inline(always)]
    fn serialize_tuple(self, _: usize) -> Result<Self, Refused> {
        Ok(self)
    }
    #[inline]
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self, Refused> {
        Ok(self)
    }
    #[inline]
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        index: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self, Refused> {
        self.varint(u64::from(index));
        Ok(self)
    }
    #[inline]
    fn serialize_map(self, len: Option<usize>) -> Result<Self, Refused> {
        self.varint(len.ok_or(Refused)? as u64);
        Ok(self)
    }
    #[inline(always)]
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, Refused> {
        Ok(self)
    }
    #[inline]
    fn serialize_struct_variant(
        self,
        _: &'static str,
        index: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self, Refused> {
        self.varint(u64::from(index));
        Ok(self)
    }
    fn collect_str<T: ?Sized + fmt::Display>(self, value: &T) -> R {
        // As postcard: format once to count the bytes, then again to write them.
        struct Count(usize);
        impl fmt::Write for Count {
            fn write_str(&mut self, s: &str) -> fmt::Result {
                self.0 += s.len();
                Ok(())
            }
        }
        struct Bytes<'s, 'a, W: Words>(&'s mut WordSer<'a, W>);
        impl<W: Words> fmt::Write for Bytes<'_, '_, W> {
            fn write_str(&mut self, s: &str) -> fmt::Result {
                self.0.bytes(s.as_bytes());
                Ok(())
            }
        }
        let mut count = Count(0);
        fmt::write(&mut count, format_args!("{value}")).map_err(|_| Refused)?;
        self.varint(count.0 as u64);
        fmt::write(&mut Bytes(self), format_args!("{value}")).map_err(|_| Refused)
    }
}

/// The compound serializers: each element in turn, nothing at the end.
macro_rules! compound {
    ($tr:ident, $f:ident $(, $key:ty)?) => {
        impl<W: Words> ser::$tr for &mut WordSer<'_, W> {
            type Ok = ();
            type Error = Refused;
            #[inline(always)]
            fn $f<T: ?Sized + Serialize>(&mut self, $(_: $key,)? v: &T) -> R {
                v.serialize(&mut **self)
            }
            #[inline(always)]
            fn end(self) -> R {
                Ok(())
            }
        }
    };
}
compound!(SerializeSeq, serialize_element);
compound!(SerializeTuple, serialize_element);
compound!(SerializeTupleStruct, serialize_field);
compound!(SerializeTupleVariant, serialize_field);
compound!(SerializeStruct, serialize_field, &'static str);
compound!(SerializeStructVariant, serialize_field, &'static str);

impl<W: Words> ser::SerializeMap for &mut WordSer<'_, W> {
    type Ok = ();
    type Error = Refused;
    #[inline]
    fn serialize_key<T: ?Sized + Serialize>(&mut self, k: &T) -> R {
        k.serialize(&mut **self)
    }
    #[inline]
    fn serialize_value<T: ?Sized + Serialize>(&mut self, v: &T) -> R {
        v.serialize(&mut **self)
    }
    fn end(self) -> R {
        Ok(())
    }
}
