//! Grid construction in linear time. The common part (the grid box, the
//! resolution, the caps) is here; the dense table is built by counting and
//! filling ([`crate::dense_build`]); the hashed table by sorting pairs: map
//! every primitive to the cells its (padded) box overlaps, emit one
//! `(Morton code, primitive)` pair per reference, radix-sort the pairs by
//! code, and read the occupied cells off the sorted runs (Kalojanov &
//! Slusallek 2009). Its references end up in one flat array in Morton
//! order, each cell's run sorted by primitive index.
//!
//! Every phase is chunked; with the `rayon` feature and
//! `GridConfig::parallel_build` the chunks run in parallel, otherwise the
//! same code runs sequentially.

use crate::cells::{Cells, CellsOut};
use crate::cluster;
use crate::geom::{self, Geom, HARD_MAX_CELLS};
use crate::geom::{gridded, is_gridded};
use crate::hash_table::CellTable;
use crate::morton;
use crate::par::{chunk_bounds, chunk_count, map_indices, SharedMut};
use crate::radix;
use crate::{CellStorage, GridConfig, Primitive};
use gridrt_bbox::math::Lanes;
use gridrt_bbox::{Aabb, Real};
use std::sync::atomic::{AtomicU64, Ordering};

/// Everything the build produces.
#[derive(Debug)]
pub(crate) struct Built {
    pub geom: Geom,
    pub cells: Cells,
    pub refs: Box<[u32]>,
    /// Primitives whose box is not finite (NaN, infinite or empty) or is
    /// outsized ([`Outsized`]), or all of them for [`GridConfig::direct`]:
    /// tested by every query.
    pub unbounded: Box<[u32]>,
    /// Morton spread tables per axis (hashed storage only).
    pub spread: [Box<[u64]>; 3],
    pub occupied: u64,
    pub max_refs: u32,
    /// The primitive of each slot of a gridded primitive: `refs` hold
    /// slots, numbered in the order the primitives first appear in the
    /// references (cell order).
    pub ids: Box<[u32]>,
}

impl Built {
    /// No cells: every query tests the `n` primitives
    /// ([`GridConfig::direct`]).
    fn direct(n: usize) -> Self {
        Built {
            geom: Geom::empty(),
            cells: Cells::Empty,
            refs: Box::new([]),
            unbounded: (0..n as u32).collect(),
            spread: [Box::new([]), Box::new([]), Box::new([])],
            occupied: 0,
            max_refs: 0,
            ids: Box::new([]),
        }
    }
}

