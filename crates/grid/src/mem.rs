//! Memory hints: large buffers ask the kernel for transparent huge pages,
//! and reads whose addresses are known ahead (the next elements of a pass
//! in order, or known random reads) can be prefetched.
//!
//! A grid over a million primitives fills tens of megabytes of fresh memory
//! during the build; with 4 KiB pages every page costs a fault and the radix
//! scatter thrashes the TLB. On Linux, `madvise(MADV_HUGEPAGE)` on a buffer
//! before its first touch lets the kernel back it with 2 MiB pages (when
//! transparent huge pages are enabled in `madvise` or `always` mode). It is
//! a hint only: on failure, or on other systems, nothing changes. So is
//! [`prefetch`], for random reads whose addresses are known in advance.
//! Both are public for callers that fill or gather large per-primitive
//! arrays of their own (a renderer's colours, a generator's spheres).

/// Buffers below this size are left alone.
const MIN_BYTES: usize = 4 << 20;

#[cfg(target_os = "linux")]
extern "C" {
    fn madvise(addr: *mut std::ffi::c_void, len: usize, advice: i32) -> i32;
}

/// Advises huge pages for the capacity of `v` (call before writing to it).
pub(crate) fn advise_huge<T>(v: &mut Vec<T>) {
    let bytes = v.capacity() * std::mem::size_of::<T>();
    if bytes < MIN_BYTES {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        const MADV_HUGEPAGE: i32 = 14;
        const PAGE: usize = 4096;
        let start = v.as_mut_ptr() as usize;
        let aligned = (start + PAGE - 1) & !(PAGE - 1);
        let len = (start + bytes - aligned) & !(PAGE - 1);
        // SAFETY: the range lies inside the vector's own allocation, and
        // MADV_HUGEPAGE changes no contents, only how pages get backed; the
        // result is ignored because the call is only a hint.
        unsafe {
            madvise(aligned as *mut std::ffi::c_void, len, MADV_HUGEPAGE);
        }
    }
}

/// An empty vector with room for `n` elements, on huge pages where
/// possible: for large buffers about to be filled (a million primitives).
///
/// ```
/// let mut v: Vec<u64> = gridrt_grid::mem::with_capacity(1 << 20);
/// v.extend(0..1 << 20);
/// assert_eq!(v[12345], 12345);
/// ```
#[must_use]
pub fn with_capacity<T>(n: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    advise_huge(&mut v);
    v
}

/// A vector of `n` copies of `x` on huge pages where possible.
pub(crate) fn filled<T: Copy>(n: usize, x: T) -> Vec<T> {
    let mut v = with_capacity(n);
    v.resize(n, x);
    v
}

/// How far ahead of a sequential pass [`prefetch_at`] is asked for: 1 KiB,
/// sixteen cache lines.
const AHEAD_BYTES: usize = 1024;

/// Prefetches the element [`AHEAD_BYTES`] after `xs[i]` (before it when
/// `back`), if there is one: for a pass over `xs` in order. On some
/// machines (the KVM guests this project is measured on among them), the
/// hardware prefetcher leaves a sequential read of a large fresh buffer
/// waiting on memory; asked ahead, the build's passes over a million
/// primitives take a third to two thirds less time.
#[inline(always)]
pub(crate) fn prefetch_at<T>(xs: &[T], i: usize, back: bool) {
    let ahead = (AHEAD_BYTES / std::mem::size_of::<T>().max(1)).max(1);
    let j = if back {
        i.checked_sub(ahead)
    } else {
        Some(i + ahead)
    };
    if let Some(x) = j.and_then(|j| xs.get(j)) {
        prefetch(x);
    }
}

/// Bytes of a cache line.
pub(crate) const LINE_BYTES: usize = 64;

/// Prefetches the cache lines of the first `bytes` bytes of `xs` (at most
/// all of it): for a short array whose start a read will need, before the
/// address of the element it needs is known.
#[inline(always)]
pub(crate) fn prefetch_head<T>(xs: &[T], bytes: usize) {
    let end = std::mem::size_of_val(xs).min(bytes);
    let start = xs.as_ptr().cast::<u8>();
    let mut at = 0;
    while at < end {
        prefetch_ptr(start.wrapping_add(at));
        at += LINE_BYTES;
    }
}

/// Prefetches elements `at` of `xs`, both ends of each (an element may
/// straddle two cache lines): for elements about to be read by index, such
/// as the primitives a grid cell refers to. Indices past the end are
/// harmless: a prefetch never faults.
///
/// ```
/// let tris = vec![[0.25f32; 10]; 100];
/// gridrt_grid::mem::prefetch_elements(&tris, &[3, 50, 1000]);
/// assert_eq!(tris[50][9], 0.25);
/// ```
#[inline(always)]
pub fn prefetch_elements<T>(xs: &[T], at: &[u32]) {
    let last = std::mem::size_of::<T>().saturating_sub(1);
    for &i in at {
        let first = xs.as_ptr().wrapping_add(i as usize).cast::<u8>();
        prefetch_ptr(first);
        prefetch_ptr(first.wrapping_add(last));
    }
}

/// Asks the CPU to bring the cache line holding `x` closer, ahead of a
/// read (on x86-64; elsewhere nothing happens). A hint: no visible effect.
/// The grid uses it when it gathers primitives; a renderer can use it for
/// per-primitive data it will read after a hit.
///
/// ```
/// let colours = vec![[0.5f32; 3]; 1000];
/// gridrt_grid::mem::prefetch(&colours[700]);
/// assert_eq!(colours[700][1], 0.5);
/// ```
#[inline(always)]
pub fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: SSE is part of x86-64; a prefetch reads nothing the
        // program sees and never faults, and `x` is a valid reference anyway.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(x).cast()) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// [`prefetch`] for an address held as a pointer, such as one computed
/// from an index not yet checked: a prefetch never faults, whatever the
/// address.
///
/// ```
/// let v = vec![1u32; 64];
/// gridrt_grid::mem::prefetch_ptr(v.as_ptr().wrapping_add(1000));
/// assert_eq!(v[63], 1);
/// ```
#[inline(always)]
pub fn prefetch_ptr<T>(x: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: SSE is part of x86-64; a prefetch reads nothing the
        // program sees and never faults.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(x.cast()) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}
