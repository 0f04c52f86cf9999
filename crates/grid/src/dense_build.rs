//! The dense build: Lagae & Dutré's compact grid (2008, "Compact, fast and
//! robust grids for ray tracing"). Count the references per cell, prefix-sum
//! the counts into offsets, then fill the one flat reference array. No
//! `(cell, primitive)` pairs are materialised: what is sorted is one record
//! per primitive.
//!
//! Each primitive's cell range is computed once, in parallel, and kept in an
//! 8-byte record (its first cell and which of the 2×2×2 cells after it it
//! covers; larger ranges are recomputed from the bounds when needed). The
//! records are then sorted (one radix pass) by the run
//! of row-major cells their range starts in, so that counting and filling
//! sweep the offsets nearly in order instead of at random: a scene's
//! primitives usually come in no spatial order, and random increments into
//! a large offset table would miss the cache at every step.
//! Counting and filling are split by slabs of cells along z, a few per
//! worker with about as many records each: a worker reads only the window
//! of sorted records that can reach its slab and touches only the offsets
//! and references of that slab, so no two workers write the same memory
//! and no atomics are needed. Sequentially there is a single slab.
//! Counting visits all eight cells of a record's 2×2×2 block and adds 0 or
//! 1 to each, so it does not branch on the range's shape (1, 2, 4 or 8
//! cells, nearly at random: a branch mispredicted about once per record);
//! filling writes the range's cells only, where the branches cost less.
//! The passes over the records (and over the primitives) prefetch ahead.

use crate::cells::CellsOut;
use crate::geom::Geom;
use crate::par::{chunk_bounds, chunk_count, map_indices, SharedMut};
use crate::radix;
use crate::{GridConfig, Primitive};
use std::ops::Range;

/// One primitive's cell range, packed in a `u64`: the primitive index in
/// bits 0..32, a shape code in bits 32..36 and the row-major index of the
/// range's first cell in bits 36..64. Codes 0..8 are a range of at most two
/// cells per axis (bit `a` set: two cells along axis `a`); [`GENERAL`] means
/// anything else, recomputed from the primitive's bounds when used (as is
/// every range when the grid has more than 2^28 cells).
type Record = u64;

/// The code of a range that is not within 2×2×2 cells.
const GENERAL: u64 = 8;
/// Bits of the first cell's index.
const BASE_SHIFT: u32 = 36;

#[inline(always)]
fn record(prim: u32, code: u64, base: usize) -> Record {
    u64::from(prim) | (code << 32) | ((base as u64) << BASE_SHIFT)
}