/// Builds the cell structure for `prims`; the references hold slots (see
/// [`Built::ids`]).
pub(crate) fn build<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    config: &GridConfig,
    budget: usize,
) -> Built {
    let parallel = config.parallel_build;
    let n = prims.len();
    // Phase 1: the union of the finite boxes, and the primitives that cannot be gridded.
    let chunks = chunk_count(n, parallel, 1 << 14);
    let parts = map_indices(chunks, parallel, |c| {
        let (s, e) = chunk_bounds(n, chunks, c);
        // In lanes: min and max without the scalar ones' NaN cases (the
        // boxes taken are finite), and nothing but these and the edge
        // statistics in the loop, so that they stay in registers. The
        // primitives left out (rare) are listed by a second loop.
        let (mut lo, mut hi) = (Lanes::INFINITY, Lanes::NEG_INFINITY);
        let mut count = 0usize;
        let mut edges = Edges::default();
        for (i, p) in (s..).zip(&prims[s..e]) {
            crate::mem::prefetch_at(prims, i, false);
            if let Some((min, max)) = gridded(&p.bounds(shared)) {
                lo = lo.min(min);
                hi = hi.max(max);
                edges.add(i, min, max);
                count += 1;
            }
        }
        let out: Vec<u32> = if count == e - s {
            Vec::new()
        } else {
            (s as u32..e as u32)
                .filter(|&i| !is_gridded(&prims[i as usize].bounds(shared)))
                .collect()
        };
        let b = if count == 0 {
            Aabb::EMPTY
        } else {
            Aabb::new(lo.truncate(), hi.truncate())
        };
        (b, out, count, edges)
    });
    let mut bounds = Aabb::EMPTY;
    let mut unbounded = Vec::new();
    let mut gridded = 0usize;
    let mut edges = Edges::default();
    for (b, out, count, e) in parts {
        bounds = bounds.union(b);
        unbounded.extend(out);
        gridded += count;
        edges = edges.merge(e);
    }
    let mut outsized = Real::INFINITY;
    let aside = config
        .set_aside_outsized
        .then(|| Outsized::find(prims, shared, &bounds, gridded, &edges));
    if let Some(o) = aside.flatten() {
        outsized = o.limit;
        bounds = o.core;
        gridded -= o.prims.len();
        unbounded.extend(o.prims);
        unbounded.sort_unstable();
    }
    let unbounded = unbounded.into_boxed_slice();
    if gridded == 0 {
        return Built {
            unbounded,
            ..Built::direct(0)
        };
    }

    // Phase 2: the resolution (lecture formula, degenerate extents, cell cap).
    let e = bounds.extent();
    let ext = [geom::wide(e.x), geom::wide(e.y), geom::wide(e.z)];
    let max_cells = config.max_cells.clamp(1, HARD_MAX_CELLS);
    let mut dims = match config.dims {
        Some(d) => geom::cap_cells(d.map(|n| u64::from(n.max(1))), max_cells),
        None if config.direct(n) => [1; 3],
        None => {
            let m = geom::sanitize_m(config.m);
            // `auto` sizes the top grid for what it holds itself when most
            // primitives crowd into a few cells, which get nested grids.
            let count = if config.auto && config.nest_min_refs == 0 {
                cluster::top_count(prims, shared, &bounds, gridded, m, max_cells)
            } else {
                gridded
            };
            geom::resolution(ext, count, cluster::top_m(gridded, count, m), max_cells)
        }
    };
    // References are bounded too, so that huge primitives over a fine grid cannot
    // exhaust memory: past the limit the resolution is halved and the build retried.
    // The memory budget caps both: a dense cell costs 4 bytes and a bit
    // (and a bit per block), a reference 4 bytes (a hashed one up to 40
    // with its occupied cell's slots), so cells and references each take
    // at most about 45% of the budget, and never less than a single cell
    // holding every primitive once.
    let per_ref = if config.storage == CellStorage::Hashed {
        90
    } else {
        9
    };
    let ref_limit = (4 * max_cells)
        .max(64 * gridded as u64)
        .min(u64::from(u32::MAX) / 2)
        .min((budget / per_ref) as u64)
        .max(gridded as u64);
    let cells_cap = max_cells.min((budget / 9).max(1) as u64);
    dims = geom::cap_cells(dims.map(u64::from), cells_cap);
    loop {
        let mut g = Geom::new(bounds, dims);
        g.slab = config.slab;
        g.outsized = outsized;
        match build_cells(prims, shared, &g, config, ref_limit, unbounded.is_empty()) {
            Some(((cells, refs, spread, occupied, max_refs), ids)) => {
                return Built {
                    geom: g,
                    cells,
                    refs,
                    unbounded,
                    spread,
                    occupied,
                    max_refs,
                    ids,
                };
            }
            None => dims = dims.map(|d| (d / 2).max(1)),
        }
    }
}

/// The longest box edges of the gridded primitives, for
/// [`Outsized::find`]: the largest of all (per axis in lanes, one `max` a
/// primitive, so that the bounds pass stays as fast as without it) and
/// the binary orders of magnitude of a fixed sample (every
/// [`Edges::STRIDE`]th primitive), whose median a few huge primitives
/// cannot move as they would a mean.
#[derive(Clone, Copy, Debug)]
struct Edges {
    /// Sampled edges per bin: bin `b` holds edges in `[2^(b − 65), 2^(b − 64))`
    /// (the first and last bins also what lies beyond).
    bins: [u32; Edges::BINS],
    max: Lanes,
}

impl Default for Edges {
    fn default() -> Self {
        Edges {
            bins: [0; Edges::BINS],
            max: Lanes::ZERO,
        }
    }
}

