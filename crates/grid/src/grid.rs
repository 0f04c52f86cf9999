//! The regular grid: construction, queries, the cell walk and self-checks.

use crate::build::{self, Cells};
use crate::counters::{Counters, NoCounters};
use crate::dda::{BlockMap, CellFn, CellIter, CellLookup, CellVisit, Dda};
use crate::geom::Geom;
use crate::nested::{Nested, Sub};
use crate::table::CellTable;
use crate::{morton, Accelerator, CellStorage, GridConfig, GridStats, Hit, Primitive};
use gridrt_bbox::{Aabb, Ray, Real};
use std::ops::ControlFlow;
use std::time::Instant;

/// `closest_hit` stops after a cell only if the best hit lies before the
/// cell's exit by more than this fraction of `|t_exit|` (a few ulps): a hit
/// on, or within rounding of, the plane between two cells may be tied with a
/// lower-index primitive in the next cell, which must be tested too.
const EXIT_MARGIN: Real = 8.0 * Real::EPSILON;

/// A regular (uniform) grid over primitives it owns (Suffern ch. 22).
///
/// The grid box is the union of the primitives' boxes, cut into
/// `dims[0] × dims[1] × dims[2]` equal cells (see [`GridConfig`] for the
/// resolution). Each cell lists the primitives whose box, widened by a few
/// ulps, overlaps it; the lists live in one flat array, found through a
/// Morton-keyed hash table of occupied cells or a dense offset table
/// ([`CellStorage`]). Queries walk the cells along the ray with a 3D-DDA and
/// return exactly what [`crate::Exhaustive`] returns.
///
/// Primitives whose box is not finite (NaN, infinite or empty) are kept
/// outside the cells and tested by every query.
///
/// The grid is immutable after [`Grid::build`] and `Sync`; per-query working
/// memory (the mailbox) is the caller's [`GridScratch`].
#[derive(Clone, Debug)]
pub struct Grid<P> {
    prims: Vec<P>,
    config: GridConfig,
    geom: Geom,
    cells: Cells,
    /// The cells' references: primitive indices, or slots when the grid
    /// keeps copies.
    refs: Box<[u32]>,
    /// Empty, or (built by [`Grid::build_with_copies`]) a copy of each
    /// gridded primitive in slot order: the order in which the cells, in
    /// storage order, first reference them.
    copies: Box<[P]>,
    /// The primitive index of each slot (empty without copies).
    ids: Box<[u32]>,
    unbounded: Box<[u32]>,
    spread: [Box<[u64]>; 3],
    blocks: BlockMap,
    /// One bit per cell key: set when the cell holds references.
    occ: Box<[u64]>,
    /// The nested grids of crowded cells.
    nested: Nested,
    stats: GridStats,
}

/// How [`Grid::build_with_copies`] gathers the copies: from the primitives
/// and the primitive of each slot.
type Gather<P> = Box<dyn FnOnce(&[P], &[u32]) -> Box<[P]>>;

/// Per-thread working memory of grid queries: the mailbox, one stamp per
/// primitive holding the id of the last query that tested it, and the
/// query counter. Made by [`Accelerator::scratch`]; each thread owns its
/// own, so no global counter or lock is involved.
#[derive(Clone, Debug, Default)]
pub struct GridScratch {
    stamps: Vec<u32>,
    ray: u32,
}

impl GridScratch {
    /// A new query id, after making sure there is one stamp per primitive.
    /// When the 32-bit id wraps around, all stamps are cleared, so an old
    /// stamp can never be mistaken for the current query.
    #[inline]
    fn begin(&mut self, prims: usize) -> u32 {
        if self.stamps.len() != prims {
            self.stamps.clear();
            self.stamps.resize(prims, 0);
            self.ray = 0;
        }
        self.ray = self.ray.wrapping_add(1);
        if self.ray == 0 {
            self.stamps.fill(0);
            self.ray = 1;
        }
        self.ray
    }
}

/// Tests bit `key` of an occupancy bitmap.
#[inline(always)]
fn bit(bits: &[u64], key: u64) -> bool {
    let w = (key >> 6) as usize;
    debug_assert!(w < bits.len());
    // SAFETY: the bitmap has a bit for every key the walk can produce.
    unsafe { bits.get_unchecked(w) >> (key & 63) & 1 != 0 }
}

/// One bit per cell of a dense table (`offsets[c]..offsets[c + 1]` are
/// cell `c`'s references): set when the cell holds references.
pub(crate) fn dense_occupancy(offsets: &[u32]) -> Box<[u64]> {
    let cells = offsets.len() - 1;
    // A word at a time, 64 comparisons of neighbouring offsets each: a
    // fixed-length loop the compiler turns into vector compares.
    let word = |w: usize| {
        let o = &offsets[w * 64..(w * 64 + 65).min(offsets.len())];
        o.windows(2)
            .enumerate()
            .fold(0u64, |bits, (b, p)| bits | u64::from(p[0] != p[1]) << b)
    };
    (0..cells.div_ceil(64)).map(word).collect()
}

struct DenseLookup<'a> {
    occ: &'a [u64],
    offsets: &'a [u32],
    refs: &'a [u32],
    nx: u64,
    nxy: u64,
}

impl<'a> DenseLookup<'a> {
    /// The lookup of a dense table over cells `dims`.
    fn new(dims: [u32; 3], occ: &'a [u64], offsets: &'a [u32], refs: &'a [u32]) -> Self {
        let [nx, ny, _] = dims.map(u64::from);
        Self {
            occ,
            offsets,
            refs,
            nx,
            nxy: nx * ny,
        }
    }
}

impl Sub {
    /// The lookup of a nested grid's dense table.
    fn lookup(&self) -> DenseLookup<'_> {
        DenseLookup::new(self.geom.dims, &self.occ, &self.offsets, &self.refs)
    }
}

