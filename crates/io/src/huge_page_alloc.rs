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

#[cfg(target_os = "linux")]
mod large {
    /// Huge page size on x86-64 and (with 4 KiB pages) aarch64.
    const HUGE: usize = 2 << 20;
    /// The alignment every mapping has (the smallest page size).
    pub(super) const PAGE: usize = 4096;

    /// The length a block of `size` bytes is mapped with.
    fn mapped(size: usize) -> usize {
        size.next_multiple_of(PAGE)
    }

    /// A fresh (zeroed) mapping of at least `size` bytes starting on a
    /// 2 MiB boundary, advised to use huge pages; null if the system has
    /// no memory for it.
    pub(super) fn map(size: usize) -> *mut u8 {
        let len = mapped(size);
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

    /// Unmaps a block of `size` bytes from [`map`] or [`remap`].
    ///
    /// # Safety
    /// `p` and `size` are a live block's.
    pub(super) unsafe fn unmap(p: *mut u8, size: usize) {
        // SAFETY: the caller's; the block was mapped with this length.
        unsafe { libc::munmap(p.cast(), mapped(size)) };
    }

    /// Grows or shrinks a mapped block, moving it if need be (the kernel
    /// moves the pages, not their bytes); null on failure, the block then
    /// left as it was.
    ///
    /// # Safety
    /// `p` and `old` are a live block's.
    pub(super) unsafe fn remap(p: *mut u8, old: usize, new: usize) -> *mut u8 {
        let (old, new) = (mapped(old), mapped(new));
        if old == new {
            return p;
        }
        // SAFETY: the caller's: `p..p + old` is one mapping of ours.
        let q = unsafe { libc::mremap(p.cast(), old, new, libc::MREMAP_MAYMOVE) };
        if q == libc::MAP_FAILED {
            return std::ptr::null_mut();
        }
        // SAFETY: `q..q + new` is the mapping just returned.
        unsafe { libc::madvise(q, new, libc::MADV_HUGEPAGE) };
        q.cast()
    }
}

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
            return large::map(layout.size());
        }
        // SAFETY: the caller's (a non-zero size).
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if is_large(&layout) {
            // A fresh mapping is zeroed already.
            // SAFETY: the caller's (a non-zero size).
            return unsafe { self.alloc(layout) };
        }
        // SAFETY: the caller's (a non-zero size).
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        #[cfg(target_os = "linux")]
        if is_large(&layout) {
            // SAFETY: the caller's: `p` is a live block of `layout`.
            return unsafe { large::unmap(p, layout.size()) };
        }
        // SAFETY: the caller's: a small block is the system allocator's.
        unsafe { System.dealloc(p, layout) }
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller's: `new_size`, rounded up to the alignment,
        // does not overflow, and the alignment is a power of two.
        let new = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
        match (is_large(&layout), is_large(&new)) {
            // SAFETY: the caller's, as for `System`.
            (false, false) => unsafe { System.realloc(p, layout, new_size) },
            #[cfg(target_os = "linux")]
            // SAFETY: the caller's: `p` is a live mapping of `layout`.
            (true, true) => unsafe { large::remap(p, layout.size(), new_size) },
            _ => {
                // SAFETY: `new` has a non-zero size (the caller's).
                let q = unsafe { self.alloc(new) };
                if !q.is_null() {
                    // SAFETY: both blocks are live, distinct and at least
                    // this long; the old one is freed with its layout.
                    unsafe {
                        std::ptr::copy_nonoverlapping(p, q, layout.size().min(new_size));
                        self.dealloc(p, layout);
                    }
                }
                q
            }
        }
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

    #[test]
    fn blocks_keep_their_bytes_across_every_kind_of_resize() {
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