impl Edges {
    const STRIDE: usize = 8;
    const BINS: usize = 128;

    /// Adds primitive `i`, whose box has corners `min` and `max`.
    #[inline(always)]
    fn add(&mut self, i: usize, min: Lanes, max: Lanes) {
        let e = max - min;
        self.max = self.max.max(e);
        if i.is_multiple_of(Self::STRIDE) {
            let exp = (geom::wide(e.max_element()).to_bits() >> 52) as i64 - 1023;
            self.bins[(exp + 65).clamp(0, Self::BINS as i64 - 1) as usize] += 1;
        }
    }

    fn merge(mut self, o: Edges) -> Edges {
        for (a, b) in self.bins.iter_mut().zip(o.bins) {
            *a += b;
        }
        self.max = self.max.max(o.max);
        self
    }

    /// An edge at or above the sample's median, and the longest edge of all.
    fn median_and_max(&self) -> Option<(f64, Real)> {
        let samples: u64 = self.bins.iter().map(|&b| u64::from(b)).sum();
        if samples == 0 {
            return None;
        }
        let mut seen = 0;
        let bin = self.bins.iter().position(|&b| {
            seen += u64::from(b);
            2 * seen >= samples
        })?;
        Some((2f64.powi(bin as i32 - 64), self.max.max_element()))
    }
}

/// A few primitives far larger than the rest (a ground under a model, a
/// wall around a room of small things), set aside from the cells and
/// tested by every query like unbounded ones, so that the grid spans the
/// rest only. One such primitive stretches the grid's box over the whole
/// ground and leaves the model a handful of coarse cells (a 4×1×4 top
/// grid for the dragon on a floor 400 times its size), where a grid over
/// the model alone is as fine as the model asks and the ground costs each
/// ray one test.
#[derive(Debug)]
struct Outsized {
    /// The longest edge a gridded primitive keeps ([`Geom::outsized`]).
    limit: Real,
    /// The box of the primitives kept.
    core: Aabb,
    /// The primitives set aside, in order.
    prims: Vec<u32>,
}

impl Outsized {
    /// An outsized primitive's longest box edge is more than this many
    /// times the median of the gridded primitives' longest edges (rounded
    /// up to a power of two).
    const FACTOR: f64 = 256.0;
    /// At most this many are set aside (each costs every ray a test).
    const MAX_PRIMS: usize = 16;
    /// And only when the box of the rest is at least this many times
    /// smaller on its longest axis than the whole scene's.
    const SHRINK: Real = 4.0;

    /// The outsized primitives of `prims` (`count` of them with finite
    /// boxes, whose union is `bounds`), if setting them aside pays.
    fn find<P: Primitive>(
        prims: &[P],
        shared: &P::Shared,
        bounds: &Aabb,
        count: usize,
        edges: &Edges,
    ) -> Option<Outsized> {
        let (median, longest) = edges.median_and_max()?;
        let limit = (median * Self::FACTOR) as Real;
        if count < 2 || !(longest > limit) {
            return None;
        }
        let mut core = Aabb::EMPTY;
        let mut out = Vec::new();
        for (i, p) in prims.iter().enumerate() {
            let Some((min, max)) = gridded(&p.bounds(shared)) else {
                continue;
            };
            if geom::longest_edge(min, max) > limit {
                if out.len() == Self::MAX_PRIMS {
                    return None;
                }
                out.push(i as u32);
            } else {
                core = core.union(Aabb::new(min.truncate(), max.truncate()));
            }
        }
        let shrinks = core.extent().max_element() * Self::SHRINK <= bounds.extent().max_element();
        (!core.is_empty() && shrinks).then_some(Outsized {
            limit,
            core,
            prims: out,
        })
    }
}

/// Replaces each reference by a slot, numbering the primitives in the
/// order they first appear in `refs` (so in cell order: a primitive's slot
/// is near those of its neighbours in space); returns the primitive of
/// each slot.
fn first_seen(refs: &mut [u32], prims: usize) -> Box<[u32]> {
    let mut slot = crate::mem::filled(prims, u32::MAX);
    let mut ids: Vec<u32> = crate::mem::with_capacity(prims);
    for r in refs.iter_mut() {
        let s = &mut slot[*r as usize];
        if *s == u32::MAX {
            *s = ids.len() as u32;
            ids.push(*r);
        }
        *r = *s;
    }
    ids.into_boxed_slice()
}