impl<'a> CellLookup<'a> for DenseLookup<'a> {
    #[inline(always)]
    fn start(&self, idx: [u32; 3], neg: [bool; 3]) -> (u64, [u64; 3]) {
        let key = u64::from(idx[0]) + self.nx * u64::from(idx[1]) + self.nxy * u64::from(idx[2]);
        let s = [1, self.nx, self.nxy];
        (
            key,
            std::array::from_fn(|a| if neg[a] { s[a].wrapping_neg() } else { s[a] }),
        )
    }
    #[inline(always)]
    fn step(st: &[u64; 3], key: u64, axis: usize) -> u64 {
        key.wrapping_add(st[axis])
    }
    #[inline(always)]
    fn occupied(&self, key: u64) -> bool {
        bit(self.occ, key)
    }
    #[inline(always)]
    fn refs(&self, key: u64) -> &'a [u32] {
        let k = key as usize;
        debug_assert!(k + 1 < self.offsets.len());
        // SAFETY: the walk only produces keys of cells inside the grid, and
        // `offsets` has one entry per cell plus one; the offsets are
        // nondecreasing and end at `refs.len()` (checked by `check_invariants`).
        unsafe {
            let s = *self.offsets.get_unchecked(k) as usize;
            let e = *self.offsets.get_unchecked(k + 1) as usize;
            self.refs.get_unchecked(s..e)
        }
    }
}

struct HashedLookup<'a> {
    occ: &'a [u64],
    table: &'a CellTable,
    refs: &'a [u32],
    spread: [&'a [u64]; 3],
}

impl<'a> CellLookup<'a> for HashedLookup<'a> {
    #[inline(always)]
    fn start(&self, idx: [u32; 3], neg: [bool; 3]) -> (u64, [u64; 3]) {
        let key = self.spread[0][idx[0] as usize]
            | self.spread[1][idx[1] as usize]
            | self.spread[2][idx[2] as usize];
        (key, neg.map(u64::from))
    }
    #[inline(always)]
    fn step(st: &[u64; 3], key: u64, axis: usize) -> u64 {
        morton::step(key, axis, st[axis] != 0)
    }
    #[inline(always)]
    fn occupied(&self, key: u64) -> bool {
        bit(self.occ, key)
    }
    #[inline(always)]
    fn refs(&self, key: u64) -> &'a [u32] {
        let (s, len) = self.table.get(key);
        let (s, e) = (s as usize, s as usize + len as usize);
        debug_assert!(e <= self.refs.len());
        // SAFETY: every run stored in the table lies within `refs`
        // (checked by `check_invariants`); empty cells give (0, 0).
        unsafe { self.refs.get_unchecked(s..e) }
    }
}

/// A closure as a [`CellFn`] (for the public visitor).
struct FnCell<F>(F);

impl<'a, B, F: FnMut(CellVisit, &'a [u32]) -> ControlFlow<B>> CellFn<'a> for FnCell<F> {
    type Break = B;
    #[inline(always)]
    fn call(&mut self, visit: CellVisit, refs: &'a [u32]) -> ControlFlow<B> {
        (self.0)(visit, refs)
    }
}

/// Where the run `cell` of the grid's references `all` starts among them.
#[inline(always)]
fn run_start(all: &[u32], cell: &[u32]) -> u32 {
    ((cell.as_ptr() as usize - all.as_ptr() as usize) / std::mem::size_of::<u32>()) as u32
}

/// The primitive index of reference `r`: `r` itself, or its slot's entry
/// in `ids` for a grid with copies.
#[inline(always)]
fn prim_id(ids: &[u32], r: u32) -> u32 {
    ids.get(r as usize).map_or(r, |&p| p)
}

/// The closest-hit query's per-cell work.
struct Closest<'q, P, C, const MB: bool> {
    /// What the references index: the grid's copies or its primitives.
    prims: &'q [P],
    /// Empty, or the primitive index of each slot.
    ids: &'q [u32],
    /// The grid's references (a cell's nested grid is found by its run's start).
    refs: &'q [u32],
    nested: &'q Nested,
    ray: &'q Ray,
    t_min: Real,
    /// `t_max`, then the best hit's t.
    t_lim: Real,
    best: Option<Hit>,
    stamps: &'q mut [u32],
    stamp: u32,
    counters: &'q mut C,
}

impl<P: Primitive, C: Counters, const MB: bool> Closest<'_, P, C, MB> {
    /// Tests one primitive, keeping its hit if it is better ([`Hit::is_better_than`]).
    #[inline(always)]
    fn test(&mut self, r: u32) {
        debug_assert!((r as usize) < self.prims.len());
        // SAFETY: every stored reference is a valid index into `prims`
        // (checked by `check_invariants`).
        let prim = unsafe { self.prims.get_unchecked(r as usize) };
        let ids = self.ids;
        self.test_prim(|| prim_id(ids, r), prim);
    }

    /// Tests primitive `p`, given as `prim` (the original or a copy).
    #[inline(always)]
    fn test_prim(&mut self, p: impl FnOnce() -> u32, prim: &P) {
        self.counters.test();
        if let Some(h) = prim.closest_hit(self.ray, self.t_min, self.t_lim) {
            self.keep(Hit::new(h, p()));
        }
    }

    /// Keeps `hit` if it is better ([`Hit::is_better_than`]); gives the
    /// limit for the tests that follow.
    #[inline(always)]
    fn keep(&mut self, hit: Hit) -> Real {
        if self.best.as_ref().map_or(true, |b| hit.is_better_than(b)) {
            self.t_lim = hit.t;
            self.best = Some(hit);
        }
        self.t_lim
    }

    /// Walks the nested grid of a crowded cell instead of testing the
    /// cell's references one by one: the same query, one level down.
    #[inline(never)]
    fn walk_sub(&mut self, sub: &Sub) {
        let Some(dda) = Dda::new(&sub.geom, self.ray, self.t_min, self.t_lim) else {
            return;
        };
        let lookup = sub.lookup();
        let none = Nested::default();
        let mut q = Closest::<P, C, MB> {
            prims: self.prims,
            ids: self.ids,
            refs: &sub.refs,
            nested: &none,
            ray: self.ray,
            t_min: self.t_min,
            t_lim: self.t_lim,
            best: self.best,
            stamps: &mut *self.stamps,
            stamp: self.stamp,
            counters: &mut *self.counters,
        };
        let _ = dda.walk(&lookup, &mut q);
        (self.t_lim, self.best) = (q.t_lim, q.best);
    }
}

