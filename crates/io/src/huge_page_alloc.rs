//! An allocator that puts large blocks on transparent huge pages: the
//! `gridrt` binary's global allocator.
//!
//! A render's large arrays (a million spheres, a grid's references and
//! cells, a mesh's vertices) are written once, soon after they are
//! allocated, and every fresh 4 KiB page costs the kernel a fault and a
//! zeroing. Backed by 2 MiB pages they take a fault per 2 MiB instead, and
//! their random reads miss the TLB less. The kernel backs a range with huge
//! pages only where it covers whole 2 MiB-aligned stretches (with transparent
//! huge pages in `madvise` or `always` mode), so [`HugePageAlloc`] maps each
//! block of at least [`LARGE`] bytes on its own, starting on a 2 MiB
//! boundary, and advises huge pages for it: only its last partial 2 MiB
//! stays on small pages, and nothing is rounded up, so the peak memory is
//! that of the bytes asked for. Smaller blocks go to the system allocator.
//! Elsewhere than on Linux everything does.
//!
//! A freed block's whole huge pages are kept (up to [`MAX_KEPT`] bytes) and
//! moved into the next large blocks, by `mremap`, which hands over page
//! tables without copying a byte; only what they do not cover is mapped
//! fresh. Fresh pages are the expensive ones: the kernel zeroes each, and
//! on a virtual machine whose host reclaims the memory other processes
//! free, each can cost the host a fault as well. A render frees large
//! temporaries (a grid build's sort buffers) shortly before it asks for
//! blocks as large (the primitives in cell order), so it touches about a
//! fifth less fresh memory. Kept pages do not raise the peak memory: a new
//! large block takes kept pages before it maps fresh ones,
//! a block that grows in place unmaps as many kept pages as it grows by,
//! and so does a rise of the small blocks' high-water mark (the bytes of
//! the system allocator's blocks are counted per thread, and added up
//! every 256 KiB). [`HugePageAlloc::release_kept`] returns them all to the
//! system.
//!
//! ```
//! use gridrt_io::HugePageAlloc;
//! use std::alloc::{GlobalAlloc, Layout};
//! let layout = Layout::array::<u64>(1 << 20).unwrap();
//! // SAFETY: the layout is not zero-sized, and the block is freed with it.
//! unsafe {
//!     let p = HugePageAlloc.alloc_zeroed(layout);
//!     assert!(!p.is_null() && *p.add(12345) == 0);
//!     HugePageAlloc.dealloc(p, layout);
//! }
//! ```

use std::alloc::{GlobalAlloc, Layout, System};

/// Blocks of at least this many bytes (1 MiB) are mapped on their own.
pub const LARGE: usize = 1 << 20;

/// The system allocator for small blocks; large ones mapped 2 MiB-aligned
/// with `madvise(MADV_HUGEPAGE)` (see the [module](self) documentation).
/// Install it with `#[global_allocator]`.
#[derive(Clone, Copy, Debug, Default)]
pub struct HugePageAlloc;

/// At most this many bytes of freed blocks' huge pages are kept for
/// later blocks (1 GiB); past it, freed blocks are unmapped.
pub const MAX_KEPT: usize = 1 << 30;

impl HugePageAlloc {
    /// Bytes of freed blocks' pages kept for later blocks now (see the
    /// [module](self) documentation); always 0 elsewhere than on Linux.
    #[must_use]
    pub fn kept_bytes() -> usize {
        #[cfg(target_os = "linux")]
        return large::kept_bytes();
        #[cfg(not(target_os = "linux"))]
        0
    }

    /// Returns the pages kept from freed blocks to the system: for a
    /// long-running process after its largest work.
    pub fn release_kept() {
        #[cfg(target_os = "linux")]
        large::release_kept(usize::MAX);
    }
}

#[cfg(target_os = "linux")]
mod large {
    use super::MAX_KEPT;
    use std::sync::{Mutex, MutexGuard, PoisonError};