/// Builds dense offsets and references; `None` past `ref_limit` references.
/// The records are sorted by their first cell exactly, the references are
/// record positions (slots), and the last element of the result is the
/// primitive of each slot.
/// `all_gridded`: every primitive's box is known to be finite (the bounds
/// pass saw no other), so the ranges pass need not check again.
pub(crate) fn build_dense<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    g: &Geom,
    config: &GridConfig,
    ref_limit: u64,
    all_gridded: bool,
) -> Option<(CellsOut, Box<[u32]>)> {
    let parallel = config.parallel_build;
    let exact = config.exact_insertion;
    let n = prims.len();
    let [nx, ny, nz] = g.dims.map(|d| d as usize);
    let nxy = nx * ny;
    let cells = nxy * nz;
    if cells > u32::MAX as usize {
        return None;
    }
    // Whether a first cell's index fits the record's 28 bits.
    let packable = cells <= 1 << (64 - BASE_SHIFT);

    // The radix pass's runs (below): 2^shift row-major cells each.
    let cell_bits = 64 - (cells as u64).leading_zeros();
    let shift = cell_bits.saturating_sub(12);
    let sorted = packable && cell_bits > shift;
    // Ranges, in parallel over chunks of primitives, each written where its
    // primitives are (one buffer, no concatenation); the total is an upper
    // bound of the references (exact insertion may drop some). Each chunk
    // also counts its records per run: the radix pass's histogram, if no
    // primitive is left out (the chunks are the radix pass's).
    let chunks = radix::chunks(n, parallel);
    let mut ranges: Vec<Record> = crate::mem::with_capacity(n);
    let dst = SharedMut(ranges.as_mut_ptr());
    // `move`: the switches and sizes are the closure's own values, which the
    // compiler keeps in registers (read through references, they would be
    // reloaded at every primitive, the records' writes aliasing them).
    let parts = map_indices(chunks, parallel, move |c| {
        let (s, e) = chunk_bounds(n, chunks, c);
        let mut len = 0;
        let mut volume = 0u64;
        let mut generals = 0usize;
        let mut hist = vec![0u32; if sorted { 1 << (cell_bits - shift) } else { 0 }];
        for (prim, p) in (s as u32..).zip(&prims[s..e]) {
            crate::mem::prefetch_at(prims, prim as usize, false);
            let b = p.bounds(shared);
            if !all_gridded && !g.holds(&b) {
                continue;
            }
            let (lo, hi) = g.cell_range(&b);
            let ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
            volume += u64::from(ext[0] + 1) * u64::from(ext[1] + 1) * u64::from(ext[2] + 1);
            let base = lo[0] as usize + lo[1] as usize * nx + lo[2] as usize * nxy;
            let code = if (ext[0] | ext[1] | ext[2]) <= 1 && packable {
                u64::from(ext[0] | (ext[1] << 1) | (ext[2] << 2))
            } else {
                GENERAL
            };
            generals += usize::from(code == GENERAL);
            if sorted {
                hist[base >> shift] += 1;
            }
            // SAFETY: chunk `c` writes only positions `s..s + len`, `len <=
            // e - s`, within the capacity `n`.
            unsafe { dst.write(s + len, record(prim, code, if packable { base } else { 0 })) };
            len += 1;
        }
        (s, len, volume, generals, hist)
    });
    // Close the gaps left by primitives that are not gridded (if any).
    let mut total = 0;
    for &(s, len, ..) in &parts {
        if s != total {
            // SAFETY: positions `s..s + len` were written above and
            // `total <= s`; `copy` handles the overlap.
            unsafe { std::ptr::copy(dst.0.add(s), dst.0.add(total), len) };
        }
        total += len;
    }
    // SAFETY: positions `0..total` now hold the records, in primitive order.
    unsafe { ranges.set_len(total) };
    let volume: u64 = parts.iter().map(|p| p.2).sum();
    if volume > ref_limit {
        return None;
    }
    let generals: usize = parts.iter().map(|p| p.3).sum();
    // Order the records by the run of 2^shift row-major cells their first
    // cell is in (one stable radix pass of at most 12 bits): counting and
    // filling then sweep the offsets nearly in order. Slots follow the
    // record order, so for them each run is then sorted by first cell too.
    if sorted {
        let mut tmp = Vec::new();
        let counted = (total == n).then(|| parts.into_iter().map(|p| p.4).collect());
        radix::sort_by_key(
            &mut ranges,
            &mut tmp,
            cell_bits - shift,
            |r: &Record| r >> (BASE_SHIFT + shift),
            parallel,
            counted,
        );
        if shift > 0 {
            sort_runs(&mut ranges, shift, parallel);
        }
    }
    let slabs = slabs(&ranges, g, sorted, shift, generals, parallel);

    // Count (per slab), then an inclusive prefix sum: offsets[c] = end of cell c.
    let corners = corners(g);
    let span = corners[7];
    let mut offsets = crate::mem::filled(cells + 1, 0u32);
    let (occupied, max_refs);
    {
        let mut rest: &mut [u32] = &mut offsets[..cells];
        let mut slab_counts = Vec::with_capacity(slabs.len());
        for slab in &slabs {
            let (head, tail) = rest.split_at_mut((slab.z1 - slab.z0) * nxy);
            slab_counts.push((slab, head));
            rest = tail;
        }
        let ranges = &ranges;
        let slab_totals: Vec<(u64, u32, u64)> =
            map_slabs(slab_counts, parallel, |(slab, counts)| {
                let mut count = Count {
                    counts: &mut *counts,
                    lo: slab.z0 * nxy,
                    corners,
                };
                for_each_ref(prims, shared, g, ranges, slab, exact, false, &mut count);
                // Local inclusive scan, with the slab's occupancy and largest cell.
                let mut acc = 0u32;
                let mut occupied = 0u64;
                let mut max = 0u32;
                for x in counts.iter_mut() {
                    let k = *x;
                    occupied += u64::from(k != 0);
                    max = max.max(k);
                    acc += k;
                    *x = acc;
                }
                (u64::from(acc), max, occupied)
            });
        // Slab bases, then add them (in parallel).
        let mut base = 0u32;
        let mut bases = Vec::with_capacity(slabs.len());
        for t in &slab_totals {
            bases.push(base);
            base += t.0 as u32;
        }
        offsets[cells] = base;
        let mut rest: &mut [u32] = &mut offsets[..cells];
        let mut work = Vec::with_capacity(slabs.len());
        for (slab, &b) in slabs.iter().zip(&bases) {
            let (head, tail) = rest.split_at_mut((slab.z1 - slab.z0) * nxy);
            work.push((b, head));
            rest = tail;
        }
        map_slabs(work, parallel, |(b, xs)| {
            if b != 0 {
                for x in xs.iter_mut() {
                    *x += b;
                }
            }
        });
        occupied = slab_totals.iter().map(|t| t.2).sum();
        max_refs = slab_totals.iter().map(|t| t.1).max().unwrap_or(0);
    }
    let total = offsets[cells] as usize;

    // Fill: walking the records backwards and filling each cell from its
    // end leaves every offset at its cell's start (and each run in record
    // order: by block, then primitive).
    let mut refs = crate::mem::filled(total, 0u32);
    {
        let mut rest_o: &mut [u32] = &mut offsets[..cells];
        let mut rest_r: &mut [u32] = &mut refs[..];
        let mut work = Vec::with_capacity(slabs.len());
        let mut consumed = 0usize;
        for slab in &slabs {
            let (oh, ot) = rest_o.split_at_mut((slab.z1 - slab.z0) * nxy);
            let end = oh.last().map_or(consumed, |&e| e as usize);
            let (rh, rt) = rest_r.split_at_mut(end - consumed);
            work.push((slab, oh, rh, consumed));
            consumed = end;
            rest_o = ot;
            rest_r = rt;
        }
        let ranges = &ranges;
        // For each shape code, the corners in its range.
        let shapes: [[usize; 8]; 8] = std::array::from_fn(|code| {
            let mut out = [0; 8];
            let inside = (0..8).filter(|i| IN_RANGE[code] >> i & 1 != 0);
            for (slot, i) in out.iter_mut().zip(inside) {
                *slot = corners[i];
            }
            out
        });
        map_slabs(work, parallel, |(slab, offs, out, base)| {
            let mut fill = Fill {
                offs,
                out,
                lo: slab.z0 * nxy,
                base,
                span,
                shapes: &shapes,
            };
            for_each_ref(prims, shared, g, ranges, slab, exact, true, &mut fill);
        });
    }
    let ids =
        crate::par::map_range(ranges.len(), parallel, |i| ranges[i] as u32).into_boxed_slice();
    Some((
        (
            crate::cells::Cells::Dense {
                offsets: offsets.into_boxed_slice(),
            },
            refs.into_boxed_slice(),
            [Box::new([]), Box::new([]), Box::new([])],
            occupied,
            max_refs,
        ),
        ids,
    ))
}