impl<'a, P: Primitive, C: Counters, const MB: bool> CellFn<'a> for Closest<'_, P, C, MB> {
    type Break = ();

    #[inline(always)]
    fn call(&mut self, visit: CellVisit, refs: &'a [u32]) -> ControlFlow<()> {
        self.counters.cell();
        if refs.is_empty() {
            return ControlFlow::Continue(());
        }
        if let Some(sub) = self.nested.find(refs.len(), run_start(self.refs, refs)) {
            self.walk_sub(sub);
        } else {
            self.test_refs(refs);
        }
        // Stop only when the best hit is certainly inside this cell: a hit on
        // (or within rounding of) the exit plane may tie with a lower-index
        // primitive of the next cell. A hit found here that lies in a later
        // cell stays in `best` and is confirmed there. (Empty cells cannot
        // change the answer, so the test is made after occupied ones only.)
        let t_exit = visit.t_exit;
        if self.best.is_some() && self.t_lim < t_exit - t_exit.abs() * EXIT_MARGIN {
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

impl<P: Primitive, C: Counters, const MB: bool> Closest<'_, P, C, MB> {
    /// Tests the references of one cell.
    #[inline(always)]
    fn test_refs(&mut self, refs: &[u32]) {
        if !MB {
            self.counters.tests(refs.len());
            let (prims, ids, ray, t_min, t_lim) =
                (self.prims, self.ids, self.ray, self.t_min, self.t_lim);
            P::closest_hits(prims, refs, ray, t_min, t_lim, &mut |r, h| {
                self.keep(Hit::new(h, prim_id(ids, r)))
            });
            return;
        }
        // With the mailbox, one at a time: each reference's stamp decides.
        for &p in refs {
            debug_assert!((p as usize) < self.stamps.len());
            // SAFETY: `GridScratch::begin` sized the stamps to the primitive count.
            let s = unsafe { self.stamps.get_unchecked_mut(p as usize) };
            if *s == self.stamp {
                self.counters.mailbox_skip();
                continue;
            }
            *s = self.stamp;
            self.test(p);
        }
    }
}

/// The any-hit query's per-cell work.
struct AnyHit<'q, P, C, const MB: bool> {
    /// What the references index: the grid's copies or its primitives.
    prims: &'q [P],
    /// The grid's references (a cell's nested grid is found by its run's start).
    refs: &'q [u32],
    nested: &'q Nested,
    ray: &'q Ray,
    t_min: Real,
    t_max: Real,
    stamps: &'q mut [u32],
    stamp: u32,
    counters: &'q mut C,
}

impl<'a, P: Primitive, C: Counters, const MB: bool> CellFn<'a> for AnyHit<'_, P, C, MB> {
    type Break = ();

    #[inline(always)]
    fn call(&mut self, _: CellVisit, refs: &'a [u32]) -> ControlFlow<()> {
        self.counters.cell();
        if refs.is_empty() {
            return ControlFlow::Continue(());
        }
        if let Some(sub) = self.nested.find(refs.len(), run_start(self.refs, refs)) {
            return self.walk_sub(sub);
        }
        for &p in refs {
            if MB {
                // SAFETY: `GridScratch::begin` sized the stamps to the primitive count.
                let s = unsafe { self.stamps.get_unchecked_mut(p as usize) };
                if *s == self.stamp {
                    self.counters.mailbox_skip();
                    continue;
                }
                *s = self.stamp;
            }
            self.counters.test();
            // SAFETY: every stored reference is a valid index into `prims`.
            let prim = unsafe { self.prims.get_unchecked(p as usize) };
            if prim.any_hit(self.ray, self.t_min, self.t_max) {
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }
}

impl<P: Primitive, C: Counters, const MB: bool> AnyHit<'_, P, C, MB> {
    /// Walks the nested grid of a crowded cell: only the references in the
    /// nested cells along the ray are tested. An occluder whose hit lies
    /// outside this cell is found in the cell that holds the hit.
    #[inline(never)]
    fn walk_sub(&mut self, sub: &Sub) -> ControlFlow<()> {
        let Some(dda) = Dda::new(&sub.geom, self.ray, self.t_min, self.t_max) else {
            return ControlFlow::Continue(());
        };
        let lookup = sub.lookup();
        let none = Nested::default();
        let mut q = AnyHit::<P, C, MB> {
            prims: self.prims,
            refs: &sub.refs,
            nested: &none,
            ray: self.ray,
            t_min: self.t_min,
            t_max: self.t_max,
            stamps: &mut *self.stamps,
            stamp: self.stamp,
            counters: &mut *self.counters,
        };
        dda.walk(&lookup, &mut q)
    }
}

/// Calls `$body` with `$l` bound to the grid's lookup (monomorphised per
/// storage); `$empty` when the grid has no cells.
macro_rules! with_lookup {
    ($self:ident, $l:ident => $body:expr, $empty:expr) => {
        match &$self.cells {
            Cells::Dense { offsets } => {
                let $l = DenseLookup::new($self.geom.dims, &$self.occ, offsets, &$self.refs);
                $body
            }
            Cells::Hashed { table } => {
                let $l = HashedLookup {
                    occ: &$self.occ,
                    table,
                    refs: &$self.refs,
                    spread: [&$self.spread[0], &$self.spread[1], &$self.spread[2]],
                };
                $body
            }
            Cells::Empty => $empty,
        }
    };
}

impl<P: Primitive> Grid<P> {
    /// Builds a grid over `prims` (which it keeps; their order defines the
    /// primitive indices of hits).
    ///
    /// Never fails: an empty scene gives a grid with no cells, degenerate
    /// extents (a flat scene, one object, all objects at one point) give
    /// one cell along the degenerate axes, and primitives with non-finite
    /// boxes are kept aside and tested by every query. See [`GridConfig`]
    /// for the resolution and its caps.
    ///
    /// # Panics
    ///
    /// If there are more than `u32::MAX` primitives (hits name primitives by
    /// a `u32`).
    #[must_use]
    pub fn build(prims: Vec<P>, config: &GridConfig) -> Self {
        Self::assemble(prims, config, None)
    }