    /// Huge page size on x86-64 and (with 4 KiB pages) aarch64.
    const HUGE: usize = 2 << 20;
    /// The alignment every mapping has (the smallest page size).
    pub(super) const PAGE: usize = 4096;
    /// At most this many runs of them (a freed block gives one run).
    const RUNS: usize = 64;

    /// The whole, 2 MiB-aligned huge pages of freed blocks, kept mapped
    /// for later blocks: `runs[..len]` as (start, pages).
    struct Kept {
        runs: [(usize, usize); RUNS],
        len: usize,
        bytes: usize,
        /// Growth of the small blocks' high-water mark not yet answered
        /// by unmapping kept pages.
        owed: usize,
    }

    impl Kept {
        /// Takes at most `pages` pages, the last kept first: their start
        /// and how many (0 when none are kept).
        fn take(&mut self, pages: usize) -> (usize, usize) {
            let Some(last) = self.len.checked_sub(1) else {
                return (0, 0);
            };
            let (start, n) = self.runs[last];
            let k = n.min(pages);
            if k == n {
                self.len = last;
            } else {
                self.runs[last] = (start + k * HUGE, n - k);
            }
            self.bytes -= k * HUGE;
            (start, k)
        }

        /// Keeps `n` pages from `start`, if there is room.
        fn keep(&mut self, start: usize, n: usize) -> bool {
            if self.len == RUNS || self.bytes + n * HUGE > MAX_KEPT {
                return false;
            }
            self.runs[self.len] = (start, n);
            self.len += 1;
            self.bytes += n * HUGE;
            true
        }
    }

    static KEPT: Mutex<Kept> = Mutex::new(Kept {
        runs: [(0, 0); RUNS],
        len: 0,
        bytes: 0,
        owed: 0,
    });

    fn kept() -> MutexGuard<'static, Kept> {
        KEPT.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Bytes of freed pages kept for reuse now.
    pub(super) fn kept_bytes() -> usize {
        kept().bytes
    }

    /// The small blocks' high-water mark grew by `bytes`: while pages are
    /// kept, as many are unmapped (a whole page once 2 MiB are owed), so
    /// that the heap's growth does not stack on top of them.
    pub(super) fn small_grew(bytes: usize) {
        let due = {
            let mut k = kept();
            k.owed = if k.len == 0 { 0 } else { k.owed + bytes };
            let due = k.owed - k.owed % HUGE;
            k.owed -= due;
            due
        };
        release_kept(due);
    }

    /// Unmaps kept pages, at least `bytes` of them (or all there are).
    pub(super) fn release_kept(bytes: usize) {
        let mut freed = 0;
        while freed < bytes {
            let (start, n) = kept().take((bytes - freed).div_ceil(HUGE));
            if n == 0 {
                return;
            }
            // SAFETY: kept pages are ours alone, and no longer kept.
            unsafe { libc::munmap(start as *mut libc::c_void, n * HUGE) };
            freed += n * HUGE;
        }
    }

    /// The length a block of `size` bytes is mapped with.
    fn mapped(size: usize) -> usize {
        size.next_multiple_of(PAGE)
    }

