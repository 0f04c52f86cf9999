//! A stable least-significant-digit radix sort, parallel over chunks when
//! asked (the build's sort of (cell key, primitive) pairs, after Kalojanov &
//! Slusallek 2009, "A parallel algorithm for construction of uniform grids").

use crate::par::{chunk_bounds, chunk_count, map_indices, SharedMut};

/// The widest digit: 4096 buckets, whose write streams still fit in L2.
const MAX_DIGIT_BITS: u32 = 12;

/// Below this length the standard library's stable sort is used.
const SMALL: usize = 1 << 12;

/// The chunks of `len` items that [`sort_by_key`] histograms.
pub(crate) fn chunks(len: usize, parallel: bool) -> usize {
    chunk_count(len, parallel, 1 << 16)
}

/// Sorts `data` stably by `key(x)`, of which only the low `key_bits` bits may
/// be set. `tmp` is scratch space (resized as needed). `counted`, if given,
/// holds the histograms of `key(x)` over each of the [`chunks`] chunks of
/// `data` (a caller that counted the keys while making the items saves a
/// pass over them); only for a single pass: `key_bits` at most
/// [`MAX_DIGIT_BITS`].
///
/// # Panics
///
/// If `data` has more than `u32::MAX` items, or if `counted` is not the
/// histograms of `data`'s keys (one of `2^key_bits` buckets per chunk,
/// counting those keys), unless the wrong histograms put every item in one
/// bucket: then `data` is left as it is. Memory stays safe either way.
pub(crate) fn sort_by_key<T, K>(
    data: &mut Vec<T>,
    tmp: &mut Vec<T>,
    key_bits: u32,
    key: K,
    parallel: bool,
    mut counted: Option<Vec<Vec<u32>>>,
) where
    T: Copy + Send + Sync,
    K: Fn(&T) -> u64 + Sync + Send,
{
    let len = data.len();
    if key_bits == 0 || len < 2 {
        return;
    }
    if len < SMALL {
        data.sort_by_key(|x| key(x));
        return;
    }
    // Positions are kept in `u32`s (half the cache of `usize`s).
    assert!(u32::try_from(len).is_ok(), "at most u32::MAX items");
    let passes = key_bits.div_ceil(MAX_DIGIT_BITS);
    let width = key_bits.div_ceil(passes);
    let buckets = 1usize << width;
    let mask = (buckets - 1) as u64;
    let chunks = chunks(len, parallel);
    assert!(
        counted.is_none() || passes == 1,
        "histograms of another sort"
    );
    for pass in 0..passes {
        let shift = pass * width;
        let digit = |x: &T| ((key(x) >> shift) & mask) as usize;
        // Per-chunk histograms of this digit.
        let src: &[T] = data;
        let hists = counted
            .take()
            .unwrap_or_else(|| histograms(src, chunks, buckets, parallel, digit));
        // All items in one bucket: this digit is constant, the pass would not move anything.
        let mut totals = vec![0usize; buckets];
        for h in &hists {
            for (t, &c) in totals.iter_mut().zip(h) {
                *t += c as usize;
            }
        }
        if totals.contains(&len) {
            continue;
        }
        // Only a caller's histograms can fail this.
        assert_eq!(
            totals.iter().sum::<usize>(),
            len,
            "histograms of another sort"
        );
        // Chunk c's items of bucket b go after all items of smaller buckets
        // and after chunk c' < c's items of bucket b: this keeps the sort stable.
        let mut starts = vec![vec![0u32; buckets]; chunks];
        let mut acc = 0u32;
        for b in 0..buckets {
            for c in 0..chunks {
                starts[c][b] = acc;
                acc += hists[c][b];
            }
        }
        tmp.clear();
        if tmp.capacity() < len {
            *tmp = Vec::with_capacity(len);
            crate::mem::advise_huge(tmp);
        }
        let dst = SharedMut(tmp.as_mut_ptr());
        let (starts, hists) = (&starts, &hists);
        map_indices(chunks, parallel, |c| {
            let (s, e) = chunk_bounds(len, chunks, c);
            let mut pos = starts[c].clone();
            let ends: Vec<u32> = pos.iter().zip(&hists[c]).map(|(&p, &h)| p + h).collect();
            for (i, x) in (s..).zip(&src[s..e]) {
                crate::mem::prefetch_at(src, i, false);
                let d = digit(x);
                let p = pos[d];
                // A histogram that undercounts (the caller's) is refused
                // before it could write into another chunk's positions.
                assert!(p < ends[d], "histograms of another sort");
                // SAFETY: positions [starts[c][b], ends[b]) are this chunk's
                // alone, and all lie below `len`.
                unsafe { dst.write(p as usize, *x) };
                pos[d] = p + 1;
            }
        });
        // SAFETY: no chunk wrote past the end of its bucket ranges, which
        // partition `0..len`, and as many items were written as the counts
        // add up to, `len`: so every position below `len` was written
        // exactly once, within the reserved capacity.
        unsafe { tmp.set_len(len) };
        std::mem::swap(data, tmp);
    }
}