    /// The build; `copy` (given for [`Grid::build_with_copies`]) gathers
    /// the copies, given the primitives and the primitive of each slot.
    fn assemble(prims: Vec<P>, config: &GridConfig, copy: Option<Gather<P>>) -> Self {
        assert!(
            u32::try_from(prims.len()).is_ok(),
            "at most u32::MAX primitives"
        );
        let start = Instant::now();
        let b = build::build(&prims, config, copy.is_some());
        let copies = copy.map_or_else(|| Box::new([]) as Box<[P]>, |f| f(&prims, &b.ids));
        let build_time = start.elapsed();
        let mut grid = Self {
            prims,
            config: *config,
            geom: b.geom,
            cells: b.cells,
            refs: b.refs,
            copies,
            ids: b.ids,
            unbounded: b.unbounded,
            spread: b.spread,
            blocks: BlockMap::default(),
            occ: Box::new([]),
            nested: Nested::default(),
            stats: GridStats::default(),
        };
        grid.blocks = grid.block_map();
        grid.occ = grid.occupancy_bits();
        let crowded = grid.runs(config.nest_min_refs as usize);
        let nested = Nested::build(grid.slots(), &grid.geom, grid.refs.len(), crowded, config);
        grid.nested = nested;
        let cells = grid.geom.cell_count();
        let table_bytes = match &grid.cells {
            Cells::Empty => 0,
            Cells::Dense { offsets } => std::mem::size_of_val(&**offsets),
            Cells::Hashed { table } => table.bytes(),
        };
        let planes: usize = grid
            .geom
            .planes
            .iter()
            .map(|p| std::mem::size_of_val(&**p))
            .sum();
        let spread: usize = grid
            .spread
            .iter()
            .map(|s| std::mem::size_of_val(&**s))
            .sum::<usize>()
            + grid.blocks.bytes()
            + std::mem::size_of_val(&*grid.occ);
        grid.stats = GridStats {
            dims: grid.geom.dims,
            cells,
            occupied_cells: b.occupied,
            references: grid.refs.len() as u64,
            mean_refs_per_occupied: if b.occupied == 0 {
                0.0
            } else {
                grid.refs.len() as f64 / b.occupied as f64
            },
            max_refs_per_cell: b.max_refs,
            bytes: table_bytes
                + std::mem::size_of_val(&*grid.refs)
                + planes
                + spread
                + std::mem::size_of_val(&*grid.unbounded)
                + std::mem::size_of_val(&*grid.copies)
                + std::mem::size_of_val(&*grid.ids)
                + grid.nested.bytes(),
            table_bytes,
            unbounded_prims: grid.unbounded.len() as u64,
            nested_cells: grid.nested.subs.len() as u64,
            build_time,
        };
        grid
    }

    /// What the references index: the copies, or the primitives.
    fn slots(&self) -> &[P] {
        if self.copies.is_empty() {
            &self.prims
        } else {
            &self.copies
        }
    }

    /// Numbers describing the grid (dimensions, occupancy, memory, build time).
    #[must_use]
    pub fn stats(&self) -> &GridStats {
        &self.stats
    }