/// A slab of whole z-layers `z0..z1` of cells, and the records that may
/// have references in it: `before`, then `window` (positions in the sorted
/// records).
struct Slab {
    z0: usize,
    z1: usize,
    window: Range<usize>,
    /// The records of [`GENERAL`] ranges before the window (which may reach
    /// any layer), in order.
    before: Vec<usize>,
}

/// Splits the grid into slabs for counting and filling: one when
/// sequential, else a few per worker, with about as many records each.
///
/// When the records are `sorted` by `first cell >> shift`, a slab's window
/// holds just the records that can reach it: a range of at most two cells
/// per axis starts at most one layer, one row and one cell before its
/// cells. The rare [`GENERAL`] ranges, which may start anywhere before,
/// are listed apart (`generals` of them). Unsorted records are all
/// scanned by every slab, so then there is one slab per worker.
fn slabs(
    ranges: &[Record],
    g: &Geom,
    sorted: bool,
    shift: u32,
    generals: usize,
    parallel: bool,
) -> Vec<Slab> {
    let [nx, ny, nz] = g.dims.map(|d| d as usize);
    let nxy = nx * ny;
    let cells = nxy * nz;
    let threads = crate::par::threads(parallel);
    let want = if sorted { threads * 4 } else { threads };
    let count = want.min(nz).min(cells / (1 << 14)).max(1);
    let all = |z0, z1| Slab {
        z0,
        z1,
        window: 0..ranges.len(),
        before: Vec::new(),
    };
    if count == 1 {
        return vec![all(0, nz)];
    }
    if !sorted {
        return (0..count)
            .map(|s| {
                let (z0, z1) = chunk_bounds(nz, count, s);
                all(z0, z1)
            })
            .collect();
    }
    let first = |r: &Record| (r >> BASE_SHIFT) as usize;
    let key = |r: &Record| first(r) >> shift;
    // Cut where the records' first cells reach the quantiles' layers.
    let mut cuts = Vec::with_capacity(count + 1);
    cuts.push(0);
    for s in 1..count {
        let z = first(&ranges[ranges.len() * s / count]) / nxy;
        cuts.push(z.max(cuts[s - 1]));
    }
    cuts.push(nz);
    let general_at: Vec<usize> = if generals == 0 {
        Vec::new()
    } else {
        (0..ranges.len())
            .filter(|&i| (ranges[i] >> 32) & 0xf == GENERAL)
            .collect()
    };
    cuts.windows(2)
        .map(|w| {
            let (lin0, lin1) = (w[0] * nxy, w[1] * nxy);
            if lin0 == lin1 {
                return Slab {
                    z0: w[0],
                    z1: w[1],
                    window: 0..0,
                    before: Vec::new(),
                };
            }
            let lo = lin0.saturating_sub(nxy + nx + 1) >> shift;
            let hi = (lin1 - 1) >> shift;
            let start = ranges.partition_point(|r| key(r) < lo);
            let end = ranges.partition_point(|r| key(r) <= hi);
            Slab {
                z0: w[0],
                z1: w[1],
                window: start..end,
                before: general_at
                    .iter()
                    .copied()
                    .take_while(|&i| i < start)
                    .collect(),
            }
        })
        .collect()
}

