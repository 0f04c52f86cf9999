//! The dense build: Lagae & Dutré's compact grid (2008, "Compact, fast and
//! robust grids for ray tracing"). Count the references per cell, prefix-sum
//! the counts into offsets, then fill the one flat reference array. No
//! `(cell, primitive)` pairs are materialised and nothing is sorted.
//!
//! Each primitive's cell range is computed once, in parallel, and kept in an
//! 8-byte record (its first cell and which of the 2×2×2 cells after it it
//! covers; larger ranges are recomputed from the bounds when needed). The
//! records are then sorted (one radix pass) by the run
//! of row-major cells their range starts in, so that counting and filling
//! sweep the offsets nearly in order instead of at random: a scene's
//! primitives usually come in no spatial order, and random increments into
//! a large offset table would miss the cache at every step.
//! Counting and filling are split by slabs of cells along z:
//! every worker reads all the records but only touches the offsets and
//! references of its own slab, so no two workers write the same memory and
//! no atomics are needed. Sequentially there is a single slab.

use crate::build::{is_gridded, CellsOut};
use crate::geom::Geom;
use crate::par::{chunk_bounds, chunk_count, map_indices};
use crate::radix;
use crate::{GridConfig, Primitive};

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
/// With `renumber` the records are sorted by their first cell exactly, the
/// references are record positions (slots) instead of primitive indices,
/// and the last element of the result is the primitive of each slot.
pub(crate) fn build_dense<P: Primitive>(
    prims: &[P],
    g: &Geom,
    config: &GridConfig,
    ref_limit: u64,
    renumber: bool,
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

    // Ranges, in parallel over chunks of primitives; the total is an upper
    // bound of the references (exact insertion may drop some).
    let chunks = chunk_count(n, parallel, 1 << 14);
    let parts = map_indices(chunks, parallel, |c| {
        let (s, e) = chunk_bounds(n, chunks, c);
        let mut out = crate::mem::with_capacity(e - s);
        let mut volume = 0u64;
        for (prim, p) in (s as u32..).zip(&prims[s..e]) {
            let b = p.bounds();
            if !is_gridded(&b) {
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
            out.push(record(prim, code, if packable { base } else { 0 }));
        }
        (out, volume)
    });
    let volume: u64 = parts.iter().map(|p| p.1).sum();
    if volume > ref_limit {
        return None;
    }
    let mut ranges: Vec<Record> = if parts.len() == 1 {
        parts.into_iter().next().map(|p| p.0).unwrap_or_default()
    } else {
        parts.into_iter().flat_map(|p| p.0).collect()
    };
    // Order the records by the run of 2^shift row-major cells their first
    // cell is in (one stable radix pass of at most 12 bits): counting and
    // filling then sweep the offsets nearly in order. Slots follow the
    // record order, so for them the order is exact (more passes).
    let cell_bits = 64 - (cells as u64).leading_zeros();
    let key_bits: u32 = if renumber { cell_bits } else { 12 };
    let shift = cell_bits.saturating_sub(key_bits);
    if cell_bits > shift && packable {
        let mut tmp = Vec::new();
        radix::sort_by_key(
            &mut ranges,
            &mut tmp,
            cell_bits - shift,
            |r: &Record| r >> (BASE_SHIFT + shift),
            parallel,
        );
    }

    // Slabs of whole z-layers, one or a few per worker.
    // Every worker scans all the records, so exactly one slab per thread.
    let slabs = crate::par::threads(parallel)
        .min(nz)
        .min(cells / (1 << 14))
        .max(1);
    let slab_z: Vec<(usize, usize)> = (0..slabs).map(|s| chunk_bounds(nz, slabs, s)).collect();

    // Count (per slab), then an inclusive prefix sum: offsets[c] = end of cell c.
    let mut offsets = crate::mem::filled(cells + 1, 0u32);
    let (occupied, max_refs);
    {
        let mut rest: &mut [u32] = &mut offsets[..cells];
        let mut slab_counts = Vec::with_capacity(slabs);
        for &(z0, z1) in &slab_z {
            let (head, tail) = rest.split_at_mut((z1 - z0) * nxy);
            slab_counts.push((z0, z1, head));
            rest = tail;
        }
        let ranges = &ranges;
        let slab_totals: Vec<(u64, u32, u64)> =
            map_slabs(slab_counts, parallel, |(z0, z1, counts)| {
                let lo = z0 * nxy;
                for_each_ref(prims, g, ranges, exact, z0, z1, false, |c, _, _| {
                    counts[c - lo] += 1
                });
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
        let mut bases = Vec::with_capacity(slabs);
        for t in &slab_totals {
            bases.push(base);
            base += t.0 as u32;
        }
        offsets[cells] = base;
        let mut rest: &mut [u32] = &mut offsets[..cells];
        let mut work = Vec::with_capacity(slabs);
        for (s, &(z0, z1)) in slab_z.iter().enumerate() {
            let (head, tail) = rest.split_at_mut((z1 - z0) * nxy);
            work.push((bases[s], head));
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
        let mut work = Vec::with_capacity(slabs);
        let mut consumed = 0usize;
        for &(z0, z1) in &slab_z {
            let (oh, ot) = rest_o.split_at_mut((z1 - z0) * nxy);
            let end = oh.last().map_or(consumed, |&e| e as usize);
            let (rh, rt) = rest_r.split_at_mut(end - consumed);
            work.push((z0, z1, oh, rh, consumed));
            consumed = end;
            rest_o = ot;
            rest_r = rt;
        }
        let ranges = &ranges;
        map_slabs(work, parallel, |(z0, z1, offs, out, base)| {
            let lo = z0 * nxy;
            for_each_ref(prims, g, ranges, exact, z0, z1, true, |c, p, slot| {
                let o = &mut offs[c - lo];
                *o -= 1;
                out[*o as usize - base] = if renumber { slot } else { p };
            });
        });
    }
    let ids = if renumber {
        crate::par::map_range(ranges.len(), parallel, |i| ranges[i] as u32).into_boxed_slice()
    } else {
        Box::new([])
    };
    Some((
        (
            crate::build::Cells::Dense {
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

/// Calls `f(cell, prim, record)` for every reference whose cell lies in the
/// z-layers `z0..z1`, in record order (reversed when `rev`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn for_each_ref<P: Primitive>(
    prims: &[P],
    g: &Geom,
    ranges: &[Record],
    exact: bool,
    z0: usize,
    z1: usize,
    rev: bool,
    mut f: impl FnMut(usize, u32, u32),
) {
    let [nx, ny, nz] = g.dims.map(|d| d as usize);
    let nxy = nx * ny;
    // The slab as a range of row-major indices (whole layers).
    let (lin0, lin1) = (z0 * nxy, z1 * nxy);
    let whole = z0 == 0 && z1 == nz;
    // For each code, the offsets of its cells from the first one.
    let corners: [[usize; 8]; 8] = std::array::from_fn(|code| {
        let mut out = [0usize; 8];
        let mut n = 0;
        for dz in 0..=(code >> 2) & 1 {
            for dy in 0..=(code >> 1) & 1 {
                for dx in 0..=code & 1 {
                    out[n] = dx + dy * nx + dz * nxy;
                    n += 1;
                }
            }
        }
        out
    });
    let mut one = |(slot, &r): (usize, &Record)| {
        let slot = slot as u32;
        let prim = r as u32;
        let code = (r >> 32) & 0xf;
        if code != GENERAL && !exact {
            // The common case: no division, no bounds, one short loop.
            let base = (r >> BASE_SHIFT) as usize;
            for &o in &corners[code as usize][..1 << code.count_ones()] {
                let c = base + o;
                if whole || (lin0..lin1).contains(&c) {
                    f(c, prim, slot);
                }
            }
            return;
        }
        let p = &prims[prim as usize];
        let (lo, hi) = g.cell_range(&p.bounds());
        let single = lo == hi;
        let k0 = (lo[2] as usize).max(z0);
        let k1 = (hi[2] as usize + 1).min(z1);
        for k in k0..k1 {
            for j in lo[1] as usize..hi[1] as usize + 1 {
                for i in lo[0] as usize..hi[0] as usize + 1 {
                    if exact
                        && !single
                        && !p.overlaps_box(&g.padded_cell_box([i as u32, j as u32, k as u32]))
                    {
                        continue;
                    }
                    f(k * nxy + j * nx + i, prim, slot);
                }
            }
        }
    };
    if rev {
        ranges.iter().enumerate().rev().for_each(&mut one);
    } else {
        ranges.iter().enumerate().for_each(&mut one);
    }
}