    /// The grid box: the union of the finite primitive boxes
    /// ([`Aabb::EMPTY`] when there is none).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.geom.bounds
    }

    /// Cells per axis (all zero for a grid without cells).
    #[must_use]
    pub fn dims(&self) -> [u32; 3] {
        self.geom.dims
    }

    /// The configuration the grid was built with.
    #[must_use]
    pub fn config(&self) -> &GridConfig {
        &self.config
    }

    /// The primitives, in index order.
    #[must_use]
    pub fn primitives(&self) -> &[P] {
        &self.prims
    }

    /// Gives the primitives back, in their original order.
    #[must_use]
    pub fn into_primitives(self) -> Vec<P> {
        self.prims
    }

    /// Indices of the primitives kept outside the cells (non-finite boxes).
    #[must_use]
    pub fn unbounded_primitives(&self) -> &[u32] {
        &self.unbounded
    }

    /// The box of cell `index` (without the insertion pad); `None` outside the grid.
    #[must_use]
    pub fn cell_bounds(&self, index: [u32; 3]) -> Option<Aabb> {
        self.in_grid(index).then(|| self.geom.cell_box(index))
    }

    /// The primitive indices stored in cell `index`, each once, in an
    /// unspecified (but deterministic) order; empty for an unoccupied cell
    /// or an index outside the grid.
    #[must_use]
    pub fn cell_refs(&self, index: [u32; 3]) -> Vec<u32> {
        if !self.in_grid(index) {
            return Vec::new();
        }
        let refs: &[u32] =
            with_lookup!(self, l => { let (k, _) = l.start(index, [false; 3]); l.refs(k) }, &[]);
        refs.iter().map(|&r| self.primitive_of(r)).collect()
    }

    /// The primitive index of a reference as [`Grid::visit_cells`] hands
    /// it out: the reference itself, or for a grid with copies
    /// ([`Grid::build_with_copies`]) the primitive of that slot.
    #[must_use]
    pub fn primitive_of(&self, reference: u32) -> u32 {
        prim_id(&self.ids, reference)
    }

    /// The occupancy of blocks of cells, for skipping empty space.
    fn block_map(&self) -> BlockMap {
        let dims = self.geom.dims;
        match &self.cells {
            Cells::Empty => BlockMap::default(),
            Cells::Dense { offsets } => BlockMap::from_dense(dims, offsets),
            Cells::Hashed { table } => {
                BlockMap::new(dims, table.occupied().map(|s| morton::decode3(s.key)))
            }
        }
    }

    /// The nested grids: one for each cell of at least `nest_min_refs`
    /// references and no other, each over what its references cover of the
    /// cell and holding exactly the cell's references in every nested cell
    /// their padded box overlaps.
    fn check_nested(&self) -> Result<(), String> {
        let crowded = self.runs(self.config.nest_min_refs as usize);
        if crowded.len() != self.nested.subs.len() {
            return Err(format!(
                "{} nested grids for {} crowded cells",
                self.nested.subs.len(),
                crowded.len()
            ));
        }
        for (idx, start, refs) in crowded {
            let sub = self
                .nested
                .find(refs.len(), start)
                .ok_or_else(|| format!("cell {idx:?}: no nested grid"))?;
            let g = &sub.geom;
            let prims = self.slots();
            let boxes = refs.iter().map(|&p| prims[p as usize].bounds());
            if g.bounds != crate::nested::cover(&self.geom, idx, boxes) || g.pad < self.geom.pad {
                return Err(format!("cell {idx:?}: nested grid not over the cell"));
            }
            let cells = g.cell_count() as usize;
            let o = &sub.offsets;
            if o.len() != cells + 1
                || o[0] != 0
                || o[cells] as usize != sub.refs.len()
                || o.windows(2).any(|w| w[0] > w[1])
            {
                return Err(format!("cell {idx:?}: nested offsets malformed"));
            }
            let mut want = Vec::new();
            for &p in refs {
                let range = g.cell_range(&prims[p as usize].bounds());
                g.for_each_cell(range, |c| want.push((c, p)));
            }
            let mut got = Vec::new();
            for c in 0..cells {
                let run = &sub.refs[o[c] as usize..o[c + 1] as usize];
                got.extend(run.iter().map(|&p| (c, p)));
                let occupied = sub.occ[c >> 6] >> (c & 63) & 1 != 0;
                if occupied == run.is_empty() {
                    return Err(format!("cell {idx:?}: nested occupancy bit {c} wrong"));
                }
            }
            want.sort_unstable();
            got.sort_unstable();
            if want != got {
                return Err(format!("cell {idx:?}: nested references differ"));
            }
        }
        Ok(())
    }

    /// The occupied cells with at least `min` references (none for 0): each
    /// cell's index, where its run starts among the references, and the run.
    fn runs(&self, min: usize) -> Vec<([u32; 3], u32, &[u32])> {
        let run = |s: u32, e: u32| &self.refs[s as usize..e as usize];
        match &self.cells {
            _ if min == 0 => Vec::new(),
            Cells::Empty => Vec::new(),
            Cells::Dense { offsets } => {
                let [nx, ny, _] = self.geom.dims;
                let keep = |(_, w): &(usize, &[u32])| (w[1] - w[0]) as usize >= min;
                let cell = |(c, w): (usize, &[u32])| {
                    let c = c as u32;
                    (
                        [c % nx, (c / nx) % ny, c / (nx * ny)],
                        w[0],
                        run(w[0], w[1]),
                    )
                };
                offsets
                    .windows(2)
                    .enumerate()
                    .filter(keep)
                    .map(cell)
                    .collect()
            }
            Cells::Hashed { table } => table
                .occupied()
                .filter(|s| s.len as usize >= min)
                .map(|s| {
                    (
                        morton::decode3(s.key),
                        s.start,
                        run(s.start, s.start + s.len),
                    )
                })
                .collect(),
        }
    }

    /// Whether the queries take the two-level walk: when enough blocks are
    /// empty, and always with the hashed table, whose probe for an empty
    /// cell costs far more than the occupancy bit.
    #[inline(always)]
    fn skips(&self) -> bool {
        self.blocks.useful || matches!(self.cells, Cells::Hashed { .. })
    }

    /// One bit per cell key (row-major index or Morton code).
    fn occupancy_bits(&self) -> Box<[u64]> {
        match &self.cells {
            Cells::Empty => Box::new([]),
            Cells::Dense { offsets } => dense_occupancy(offsets),
            Cells::Hashed { table } => {
                let d = self.geom.dims.map(|n| n - 1);
                let max_key = morton::encode3(d[0], d[1], d[2]);
                let mut bits = vec![0u64; (max_key as usize + 1).div_ceil(64)];
                for s in table.occupied() {
                    bits[(s.key >> 6) as usize] |= 1 << (s.key & 63);
                }
                bits.into_boxed_slice()
            }
        }
    }

    fn in_grid(&self, index: [u32; 3]) -> bool {
        (0..3).all(|a| index[a] < self.geom.dims[a])
    }

    /// The cells the ray passes through within `[t_min, t_max]`, in order,
    /// each with its parametric interval: a non-allocating 3D-DDA
    /// (Amanatides & Woo 1987). Empty when the ray misses the grid box in
    /// that range, or the range is empty or NaN.
    ///
    /// The walk enters through the robust [`Aabb::hit`]; an entry on the
    /// grid's max face starts in the last cell; an axis along which the ray
    /// does not move (direction ±0, or a denormal whose reciprocal overflows)
    /// is never stepped.
    pub fn cells_along(&self, ray: &Ray, t_min: Real, t_max: Real) -> CellIter<'_> {
        CellIter::new(Dda::new(&self.geom, ray, t_min, t_max))
    }

    /// Calls `f` for every cell along the ray within `[t_min, t_max]`, in
    /// order, with the cell's visit and its references (empty for an
    /// unoccupied cell), until `f` returns `ControlFlow::Break`. The same
    /// walk as [`Grid::cells_along`], with the cell lookup done. References
    /// are primitive indices, except in a grid with copies, where
    /// [`Grid::primitive_of`] maps them to primitive indices.
    pub fn visit_cells<B>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        mut f: impl FnMut(CellVisit, &[u32]) -> ControlFlow<B>,
    ) -> ControlFlow<B> {
        let Some(dda) = Dda::new(&self.geom, ray, t_min, t_max) else {
            return ControlFlow::Continue(());
        };
        with_lookup!(self, l => dda.walk(&l, &mut FnCell(&mut f)), ControlFlow::Continue(()))
    }

    /// [`Accelerator::closest_hit`] that also reports cells visited, tests
    /// made and mailbox skips to `counters`.
    pub fn closest_hit_counted<C: Counters>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        scratch: &mut GridScratch,
        counters: &mut C,
    ) -> Option<Hit> {
        if self.config.mailbox {
            self.closest::<C, true>(ray, t_min, t_max, scratch, counters)
        } else {
            self.closest::<C, false>(ray, t_min, t_max, scratch, counters)
        }
    }

    /// [`Accelerator::any_hit`] that also reports to `counters`.
    pub fn any_hit_counted<C: Counters>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        scratch: &mut GridScratch,
        counters: &mut C,
    ) -> bool {
        if self.config.mailbox {
            self.any::<C, true>(ray, t_min, t_max, scratch, counters)
        } else {
            self.any::<C, false>(ray, t_min, t_max, scratch, counters)
        }
    }

    #[inline(always)]
    fn closest<C: Counters, const MB: bool>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        scratch: &mut GridScratch,
        counters: &mut C,
    ) -> Option<Hit> {
        counters.ray();
        if !(t_min <= t_max) {
            return None;
        }
        let mut q = Closest::<P, C, MB> {
            prims: self.slots(),
            ids: &self.ids,
            refs: &self.refs,
            nested: &self.nested,
            ray,
            t_min,
            t_lim: t_max,
            best: None,
            stamps: &mut [],
            stamp: 0,
            counters,
        };
        for &p in self.unbounded.iter() {
            q.test_prim(|| p, &self.prims[p as usize]);
        }
        let Some(dda) = Dda::new(&self.geom, ray, t_min, t_max) else {
            return q.best;
        };
        if MB {
            q.stamp = scratch.begin(self.prims.len());
            q.stamps = &mut scratch.stamps;
        }
        // Sparse grids skip empty blocks and cells; dense ones walk every cell.
        let _ = if self.skips() {
            with_lookup!(self, l => dda.walk_skip(&l, &self.blocks, &mut q), ControlFlow::Continue(()))
        } else {
            with_lookup!(self, l => dda.walk(&l, &mut q), ControlFlow::Continue(()))
        };
        q.best
    }

    #[inline(always)]
    fn any<C: Counters, const MB: bool>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        scratch: &mut GridScratch,
        counters: &mut C,
    ) -> bool {
        counters.ray();
        if !(t_min <= t_max) {
            return false;
        }
        for &p in self.unbounded.iter() {
            counters.test();
            if self.prims[p as usize].any_hit(ray, t_min, t_max) {
                return true;
            }
        }
        let Some(dda) = Dda::new(&self.geom, ray, t_min, t_max) else {
            return false;
        };
        let mut q = AnyHit::<P, C, MB> {
            prims: self.slots(),
            refs: &self.refs,
            nested: &self.nested,
            ray,
            t_min,
            t_max,
            stamps: &mut [],
            stamp: 0,
            counters,
        };
        if MB {
            q.stamp = scratch.begin(self.prims.len());
            q.stamps = &mut scratch.stamps;
        }
        if self.skips() {
            with_lookup!(self, l => dda.walk_skip(&l, &self.blocks, &mut q), ControlFlow::Continue(())).is_break()
        } else {
            with_lookup!(self, l => dda.walk(&l, &mut q), ControlFlow::Continue(())).is_break()
        }
    }

    /// Checks the grid's internal consistency; `Err` names the first
    /// violation. Meant for tests (it is slow: it re-derives every
    /// primitive's cells).
    ///
    /// Checked: the geometry (planes nondecreasing from the box's min to its
    /// max, cell count within the cap), the CSR layout (offsets or table
    /// runs inside the reference array, no primitive twice in a
    /// cell, keys in Morton order), that every gridded primitive is in
    /// exactly the cells its padded box overlaps (or, with exact insertion,
    /// in every such cell it reports touching and no other), that the
    /// unbounded list holds exactly the primitives with non-finite boxes,
    /// that a grid with copies has exactly one slot per gridded primitive
    /// holding its copy, and that the stats match.
    pub fn check_invariants(&self) -> Result<(), String> {
        let g = &self.geom;
        let n = self.prims.len();
        if self.copies.len() != self.ids.len() {
            return Err(format!(
                "{} copies for {} slots",
                self.copies.len(),
                self.ids.len()
            ));
        }
        if !self.copies.is_empty() {
            // Every gridded primitive has exactly one slot holding its copy.
            let mut seen = vec![false; n];
            for (k, (c, &p)) in self.copies.iter().zip(self.ids.iter()).enumerate() {
                let Some(prim) = self.prims.get(p as usize) else {
                    return Err(format!("slot {k}: primitive {p} of {n}"));
                };
                if std::mem::replace(&mut seen[p as usize], true) {
                    return Err(format!("primitive {p} has two slots"));
                }
                if prim.bounds() != c.bounds() {
                    return Err(format!("slot {k} is not a copy of primitive {p}"));
                }
            }
            if self.ids.len() + self.unbounded.len() != n {
                return Err("not every gridded primitive has a slot".into());
            }
        }
        if g.is_empty() {
            if !self.refs.is_empty() || !matches!(self.cells, Cells::Empty) {
                return Err("empty grid with cells or references".into());
            }
        } else {
            for a in 0..3 {
                let p = &g.planes[a];
                if g.dims[a] == 0 || p.len() != g.dims[a] as usize + 1 {
                    return Err(format!(
                        "axis {a}: {} planes for {} cells",
                        p.len(),
                        g.dims[a]
                    ));
                }
                if p[0] != g.bounds.min[a] || p[p.len() - 1] != g.bounds.max[a] {
                    return Err(format!("axis {a}: planes do not span the grid box"));
                }
                if p.windows(2).any(|w| !(w[0] <= w[1])) {
                    return Err(format!("axis {a}: planes not nondecreasing"));
                }
            }
            if g.cell_count() > self.config.max_cells.max(1) {
                return Err(format!(
                    "{} cells exceed max_cells {}",
                    g.cell_count(),
                    self.config.max_cells
                ));
            }
        }
        let slots = self.slots().len();
        if let Some(&p) = self.refs.iter().find(|&&p| p as usize >= slots) {
            return Err(format!("reference {p} of {slots}"));
        }
        // Every cell's run, by key order.
        let mut runs: Vec<(u64, [u32; 3], u32, u32)> = Vec::new();
        match &self.cells {
            Cells::Empty => {}
            Cells::Dense { offsets } => {
                if offsets.len() as u64 != g.cell_count() + 1 {
                    return Err("dense offsets: wrong length".into());
                }
                if offsets[0] != 0 || offsets[offsets.len() - 1] as usize != self.refs.len() {
                    return Err("dense offsets do not span the references".into());
                }
                let [nx, ny, _] = g.dims;
                for c in 0..offsets.len() - 1 {
                    let (s, e) = (offsets[c], offsets[c + 1]);
                    if s > e {
                        return Err(format!("dense offsets decrease at cell {c}"));
                    }
                    if e > s {
                        let c32 = c as u32;
                        let idx = [c32 % nx, (c32 / nx) % ny, c32 / (nx * ny)];
                        runs.push((c as u64, idx, s, e - s));
                    }
                }
            }
            Cells::Hashed { table } => {
                let mut slots: Vec<_> = table.occupied().copied().collect();
                slots.sort_by_key(|s| s.start);
                let mut next = 0u32;
                let mut prev_key = None;
                for s in &slots {
                    if s.start != next || s.len == 0 {
                        return Err(format!("hashed runs not contiguous at {}", s.start));
                    }
                    next = s.start + s.len;
                    if prev_key.is_some_and(|k| k >= s.key) {
                        return Err("references not in Morton order".into());
                    }
                    prev_key = Some(s.key);
                    let idx = morton::decode3(s.key);
                    if !self.in_grid(idx) {
                        return Err(format!("cell key {} outside the grid", s.key));
                    }
                    if table.get(s.key) != (s.start, s.len) {
                        return Err(format!("cell key {} not found by probing", s.key));
                    }
                    runs.push((s.key, idx, s.start, s.len));
                }
                if next as usize != self.refs.len() {
                    return Err("hashed runs do not span the references".into());
                }
                if table.capacity() < 2 * slots.len() {
                    return Err("hash table over half full".into());
                }
            }
        }
        // The block map and the occupancy bits say which cells hold references.
        if !matches!(self.cells, Cells::Empty) {
            let blocks = BlockMap::new(g.dims, runs.iter().map(|r| r.1));
            if blocks.bits != self.blocks.bits {
                return Err("block map disagrees with the occupied cells".into());
            }
            let bit = |key: u64| {
                self.occ
                    .get((key >> 6) as usize)
                    .map_or(0, |w| w >> (key & 63) & 1)
            };
            let set: u64 = self.occ.iter().map(|w| u64::from(w.count_ones())).sum();
            if set != runs.len() as u64 || runs.iter().any(|r| bit(r.0) == 0) {
                return Err("occupancy bits disagree with the occupied cells".into());
            }
        }
        self.check_nested()?;
        // Expected (cell, primitive) pairs against the stored ones.
        let mut stored: Vec<([u32; 3], u32)> = Vec::with_capacity(self.refs.len());
        for &(_, idx, s, len) in &runs {
            let r = &self.refs[s as usize..(s + len) as usize];
            let mut sorted = r.to_vec();
            sorted.sort_unstable();
            if sorted.windows(2).any(|w| w[0] == w[1]) {
                return Err(format!("cell {idx:?}: a primitive listed twice"));
            }
            stored.extend(r.iter().map(|&p| (idx, self.primitive_of(p))));
        }
        let mut expected = Vec::with_capacity(stored.len());
        let mut unbounded = Vec::new();
        for (p, prim) in self.prims.iter().enumerate() {
            let b = prim.bounds();
            if !build::is_gridded(&b) {
                unbounded.push(p as u32);
                continue;
            }
            if g.is_empty() {
                return Err(format!("primitive {p} is finite but the grid is empty"));
            }
            if !g.bounds.contains(b.min) || !g.bounds.contains(b.max) {
                return Err(format!("primitive {p} sticks out of the grid box"));
            }
            let (lo, hi) = g.cell_range(&b);
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        let inside = !self.config.exact_insertion
                            || lo == hi
                            || prim.overlaps_box(&g.padded_cell_box([i, j, k]));
                        if inside {
                            expected.push(([i, j, k], p as u32));
                        }
                    }
                }
            }
        }
        if unbounded[..] != self.unbounded[..] {
            return Err("unbounded list does not match the non-finite boxes".into());
        }
        stored.sort_unstable();
        expected.sort_unstable();
        if stored != expected {
            let missing = expected.iter().find(|x| stored.binary_search(x).is_err());
            let extra = stored.iter().find(|x| expected.binary_search(x).is_err());
            return Err(format!(
                "cell contents differ: missing {missing:?}, extra {extra:?}"
            ));
        }
        let s = &self.stats;
        if s.dims != g.dims
            || s.references != self.refs.len() as u64
            || s.occupied_cells != runs.len() as u64
        {
            return Err("stats do not match the grid".into());
        }
        if s.max_refs_per_cell != runs.iter().map(|r| r.3).max().unwrap_or(0) {
            return Err("stats: wrong max references per cell".into());
        }
        Ok(())
    }
}