    /// A fresh (zeroed) mapping of `len` bytes starting on a 2 MiB
    /// boundary, advised to use huge pages; null if the system has no
    /// memory for it.
    fn fresh(len: usize) -> *mut u8 {
        let Some(span) = len.checked_add(HUGE) else {
            return std::ptr::null_mut();
        };
        // SAFETY: an anonymous private mapping at an address of the
        // kernel's choice touches no existing memory.
        let raw = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                span,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            )
        };
        if raw == libc::MAP_FAILED {
            return std::ptr::null_mut();
        }
        let raw = raw as usize;
        let start = raw.next_multiple_of(HUGE);
        let (head, tail) = (start - raw, raw + span - (start + len));
        // SAFETY: the head and tail lie inside the mapping just made and
        // outside the block returned; advising changes no contents.
        unsafe {
            if head > 0 {
                libc::munmap(raw as *mut libc::c_void, head);
            }
            if tail > 0 {
                libc::munmap((start + len) as *mut libc::c_void, tail);
            }
            libc::madvise(start as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
        }
        start as *mut u8
    }

    /// A mapping of at least `size` bytes starting on a 2 MiB boundary,
    /// made of kept pages where there are some (zeroed again if `zeroed`),
    /// the rest fresh; null if the system has no memory for it.
    ///
    /// The kept pages are moved, not copied: `mremap` hands their page
    /// tables to the new address, 2 MiB-aligned on both sides, so huge
    /// pages stay huge. A block's last partial 2 MiB takes the start of a
    /// kept page, whose rest is unmapped. A page the kernel cannot move is
    /// unmapped, and a fresh one mapped in its place.
    pub(super) fn map(size: usize, zeroed: bool) -> *mut u8 {
        let len = mapped(size);
        let start = fresh(len);
        if start.is_null() {
            return start;
        }
        let mut at = 0;
        while at < len {
            let (from, n) = kept().take((len - at).div_ceil(HUGE));
            if n == 0 {
                break;
            }
            let moved = (n * HUGE).min(len - at);
            // SAFETY: the `n` pages at `from` were kept, so are ours alone;
            // `at..at + moved` lies in the block just mapped, which nothing
            // else uses yet.
            let ok = unsafe { move_pages(from, start as usize + at, moved, zeroed) };
            if moved < n * HUGE {
                // SAFETY: the rest of the last page taken is ours alone.
                unsafe { libc::munmap((from + moved) as *mut libc::c_void, n * HUGE - moved) };
            }
            if !ok {
                // SAFETY: the block is ours, and has a hole.
                unsafe { libc::munmap(start.cast(), len) };
                return std::ptr::null_mut();
            }
            at += moved;
        }
        start
    }

    /// Moves the `len` bytes of kept pages at `src` to `dst` (zeroing them
    /// if `zeroed`); if they cannot be moved, unmaps them and maps fresh
    /// pages at `dst`. False if `dst` is left unmapped.
    ///
    /// # Safety
    /// `src..src + len` are kept pages and `dst..dst + len` is part of a
    /// block being made.
    unsafe fn move_pages(src: usize, dst: usize, len: usize, zeroed: bool) -> bool {
        // SAFETY: the caller's: both ranges are ours alone; MREMAP_FIXED
        // replaces the fresh, untouched pages at `dst`.
        let moved = unsafe {
            libc::mremap(
                src as *mut libc::c_void,
                len,
                len,
                libc::MREMAP_MAYMOVE | libc::MREMAP_FIXED,
                dst as *mut libc::c_void,
            )
        };
        if moved != libc::MAP_FAILED {
            if zeroed {
                // SAFETY: `dst..dst + len` is mapped, writable and ours.
                unsafe { std::ptr::write_bytes(dst as *mut u8, 0, len) };
            }
            return true;
        }
        // SAFETY: the caller's: both ranges are ours; MAP_FIXED replaces
        // whatever the failed move left at `dst`.
        unsafe {
            libc::munmap(src as *mut libc::c_void, len);
            let p = libc::mmap(
                dst as *mut libc::c_void,
                len,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_FIXED,
                -1,
                0,
            );
            if p == libc::MAP_FAILED {
                return false;
            }
            libc::madvise(p, len, libc::MADV_HUGEPAGE);
        }
        true
    }

    /// Frees a block of `size` bytes from [`map`] or [`remap`]: its whole
    /// 2 MiB-aligned huge pages are kept for later blocks while the kept
    /// pages stay under `MAX_KEPT`, the rest is unmapped.
    ///
    /// # Safety
    /// `p` and `size` are a live block's.
    pub(super) unsafe fn unmap(p: *mut u8, size: usize) {
        let (start, end) = (p as usize, p as usize + mapped(size));
        let (first, last) = (start.next_multiple_of(HUGE), end & !(HUGE - 1));
        let unmap = |a: usize, b: usize| {
            if a < b {
                // SAFETY: the caller's: `a..b` lies in the block, which
                // is ours and no longer used.
                unsafe { libc::munmap(a as *mut libc::c_void, b - a) };
            }
        };
        if first < last && kept().keep(first, (last - first) / HUGE) {
            unmap(start, first);
            unmap(last, end);
        } else {
            unmap(start, end);
        }
    }

    /// Grows or shrinks a mapped block, moving it if need be (the kernel
    /// moves the pages, not their bytes); null on failure (a block made
    /// of moved pages may not be movable as one), the block then left as
    /// it was. What a block grows by is fresh, so as many kept pages are
    /// unmapped first.
    ///
    /// # Safety
    /// `p` and `old` are a live block's.
    pub(super) unsafe fn remap(p: *mut u8, old: usize, new: usize) -> *mut u8 {
        let (old, new) = (mapped(old), mapped(new));
        if old == new {
            return p;
        }
        release_kept(new.saturating_sub(old));
        // SAFETY: the caller's: `p..p + old` is a block of ours.
        let q = unsafe { libc::mremap(p.cast(), old, new, libc::MREMAP_MAYMOVE) };
        if q == libc::MAP_FAILED {
            return std::ptr::null_mut();
        }
        // SAFETY: `q..q + new` is the mapping just returned.
        unsafe { libc::madvise(q, new, libc::MADV_HUGEPAGE) };
        q.cast()
    }
}