/// Sorts each run of records with the same `first cell >> shift` by first
/// cell, stably (so equal first cells stay in primitive order). The runs
/// are short (a few hundred records over `2^shift` cells), so each is
/// sorted in cache by counting, or by comparison when its cells far
/// outnumber its records.
fn sort_runs(ranges: &mut [Record], shift: u32, parallel: bool) {
    let run = |r: &Record| r >> (BASE_SHIFT + shift);
    let cell = |r: &Record| ((r >> BASE_SHIFT) & ((1 << shift) - 1)) as usize;
    // Chunks of whole runs: each nominal start moves up to a run's start.
    let len = ranges.len();
    let chunks = chunk_count(len, parallel, 1 << 16);
    let mut starts: Vec<usize> = (0..chunks)
        .map(|c| {
            let mut i = chunk_bounds(len, chunks, c).0;
            while i > 0 && i < len && run(&ranges[i]) == run(&ranges[i - 1]) {
                i += 1;
            }
            i
        })
        .collect();
    starts.push(len);
    let mut parts = Vec::with_capacity(chunks);
    let mut rest = ranges;
    for w in starts.windows(2) {
        // The first run start at or after a nominal start never decreases.
        let (head, tail) = rest.split_at_mut(w[1] - w[0]);
        parts.push(head);
        rest = tail;
    }
    map_slabs(parts, parallel, |part| {
        let buckets = 1usize << shift;
        // Bucket starts, then next free positions; and the run's records
        // by cell. Both reused from run to run, never cleared in full.
        let mut counts = vec![0u32; buckets + 1];
        let mut tmp: Vec<Record> = Vec::new();
        let mut i = 0;
        while i < part.len() {
            let key = run(&part[i]);
            let n = part[i..]
                .iter()
                .position(|r| run(r) != key)
                .unwrap_or(part.len() - i);
            let group = &mut part[i..i + n];
            i += n;
            if n < 2 {
                continue;
            }
            if buckets > 8 * n {
                group.sort_by_key(cell);
                continue;
            }
            counts.fill(0);
            for r in group.iter() {
                // SAFETY: `cell` is below `buckets` (masked by `shift` bits).
                unsafe { *counts.get_unchecked_mut(cell(r) + 1) += 1 };
            }
            let mut acc = 0;
            for c in counts.iter_mut() {
                acc += *c;
                *c = acc;
            }
            if tmp.len() < n {
                tmp.resize(n, 0);
            }
            for &r in group.iter() {
                // SAFETY: as above; the starts of the buckets `cell(r)` (each
                // advanced once per record in it) stay below `n`, the total.
                unsafe {
                    let slot = counts.get_unchecked_mut(cell(&r));
                    *tmp.get_unchecked_mut(*slot as usize) = r;
                    *slot += 1;
                }
            }
            group.copy_from_slice(&tmp[..n]);
        }
    });
}

