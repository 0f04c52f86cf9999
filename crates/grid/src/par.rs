//! The little parallelism the build needs, with one sequential fallback, so
//! the same code runs with and without the `rayon` feature.

/// Runs `f(i)` for `i in 0..n`, in parallel when `parallel` is true and the
/// `rayon` feature is on, and returns the results in order.
pub(crate) fn map_indices<R: Send>(
    n: usize,
    parallel: bool,
    f: impl Fn(usize) -> R + Sync + Send,
) -> Vec<R> {
    #[cfg(feature = "rayon")]
    if parallel && n > 1 {
        use rayon::prelude::*;
        return (0..n).into_par_iter().map(f).collect();
    }
    let _ = parallel;
    (0..n).map(f).collect()
}

/// `(0..n).map(f).collect()`, in parallel when `parallel` is true and the
/// `rayon` feature is on (writing straight into the result, on huge pages
/// where possible).
pub(crate) fn map_range<R: Send>(
    n: usize,
    parallel: bool,
    f: impl Fn(usize) -> R + Sync + Send,
) -> Vec<R> {
    let mut out = crate::mem::with_capacity(n);
    #[cfg(feature = "rayon")]
    if parallel {
        use rayon::prelude::*;
        (0..n)
            .into_par_iter()
            .with_min_len(1 << 14)
            .map(f)
            .collect_into_vec(&mut out);
        return out;
    }
    let _ = parallel;
    out.extend((0..n).map(f));
    out
}

/// How many chunks to split `len` items into: one when sequential, a few
/// per thread otherwise (for load balance), never more than `len / min_chunk`.
pub(crate) fn chunk_count(len: usize, parallel: bool, min_chunk: usize) -> usize {
    #[cfg(feature = "rayon")]
    if parallel {
        let want = rayon::current_num_threads() * 4;
        return want.min(len / min_chunk.max(1)).max(1);
    }
    let _ = (len, parallel, min_chunk);
    1
}

/// The number of worker threads a parallel phase may use (1 when sequential).
pub(crate) fn threads(parallel: bool) -> usize {
    #[cfg(feature = "rayon")]
    if parallel {
        return rayon::current_num_threads();
    }
    let _ = parallel;
    1
}

/// The bounds `[start, end)` of chunk `c` of `chunks` over `len` items.
#[inline]
pub(crate) fn chunk_bounds(len: usize, chunks: usize, c: usize) -> (usize, usize) {
    let start = len * c / chunks;
    let end = len * (c + 1) / chunks;
    (start, end)
}

/// A raw pointer that may be shared between the build's worker threads.
/// Every use writes to index ranges that no other thread touches.
#[derive(Clone, Copy)]
pub(crate) struct SharedMut<T>(pub *mut T);
// SAFETY: the build only writes through it to disjoint ranges, one per worker,
// and reads happen after all workers have joined.
unsafe impl<T: Send> Send for SharedMut<T> {}
// SAFETY: as above.
unsafe impl<T: Send> Sync for SharedMut<T> {}

impl<T> SharedMut<T> {
    /// Writes `v` at index `i`.
    ///
    /// # Safety
    /// `i` must be in bounds of the allocation, and no other thread may
    /// access index `i` concurrently.
    #[inline]
    pub(crate) unsafe fn write(self, i: usize, v: T) {
        // SAFETY: guaranteed by the caller.
        unsafe { self.0.add(i).write(v) }
    }

    /// Moves the value at index `i` out (a bitwise read).
    ///
    /// # Safety
    /// `i` must be in bounds and initialised; the value must be read once
    /// and not dropped in place afterwards, and no thread may write index
    /// `i` concurrently.
    #[inline]
    pub(crate) unsafe fn read(&self, i: usize) -> T {
        // SAFETY: guaranteed by the caller.
        unsafe { self.0.add(i).read() }
    }

    /// Asks the processor to load index `i`, which must be in bounds.
    #[inline]
    pub(crate) fn prefetch(&self, i: usize) {
        crate::mem::prefetch_ptr(self.0.wrapping_add(i));
    }
}