/// Small blocks' bytes are counted per thread and added to the process's
/// count once this many have gathered.
#[cfg(target_os = "linux")]
const SMALL_FLUSH: isize = 256 << 10;

thread_local! {
    #[cfg(target_os = "linux")]
    /// This thread's small-block bytes not yet added to [`SMALL_LIVE`].
    static SMALL_PENDING: std::cell::Cell<isize> = const { std::cell::Cell::new(0) };
}

/// Live bytes of small blocks (the system allocator's), give or take
/// [`SMALL_FLUSH`] a thread.
#[cfg(target_os = "linux")]
static SMALL_LIVE: std::sync::atomic::AtomicIsize = std::sync::atomic::AtomicIsize::new(0);
/// The highest [`SMALL_LIVE`] so far.
#[cfg(target_os = "linux")]
static SMALL_HIGH: std::sync::atomic::AtomicIsize = std::sync::atomic::AtomicIsize::new(0);

/// Counts `delta` bytes of small blocks allocated (or freed, if
/// negative); when their high-water mark rises, as many kept pages are
/// given back, so that kept pages do not raise the peak memory.
#[cfg(target_os = "linux")]
#[inline(always)]
fn count_small(delta: isize) {
    use std::sync::atomic::Ordering::Relaxed;
    // A thread being torn down has no counter left: its blocks go uncounted.
    let _ = SMALL_PENDING.try_with(|pending| {
        let v = pending.get() + delta;
        if v.abs() < SMALL_FLUSH {
            pending.set(v);
            return;
        }
        pending.set(0);
        let live = SMALL_LIVE.fetch_add(v, Relaxed) + v;
        let high = SMALL_HIGH.fetch_max(live, Relaxed);
        if live > high {
            large::small_grew((live - high) as usize);
        }
    });
}

/// Elsewhere no pages are kept, so there is nothing to count.
#[cfg(not(target_os = "linux"))]
#[inline(always)]
fn count_small(_: isize) {}

/// Whether a block of `layout` is mapped on its own.
#[cfg(target_os = "linux")]
fn is_large(layout: &Layout) -> bool {
    layout.size() >= LARGE && layout.align() <= large::PAGE
}

#[cfg(not(target_os = "linux"))]
fn is_large(_: &Layout) -> bool {
    false
}