/// Runs `f` on every work item, in parallel when asked.
fn map_slabs<W: Send, R: Send>(
    work: Vec<W>,
    parallel: bool,
    f: impl Fn(W) -> R + Sync + Send,
) -> Vec<R> {
    #[cfg(feature = "rayon")]
    if parallel && work.len() > 1 {
        use rayon::prelude::*;
        return work.into_par_iter().map(f).collect();
    }
    let _ = parallel;
    work.into_iter().map(f).collect()
}

/// Hands the records to `v`, in order (reversed when `rev`), each with
/// its slot (its position in the records): to [`Visitor::block`] for a
/// record of at most 2×2×2 cells whose block lies wholly in the slab, else
/// to [`Visitor::cell`] for every cell of its range in the slab.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the primitives, what they share, the geometry and the build's switches
fn for_each_ref<P: Primitive, V: Visitor>(
    prims: &[P],
    shared: &P::Shared,
    g: &Geom,
    ranges: &[Record],
    slab: &Slab,
    exact: bool,
    rev: bool,
    v: &mut V,
) {
    let [nx, ny, nz] = g.dims.map(|d| d as usize);
    let nxy = nx * ny;
    let Slab {
        z0,
        z1,
        ref window,
        ref before,
    } = *slab;
    // The slab as a range of row-major indices (whole layers).
    let (lin0, lin1) = (z0 * nxy, z1 * nxy);
    let whole = z0 == 0 && z1 == nz;
    let corners = corners(g);
    let span = corners[7];
    // A record through the general case, out of line.
    let far = |slot: usize, prim: u32, v: &mut V| {
        general(prims, shared, g, exact, z0, z1, prim, &mut |c| {
            v.cell(c, slot as u32);
        });
    };
    let one = |slot: usize, r: Record, v: &mut V| {
        let code = (r >> 32) & 0xf;
        if code == GENERAL || exact {
            far(slot, r as u32, v);
            return;
        }
        let slot = slot as u32;
        // The common case: no division, no bounds, the whole block in the
        // slab (else the cells of the range that are).
        let base = (r >> BASE_SHIFT) as usize;
        if base >= lin0 && base + span < lin1 {
            v.block(base, code as usize, slot);
            return;
        }
        for (i, &o) in corners.iter().enumerate() {
            let c = base + o;
            if IN_RANGE[code as usize] >> i & 1 != 0 && (whole || (lin0..lin1).contains(&c)) {
                v.cell(c, slot);
            }
        }
    };
    let first = window.start;
    let window = &ranges[window.clone()];
    if rev {
        for (i, &r) in window.iter().enumerate().rev() {
            crate::mem::prefetch_at(window, i, true);
            one(first + i, r, v);
        }
        for &slot in before.iter().rev() {
            far(slot, ranges[slot] as u32, v);
        }
    } else {
        for &slot in before {
            far(slot, ranges[slot] as u32, v);
        }
        for (i, &r) in window.iter().enumerate() {
            crate::mem::prefetch_at(window, i, false);
            one(first + i, r, v);
        }
    }
}

/// What [`for_each_ref`] hands the references to. `block` is the hot
/// path, called at one place so that it is inlined into the loop over the
/// records; `cell` is the rare one.
trait Visitor {
    /// The 2×2×2 block of cells from `at` (cells of the slab), of which
    /// the record's range (shape `code`) holds the slot.
    fn block(&mut self, at: usize, code: usize, slot: u32);
    /// One cell of the slab that holds the slot.
    fn cell(&mut self, c: usize, slot: u32);
}

/// The counting pass: one slab's counts, from the slab's first cell `lo`.
struct Count<'a> {
    counts: &'a mut [u32],
    lo: usize,
    corners: [usize; 8],
}

impl Visitor for Count<'_> {
    #[inline(always)]
    fn block(&mut self, at: usize, code: usize, _: u32) {
        // All eight corners, each adding 0 or 1: no branch on the range's
        // shape, which no predictor guesses.
        let mask = IN_RANGE[code];
        let w = &mut self.counts[at - self.lo..=at - self.lo + self.corners[7]];
        for (i, &o) in self.corners.iter().enumerate() {
            // SAFETY: `o <= corners[7]` (the last corner is the farthest).
            unsafe { *w.get_unchecked_mut(o) += (mask >> i) & 1 };
        }
    }

    fn cell(&mut self, c: usize, _: u32) {
        self.counts[c - self.lo] += 1;
    }
}