impl<P: Primitive + Clone + Send> Grid<P> {
    /// Like [`Grid::build`], and also stores a copy of every gridded
    /// primitive in cell order (by the first cell that references it), so
    /// that primitives near each other in space lie near each other in
    /// memory; the references then name copies (slots), and hits are mapped
    /// back to primitive indices. A query reads a cell's primitives from a
    /// few neighbouring cache lines instead of jumping to wherever the scene
    /// order put them: for small primitives in large scenes (a million
    /// spheres in random order) most of a query's time is those cache
    /// misses. It costs one copy and one index per primitive (in
    /// [`GridStats::bytes`]), an exact sort by first cell, and one gather
    /// at build time (in parallel when the configuration allows). Answers
    /// are identical with and without, ties included (they are decided by
    /// primitive index, not slot).
    ///
    /// ```
    /// use gridrt_grid::{Aabb, Accelerator, Grid, GridConfig, PrimHit, Primitive, Ray, Real, Vec3};
    /// # #[derive(Clone)]
    /// # struct Ball(Vec3, Real);
    /// # impl Primitive for Ball {
    /// #     fn bounds(&self) -> Aabb {
    /// #         Aabb::new(self.0 - Vec3::splat(self.1), self.0 + Vec3::splat(self.1))
    /// #     }
    /// #     fn closest_hit(&self, ray: &Ray, t0: Real, t1: Real) -> Option<PrimHit> {
    /// #         let oc = ray.origin - self.0;
    /// #         let (a, b, c) = (ray.dir.dot(ray.dir), oc.dot(ray.dir), oc.dot(oc) - self.1 * self.1);
    /// #         let disc = b * b - a * c;
    /// #         if disc < 0.0 {
    /// #             return None;
    /// #         }
    /// #         let s = disc.sqrt();
    /// #         [(-b - s) / a, (-b + s) / a].into_iter().find(|t| (t0..=t1).contains(t)).map(|t| PrimHit { t, u: 0.0, v: 0.0 })
    /// #     }
    /// # }
    /// // `Ball` is the sphere of the crate example.
    /// let spheres: Vec<Ball> = (0..100).map(|i| Ball(Vec3::new(i as Real, 0.0, 0.0), 0.4)).collect();
    /// let plain = Grid::build(spheres.clone(), &GridConfig::default());
    /// let fast = Grid::build_with_copies(spheres, &GridConfig::default());
    /// let ray = Ray::new(Vec3::new(-5.0, 0.1, 0.0), Vec3::X);
    /// let a = plain.closest_hit(&ray, 0.0, Real::INFINITY, &mut plain.scratch());
    /// let b = fast.closest_hit(&ray, 0.0, Real::INFINITY, &mut fast.scratch());
    /// assert_eq!(a, b);
    /// assert_eq!(b.unwrap().prim, 0);
    /// assert!(fast.stats().bytes > plain.stats().bytes);
    /// ```
    ///
    /// # Panics
    ///
    /// As [`Grid::build`].
    #[must_use]
    pub fn build_with_copies(prims: Vec<P>, config: &GridConfig) -> Self {
        let parallel = config.parallel_build;
        Self::assemble(
            prims,
            config,
            Some(Box::new(move |prims: &[P], ids: &[u32]| {
                crate::par::map_range(ids.len(), parallel, |i| {
                    // The reads jump around: ask for a primitive some slots ahead.
                    if let Some(&p) = ids.get(i + 32) {
                        crate::mem::prefetch(&prims[p as usize]);
                    }
                    prims[ids[i] as usize].clone()
                })
                .into_boxed_slice()
            })),
        )
    }
}