// SAFETY: small blocks are the system allocator's, under its contract.
// Large blocks are whole mappings of at least their size, aligned to a
// page (which `is_large` requires to satisfy the layout), freed and
// resized only as mappings; which kind a block is follows from its layout
// alone, so `dealloc` and `realloc` see the kind `alloc` chose.
unsafe impl GlobalAlloc for HugePageAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        #[cfg(target_os = "linux")]
        if is_large(&layout) {
            return large::map(layout.size(), false);
        }
        count_small(layout.size() as isize);
        // SAFETY: the caller's (a non-zero size).
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        #[cfg(target_os = "linux")]
        if is_large(&layout) {
            return large::map(layout.size(), true);
        }
        count_small(layout.size() as isize);
        // SAFETY: the caller's (a non-zero size).
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        #[cfg(target_os = "linux")]
        if is_large(&layout) {
            // SAFETY: the caller's: `p` is a live block of `layout`.
            return unsafe { large::unmap(p, layout.size()) };
        }
        count_small(-(layout.size() as isize));
        // SAFETY: the caller's: a small block is the system allocator's.
        unsafe { System.dealloc(p, layout) }
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller's: `new_size`, rounded up to the alignment,
        // does not overflow, and the alignment is a power of two.
        let new = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
        match (is_large(&layout), is_large(&new)) {
            (false, false) => {
                count_small(new_size as isize - layout.size() as isize);
                // SAFETY: the caller's, as for `System`.
                return unsafe { System.realloc(p, layout, new_size) };
            }
            #[cfg(target_os = "linux")]
            (true, true) => {
                // SAFETY: the caller's: `p` is a live block of `layout`.
                let q = unsafe { large::remap(p, layout.size(), new_size) };
                if !q.is_null() {
                    return q;
                }
            }
            _ => {}
        }
        // SAFETY: `new` has a non-zero size (the caller's).
        let q = unsafe { self.alloc(new) };
        if !q.is_null() {
            // SAFETY: both blocks are live, distinct and at least this
            // long; the old one is freed with its layout.
            unsafe {
                std::ptr::copy_nonoverlapping(p, q, layout.size().min(new_size));
                self.dealloc(p, layout);
            }
        }
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes `len` bytes at `p` with a pattern of `seed`.
    unsafe fn fill(p: *mut u8, len: usize, seed: u8) {
        for i in (0..len).step_by(997) {
            // SAFETY: the caller's: `p..p + len` is a live block.
            unsafe { *p.add(i) = seed.wrapping_add(i as u8) };
        }
    }

    /// Checks the pattern of [`fill`] over the first `len` bytes.
    unsafe fn check(p: *const u8, len: usize, seed: u8) {
        for i in (0..len).step_by(997) {
            // SAFETY: the caller's.
            assert_eq!(unsafe { *p.add(i) }, seed.wrapping_add(i as u8), "byte {i}");
        }
    }

    /// The module's tests share the kept pages: one at a time.
    static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

    fn serial() -> std::sync::MutexGuard<'static, ()> {
        SERIAL
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Page faults taken by this thread so far.
    #[cfg(target_os = "linux")]
    fn faults() -> i64 {
        // SAFETY: `getrusage` fills the struct it is given.
        unsafe {
            let mut u: libc::rusage = std::mem::zeroed();
            libc::getrusage(libc::RUSAGE_THREAD, &mut u);
            u.ru_minflt
        }
    }

    /// Writes one byte in each 4 KiB page of `p..p + len`.
    unsafe fn touch(p: *mut u8, len: usize) {
        for i in (0..len).step_by(4096) {
            // SAFETY: the caller's: `p..p + len` is a live block.
            unsafe { *p.add(i) = 1 };
        }
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn freed_pages_move_into_later_blocks_zeroed_when_asked() {
        let _one = serial();
        HugePageAlloc::release_kept();
        assert_eq!(HugePageAlloc::kept_bytes(), 0);
        let a = HugePageAlloc;
        let half = Layout::from_size_align(8 << 20, 8).unwrap();
        let whole = Layout::from_size_align(16 << 20, 8).unwrap();
        // SAFETY: every block is freed with its layout.
        unsafe {
            // A fresh block of 16 MiB costs faults when touched.
            let before = faults();
            let p = a.alloc(whole);
            touch(p, whole.size());
            let fresh = faults() - before;
            a.dealloc(p, whole);
            HugePageAlloc::release_kept();
            // Two written halves, freed, make the next whole block.
            let (x, y) = (a.alloc(half), a.alloc(half));
            fill(x, half.size(), 3);
            fill(y, half.size(), 5);
            a.dealloc(x, half);
            a.dealloc(y, half);
            assert_eq!(HugePageAlloc::kept_bytes(), 16 << 20);
            let before = faults();
            let z = a.alloc_zeroed(whole);
            assert!((z as usize).is_multiple_of(2 << 20));
            assert_eq!(HugePageAlloc::kept_bytes(), 0);
            assert!((0..whole.size()).step_by(997).all(|i| *z.add(i) == 0));
            touch(z, whole.size());
            let reused = faults() - before;
            assert!(fresh > 0 && reused == 0, "fresh {fresh}, reused {reused}");
            // A block's partial last 2 MiB takes the start of a kept page.
            let part = Layout::from_size_align((4 << 20) + 12_345, 8).unwrap();
            let (x, y) = (a.alloc(half), a.alloc(half));
            touch(x, half.size());
            touch(y, half.size());
            a.dealloc(x, half);
            a.dealloc(y, half);
            let before = faults();
            let w = a.alloc(part);
            touch(w, part.size());
            assert_eq!(faults() - before, 0);
            assert_eq!(HugePageAlloc::kept_bytes(), 10 << 20);
            a.dealloc(w, part);
            HugePageAlloc::release_kept();
            // Growing in place unmaps as many kept pages as it adds.
            let small = Layout::from_size_align(2 << 20, 8).unwrap();
            let (x, v) = (a.alloc(half), a.alloc(small));
            a.dealloc(x, half);
            assert_eq!(HugePageAlloc::kept_bytes(), 8 << 20);
            let v = a.realloc(v, small, 6 << 20);
            assert_eq!(HugePageAlloc::kept_bytes(), 4 << 20);
            a.dealloc(v, Layout::from_size_align(6 << 20, 8).unwrap());
            HugePageAlloc::release_kept();
            // A block of moved pages grows, shrinks and frees like any other.
            fill(z, whole.size(), 9);
            let big = 40 << 20;
            let g = a.realloc(z, whole, big);
            assert!(!g.is_null());
            check(g, whole.size(), 9);
            fill(g, big, 11);
            let s = a.realloc(g, Layout::from_size_align(big, 8).unwrap(), 3 << 20);
            check(s, 3 << 20, 11);
            a.dealloc(s, Layout::from_size_align(3 << 20, 8).unwrap());
        }
        HugePageAlloc::release_kept();
        assert_eq!(HugePageAlloc::kept_bytes(), 0);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// Any sequence of allocations, resizes and frees of large blocks,
        /// fresh or made of kept pages, keeps every live block's bytes, and
        /// zeroed blocks come zeroed.
        #[test]
        fn blocks_keep_their_bytes_whatever_was_freed_before(
            ops in proptest::collection::vec((0u8..4, 1usize..12_000_000, 0usize..8), 1..24),
        ) {
            let _one = serial();
            let a = HugePageAlloc;
            let mut live: Vec<(*mut u8, Layout, u8)> = Vec::new();
            for (k, (op, size, which)) in ops.into_iter().enumerate() {
                let seed = k as u8;
                let layout = Layout::from_size_align(size.max(LARGE), 8).unwrap();
                // SAFETY: every live block is freed once, with its layout.
                unsafe {
                    match op {
                        0 | 1 => {
                            let p = if op == 0 { a.alloc(layout) } else { a.alloc_zeroed(layout) };
                            proptest::prop_assert!(!p.is_null());
                            if op == 1 {
                                proptest::prop_assert!((0..layout.size()).step_by(4093).all(|i| *p.add(i) == 0));
                            }
                            fill(p, layout.size(), seed);
                            live.push((p, layout, seed));
                        }
                        2 if !live.is_empty() => {
                            let (p, old, s) = live.remove(which % live.len());
                            let q = a.realloc(p, old, layout.size());
                            proptest::prop_assert!(!q.is_null());
                            check(q, old.size().min(layout.size()), s);
                            fill(q, layout.size(), seed);
                            live.push((q, layout, seed));
                        }
                        _ if !live.is_empty() => {
                            let (p, l, s) = live.remove(which % live.len());
                            check(p, l.size(), s);
                            a.dealloc(p, l);
                        }
                        _ => {}
                    }
                }
            }
            for (p, l, s) in live {
                // SAFETY: as above.
                unsafe {
                    check(p, l.size(), s);
                    a.dealloc(p, l);
                }
            }
        }
    }

    #[test]
    fn blocks_keep_their_bytes_across_every_kind_of_resize() {
        let _one = serial();
        let a = HugePageAlloc;
        // small → small → large → larger → smaller large → small.
        let sizes = [
            1000,
            200_000,
            LARGE + 12_345,
            5 * LARGE + 7,
            3 * LARGE,
            3 * LARGE + 10,
            40_000,
        ];
        let mut layout = Layout::from_size_align(sizes[0], 8).unwrap();
        // SAFETY: every block is live while used and freed with its layout.
        unsafe {
            let mut p = a.alloc(layout);
            assert!(!p.is_null());
            fill(p, layout.size(), 7);
            for &n in &sizes[1..] {
                let kept = layout.size().min(n);
                p = a.realloc(p, layout, n);
                assert!(!p.is_null() && (p as usize).is_multiple_of(8));
                check(p, kept, 7);
                layout = Layout::from_size_align(n, 8).unwrap();
                fill(p, n, 7);
            }
            a.dealloc(p, layout);
        }
    }

    #[test]
    fn large_blocks_start_on_huge_page_boundaries_and_are_zeroed() {
        let _one = serial();
        let layout = Layout::from_size_align(3 * LARGE + 1, 64).unwrap();
        // SAFETY: the block is freed with its layout.
        unsafe {
            let p = HugePageAlloc.alloc_zeroed(layout);
            assert!(!p.is_null());
            if cfg!(target_os = "linux") {
                assert!((p as usize).is_multiple_of(2 << 20));
            }
            assert!((0..layout.size()).step_by(4096).all(|i| *p.add(i) == 0));
            assert_eq!(*p.add(layout.size() - 1), 0);
            HugePageAlloc.dealloc(p, layout);
        }
    }

    #[test]
    fn vectors_grow_and_shrink_through_it() {
        let _one = serial();
        // Through the trait, as `Vec` with a global allocator would.
        let a = HugePageAlloc;
        let mut layout = Layout::array::<u32>(1).unwrap();
        // SAFETY: as above.
        unsafe {
            let mut p = a.alloc(layout).cast::<u32>();
            let mut cap = 1usize;
            for i in 0..1_000_000u32 {
                if i as usize == cap {
                    let grown = Layout::array::<u32>(cap * 2).unwrap();
                    p = a.realloc(p.cast(), layout, grown.size()).cast();
                    assert!(!p.is_null());
                    (layout, cap) = (grown, cap * 2);
                }
                p.add(i as usize).write(i);
            }
            assert!((0..1_000_000u32).all(|i| *p.add(i as usize) == i));
            a.dealloc(p.cast(), layout);
        }
    }
}
