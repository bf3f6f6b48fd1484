//! Performance hints: no effect on any result, only on how soon memory is at hand.
//!
//! Layer: the lowest (imports nothing of the crate), beside `time` and `trace`.

/// Asks the processor to start loading the cache lines of the `bytes` bytes at `p` into its
/// caches, to be read soon: a hint, with no effect on any result (a no-op off x86-64). Worth it
/// where a read that misses the caches is known well ahead (the event queue's slots of a new
/// day, a look's memo while other lookers run).
///
/// ```
/// let v = vec![1u64; 1024];
/// vitro::hint::prefetch(v.as_ptr().wrapping_add(512), 64);
/// assert_eq!(v[512], 1);
/// ```
#[inline(always)]
pub fn prefetch<T>(p: *const T, bytes: usize) {
    #[cfg(target_arch = "x86_64")]
    for off in (0..bytes).step_by(64) {
        // SAFETY: a prefetch never faults and never writes, whatever the address (and
        // `wrapping_add` makes no claim about it either).
        unsafe {
            use core::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>().wrapping_add(off));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, bytes);
}