/// A `(key, primitive)` pair as the sort sees it.
trait Pair: Copy + Send + Sync {
    fn new(key: u64, prim: u32) -> Self;
    fn key(&self) -> u64;
    fn prim(&self) -> u32;
}

/// Key and primitive packed in one word, for keys of at most 32 bits.
impl Pair for u64 {
    #[inline(always)]
    fn new(key: u64, prim: u32) -> Self {
        (key << 32) | u64::from(prim)
    }
    #[inline(always)]
    fn key(&self) -> u64 {
        self >> 32
    }
    #[inline(always)]
    fn prim(&self) -> u32 {
        *self as u32
    }
}

/// Wide keys (Morton codes of more than 32 bits).
#[derive(Clone, Copy)]
struct Wide {
    key: u64,
    prim: u32,
}

impl Pair for Wide {
    #[inline(always)]
    fn new(key: u64, prim: u32) -> Self {
        Self { key, prim }
    }
    #[inline(always)]
    fn key(&self) -> u64 {
        self.key
    }
    #[inline(always)]
    fn prim(&self) -> u32 {
        self.prim
    }
}

/// Builds cells and references on a fixed geometry; `None` when the
/// references would exceed `ref_limit`. `all_gridded`: every primitive's
/// box is known to be finite.
fn build_cells<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    g: &Geom,
    config: &GridConfig,
    ref_limit: u64,
    all_gridded: bool,
) -> Option<(CellsOut, Box<[u32]>)> {
    if config.storage == CellStorage::Dense {
        return crate::dense_build::build_dense(prims, shared, g, config, ref_limit, all_gridded);
    }
    let spread: [Box<[u64]>; 3] = std::array::from_fn(|a| {
        (0..g.dims[a])
            .map(|i| morton::encode3(i, 0, 0) << a)
            .collect()
    });
    let max_key = spread[0][g.dims[0] as usize - 1]
        | spread[1][g.dims[1] as usize - 1]
        | spread[2][g.dims[2] as usize - 1];
    let key_bits = 64 - max_key.leading_zeros();
    let mut out = if key_bits <= 32 {
        build_pairs::<P, u64>(
            prims,
            shared,
            g,
            config,
            ref_limit,
            spread,
            key_bits,
            all_gridded,
        )
    } else {
        build_pairs::<P, Wide>(
            prims,
            shared,
            g,
            config,
            ref_limit,
            spread,
            key_bits,
            all_gridded,
        )
    }?;
    if config.cell_groups {
        crate::groups::sort_crowded_runs(prims, shared, &out.0, g.dims, &mut out.1);
    }
    let ids = first_seen(&mut out.1, prims.len());
    Some((out, ids))
}