/// The histogram of `digit` over each of `chunks` chunks of `src`.
fn histograms<T: Sync>(
    src: &[T],
    chunks: usize,
    buckets: usize,
    parallel: bool,
    digit: impl Fn(&T) -> usize + Sync + Send,
) -> Vec<Vec<u32>> {
    map_indices(chunks, parallel, |c| {
        let (s, e) = chunk_bounds(src.len(), chunks, c);
        let mut h = vec![0u32; buckets];
        for (i, x) in (s..).zip(&src[s..e]) {
            crate::mem::prefetch_at(src, i, false);
            h[digit(x)] += 1;
        }
        h
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(s: &mut u64) -> u64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *s >> 33
    }

    #[test]
    fn sorts_stably_like_std() {
        for &(n, bits) in &[
            (10usize, 5u32),
            (5000, 7),
            (70_000, 24),
            (100_000, 30),
            (20_000, 40),
        ] {
            let mut s = 7u64;
            let mut v: Vec<(u64, u32)> = (0..n as u32)
                .map(|i| (lcg(&mut s) & ((1u64 << bits) - 1), i))
                .collect();
            let mut want = v.clone();
            want.sort_by_key(|x| x.0);
            for parallel in [false, true] {
                let mut got = v.clone();
                let mut tmp = Vec::new();
                sort_by_key(&mut got, &mut tmp, bits, |x| x.0, parallel, None);
                assert_eq!(got, want, "n = {n}, bits = {bits}, parallel = {parallel}");
            }
            v.clear();
        }
    }

    /// Histograms counted by the caller give the same sort; histograms of
    /// other items are refused.
    #[test]
    fn counted_histograms_sort_alike() {
        let bits = 11;
        let mut s = 3u64;
        let v: Vec<(u64, u32)> = (0..300_000)
            .map(|i| (lcg(&mut s) & ((1 << bits) - 1), i))
            .collect();
        let mut want = v.clone();
        want.sort_by_key(|x| x.0);
        for parallel in [false, true] {
            let n = chunks(v.len(), parallel);
            let hists = histograms(&v, n, 1 << bits, parallel, |x| x.0 as usize);
            let mut got = v.clone();
            let mut tmp = Vec::new();
            // One count too many; one moved to the wrong bucket (the total
            // still right): both refused.
            let mut extra = hists.clone();
            extra[0][0] += 1;
            let mut moved = hists.clone();
            moved[0][0] += 1;
            moved[0][1] -= 1;
            for wrong in [extra, moved] {
                let items = v.clone();
                let refused = std::panic::catch_unwind(move || {
                    let (mut got, mut tmp) = (items, Vec::new());
                    sort_by_key(&mut got, &mut tmp, bits, |x| x.0, parallel, Some(wrong));
                });
                assert!(refused.is_err());
            }
            sort_by_key(&mut got, &mut tmp, bits, |x| x.0, parallel, Some(hists));
            assert_eq!(got, want, "parallel = {parallel}");
        }
    }
}