impl<P: Primitive> Accelerator for Grid<P> {
    type Prim = P;
    type Scratch = GridScratch;

    /// A mailbox sized to the primitives when `config.mailbox` is on,
    /// otherwise an empty scratch (nothing allocated).
    fn scratch(&self) -> GridScratch {
        if self.config.mailbox {
            GridScratch {
                stamps: vec![0; self.prims.len()],
                ray: 0,
            }
        } else {
            GridScratch::default()
        }
    }

    fn primitives(&self) -> &[P] {
        &self.prims
    }

    #[inline]
    fn closest_hit(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        scratch: &mut GridScratch,
    ) -> Option<Hit> {
        self.closest_hit_counted(ray, t_min, t_max, scratch, &mut NoCounters)
    }

    #[inline]
    fn any_hit(&self, ray: &Ray, t_min: Real, t_max: Real, scratch: &mut GridScratch) -> bool {
        self.any_hit_counted(ray, t_min, t_max, scratch, &mut NoCounters)
    }
}

impl<P> Grid<P> {
    /// Whether the grid keeps copies of its primitives in cell order
    /// ([`Grid::build_with_copies`]).
    #[must_use]
    pub fn has_copies(&self) -> bool {
        !self.copies.is_empty()
    }

    /// The cell storage in use ([`GridConfig::storage`]).
    #[must_use]
    pub fn storage(&self) -> CellStorage {
        self.config.storage
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Exhaustive, PrimHit};
    use gridrt_bbox::Vec3;