/// The filling pass: one slab's offsets (from its first cell `lo`) and
/// references (from reference `base`), with the corners of each shape.
struct Fill<'a> {
    offs: &'a mut [u32],
    out: &'a mut [u32],
    lo: usize,
    base: usize,
    span: usize,
    shapes: &'a [[usize; 8]; 8],
}

impl Visitor for Fill<'_> {
    #[inline(always)]
    fn block(&mut self, at: usize, code: usize, slot: u32) {
        // The range's corners only: here the branches on its shape cost
        // less than writing all eight.
        let w = &mut self.offs[at - self.lo..=at - self.lo + self.span];
        for &o in &self.shapes[code][..1 << code.count_ones()] {
            w[o] -= 1;
            self.out[w[o] as usize - self.base] = slot;
        }
    }

    fn cell(&mut self, c: usize, slot: u32) {
        let o = &mut self.offs[c - self.lo];
        *o -= 1;
        self.out[*o as usize - self.base] = slot;
    }
}

/// For each shape code, bit `i` set when [corner](corners) `i` of the
/// 2×2×2 block is in the range.
const IN_RANGE: [u32; 8] = {
    let mut masks = [0; 8];
    let mut code = 0;
    while code < 8 {
        let mut i = 0;
        while i < 8 {
            if i & !code == 0 {
                masks[code] |= 1 << i;
            }
            i += 1;
        }
        code += 1;
    }
    masks
};

/// The offsets of a 2×2×2 block's cells from its first: bit `a` of corner
/// `i` set means one cell further along axis `a`.
fn corners(g: &Geom) -> [usize; 8] {
    let [nx, ny, _] = g.dims.map(|d| d as usize);
    std::array::from_fn(|i| (i & 1) + (i >> 1 & 1) * nx + (i >> 2) * nx * ny)
}

/// [`for_each_ref`]'s general case (a large range, or exact insertion),
/// out of line so that the common case's loop keeps its state in registers:
/// calls `f` with every cell of primitive `prim` in the z-layers `z0..z1`.
#[inline(never)]
#[allow(clippy::too_many_arguments)] // the primitives, what they share, the geometry and the build's switches
fn general<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    g: &Geom,
    exact: bool,
    z0: usize,
    z1: usize,
    prim: u32,
    f: &mut dyn FnMut(usize),
) {
    let [nx, ny, _] = g.dims.map(|d| d as usize);
    let nxy = nx * ny;
    let p = &prims[prim as usize];
    let (lo, hi) = g.cell_range(&p.bounds(shared));
    let single = lo == hi;
    let k0 = (lo[2] as usize).max(z0);
    let k1 = (hi[2] as usize + 1).min(z1);
    for k in k0..k1 {
        for j in lo[1] as usize..hi[1] as usize + 1 {
            for i in lo[0] as usize..hi[0] as usize + 1 {
                if exact
                    && !single
                    && !p.overlaps_box(shared, &g.padded_cell_box([i as u32, j as u32, k as u32]))
                {
                    continue;
                }
                f(k * nxy + j * nx + i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Records sorted by run (as after the radix pass), then by `sort_runs`,
    /// equal a stable sort by first cell; runs both dense (counting) and
    /// sparse (comparison), in one chunk and in several.
    #[test]
    fn sort_runs_sorts_each_run_stably_by_first_cell() {
        let mut s = 9u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            s >> 33
        };
        for (n, cell_bits, shift) in [
            (50_000usize, 18u32, 6u32),
            (3_000, 24, 14),
            (200_000, 21, 9),
        ] {
            let mut v: Vec<Record> = (0..n as u32)
                .map(|p| record(p, next() % 8, (next() % (1 << cell_bits)) as usize))
                .collect();
            v.sort_by_key(|r| r >> (BASE_SHIFT + shift));
            let mut want = v.clone();
            want.sort_by_key(|r| r >> BASE_SHIFT);
            for parallel in [false, true] {
                let mut got = v.clone();
                sort_runs(&mut got, shift, parallel);
                assert_eq!(got, want, "n = {n}, shift = {shift}, parallel = {parallel}");
            }
        }
    }
}