/// The hashed table's build: `(Morton code, primitive)` pairs, sorted.
/// `all_gridded` as for [`crate::dense_build::build_dense`].
#[allow(clippy::too_many_arguments)] // the primitives, what they share, the geometry and the build's switches
fn build_pairs<P: Primitive, T: Pair>(
    prims: &[P],
    shared: &P::Shared,
    g: &Geom,
    config: &GridConfig,
    ref_limit: u64,
    spread: [Box<[u64]>; 3],
    key_bits: u32,
    all_gridded: bool,
) -> Option<CellsOut> {
    let parallel = config.parallel_build;
    let n = prims.len();
    let key_of = |i: u32, j: u32, k: u32| -> u64 {
        spread[0][i as usize] | spread[1][j as usize] | spread[2][k as usize]
    };

    // Phase 3: one pair per reference, chunk by chunk (in primitive order).
    let total = AtomicU64::new(0);
    let chunks = chunk_count(n, parallel, 1 << 14);
    let parts: Vec<Option<Vec<T>>> = map_indices(chunks, parallel, |c| {
        let (s, e) = chunk_bounds(n, chunks, c);
        let mut out: Vec<T> = Vec::with_capacity((e - s) * 4);
        let mut since_check = 0usize;
        for (p, prim) in (s as u32..).zip(&prims[s..e]) {
            let b = prim.bounds(shared);
            if !all_gridded && !g.holds(&b) {
                continue;
            }
            let (lo, hi) = g.cell_range(&b);
            let single = lo == hi;
            let before = out.len();
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        if config.exact_insertion
                            && !single
                            && !prim.overlaps_box(shared, &g.padded_cell_box([i, j, k]))
                        {
                            continue;
                        }
                        out.push(T::new(key_of(i, j, k), p));
                    }
                }
            }
            since_check += out.len() - before;
            if since_check > 1 << 16 {
                let t = total.fetch_add(since_check as u64, Ordering::Relaxed) + since_check as u64;
                since_check = 0;
                if t > ref_limit {
                    return None;
                }
            }
        }
        let t = total.fetch_add(since_check as u64, Ordering::Relaxed) + since_check as u64;
        (t <= ref_limit).then_some(out)
    });
    let mut parts: Vec<Vec<T>> = parts.into_iter().collect::<Option<_>>()?;
    let mut pairs: Vec<T> = if parts.len() == 1 {
        parts.pop().unwrap_or_default()
    } else {
        concat(parts, parallel)
    };

    // Phase 4: sort by cell key (stable: each run stays in primitive order).
    let mut tmp = Vec::new();
    radix::sort_by_key(&mut pairs, &mut tmp, key_bits, T::key, parallel, None);
    drop(tmp);
    let r = pairs.len();

    // Phase 5: the flat reference array and the cells.
    let refs: Box<[u32]> = {
        let mut refs = Vec::with_capacity(r);
        let chunks = chunk_count(r, parallel, 1 << 16);
        let dst = SharedMut(refs.as_mut_ptr());
        let pairs = &pairs;
        map_indices(chunks, parallel, |c| {
            let (s, e) = chunk_bounds(r, chunks, c);
            for (i, p) in pairs[s..e].iter().enumerate() {
                // SAFETY: each chunk writes its own range below `r`, within capacity.
                unsafe { dst.write(s + i, p.prim()) };
            }
        });
        // SAFETY: all `r` elements were written above.
        unsafe { refs.set_len(r) };
        refs.into_boxed_slice()
    };
    // Run starts (indices into `pairs` where the key changes).
    let mut occupied = 0u64;
    let mut max_refs = 0u32;
    let mut run_start = 0usize;
    let mut runs: Vec<(u64, u32, u32)> = Vec::new();
    for i in 1..=r {
        if i == r || pairs[i].key() != pairs[run_start].key() {
            let len = (i - run_start) as u32;
            occupied += 1;
            max_refs = max_refs.max(len);
            runs.push((pairs[run_start].key(), run_start as u32, len));
            run_start = i;
        }
    }
    let mut table = CellTable::with_cells(runs.len());
    for &(key, start, len) in &runs {
        table.insert(key, start, len);
    }
    Some((Cells::Hashed { table }, refs, spread, occupied, max_refs))
}

/// Concatenates the per-chunk pair vectors (in parallel when asked).
fn concat<T: Pair>(parts: Vec<Vec<T>>, parallel: bool) -> Vec<T> {
    let total: usize = parts.iter().map(Vec::len).sum();
    let mut out: Vec<T> = Vec::with_capacity(total);
    let mut starts = Vec::with_capacity(parts.len());
    let mut acc = 0;
    for p in &parts {
        starts.push(acc);
        acc += p.len();
    }
    let dst = SharedMut(out.as_mut_ptr());
    let parts = &parts;
    let starts = &starts;
    map_indices(parts.len(), parallel, |c| {
        for (i, x) in parts[c].iter().enumerate() {
            // SAFETY: part c owns positions starts[c]..starts[c] + len, below `total`.
            unsafe { dst.write(starts[c] + i, *x) };
        }
    });
    // SAFETY: the parts cover 0..total exactly.
    unsafe { out.set_len(total) };
    out
}