    /// A ball, just enough for these tests.
    #[derive(Clone, Debug)]
    struct Ball(Vec3, Real);

    impl Primitive for Ball {
        fn bounds(&self) -> Aabb {
            Aabb::new(self.0 - Vec3::splat(self.1), self.0 + Vec3::splat(self.1))
        }
        fn closest_hit(&self, ray: &Ray, t0: Real, t1: Real) -> Option<PrimHit> {
            let oc = ray.origin - self.0;
            let (a, b, c) = (
                ray.dir.dot(ray.dir),
                oc.dot(ray.dir),
                oc.dot(oc) - self.1 * self.1,
            );
            let disc = b * b - a * c;
            if disc < 0.0 {
                return None;
            }
            let s = disc.sqrt();
            [(-b - s) / a, (-b + s) / a]
                .into_iter()
                .find(|t| (t0..=t1).contains(t))
                .map(|t| PrimHit { t, u: 0.0, v: 0.0 })
        }
    }

    fn lcg(s: &mut u64) -> Real {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*s >> 40) as Real / (1u64 << 24) as Real
    }

    #[test]
    fn mailbox_ids_wrap_around_safely() {
        let mut s = GridScratch::default();
        assert_eq!(s.begin(3), 1);
        s.stamps[1] = 1;
        s.ray = u32::MAX;
        // The id wraps to 0, which would match fresh stamps: all are cleared.
        s.stamps[2] = u32::MAX;
        assert_eq!(s.begin(3), 1);
        assert_eq!(s.stamps, vec![0, 0, 0]);
        // A scratch sized for other primitives is resized and reset.
        assert_eq!(s.begin(5), 1);
        assert_eq!(s.stamps.len(), 5);
    }

    #[test]
    fn sparse_scenes_skip_empty_blocks_and_stay_exact() {
        // Clusters of balls far apart: most blocks of the grid are empty.
        let mut seed = 1;
        let mut prims = Vec::new();
        for c in 0..6 {
            let centre = Vec3::new(
                c as Real * 7.0 - 20.0,
                (c % 3) as Real * 9.0 - 9.0,
                (c % 2) as Real * 11.0,
            );
            for _ in 0..80 {
                let p = centre + Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed));
                prims.push(Ball(p, 0.02 + 0.05 * lcg(&mut seed)));
            }
        }
        let e = Exhaustive::new(prims.clone());
        for storage in [CellStorage::Dense, CellStorage::Hashed] {
            for mailbox in [false, true] {
                let g = Grid::build(
                    prims.clone(),
                    &GridConfig {
                        storage,
                        mailbox,
                        m: 3.0,
                        ..GridConfig::default()
                    },
                );
                assert!(g.blocks.useful, "the walk should skip empty blocks here");
                g.check_invariants().expect("invariants");
                let mut sc = g.scratch();
                let mut hits = 0;
                for i in 0..3000 {
                    let o = Vec3::new(
                        lcg(&mut seed) * 60.0 - 30.0,
                        lcg(&mut seed) * 40.0 - 20.0,
                        lcg(&mut seed) * 40.0 - 15.0,
                    );
                    let target = prims[i % prims.len()].0
                        + Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 0.2;
                    let r = Ray::new(o, target - o);
                    let want = e.closest_hit(&r, 0.0, Real::INFINITY, &mut ());
                    assert_eq!(g.closest_hit(&r, 0.0, Real::INFINITY, &mut sc), want);
                    assert_eq!(
                        g.any_hit(&r, 0.0, 0.9, &mut sc),
                        e.any_hit(&r, 0.0, 0.9, &mut ())
                    );
                    hits += usize::from(want.is_some());
                }
                assert!(hits > 1000, "{hits}");
            }
        }
    }

    #[test]
    fn dense_scenes_walk_every_cell() {
        let mut seed = 3;
        let prims: Vec<Ball> = (0..2000)
            .map(|_| {
                Ball(
                    Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)),
                    0.02,
                )
            })
            .collect();
        let g = Grid::build(prims, &GridConfig::default());
        assert!(!g.blocks.useful);
    }
}
