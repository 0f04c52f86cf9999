//! The regular grid: construction, queries, the cell walk and self-checks.

use crate::build;
use crate::cells::{dense_occupancy, Cells};
use crate::counters::{Counters, NoCounters};
use crate::dda::{BlockMap, CellFn, CellIter, CellLookup, CellVisit, Dda};
use crate::empty_space;
use crate::geom::{self, Geom};
use crate::groups::{Groups, Run, GROUP_MIN_REFS};
use crate::nested::{NestParams, Nested};
use crate::{
    any_hits_each, morton, Accelerator, CellStorage, GridConfig, GridStats, Hit, Primitive,
};
use gridrt_bbox::{Aabb, Ray, Real, SlabRay};
use std::ops::ControlFlow;
use std::time::Instant;

mod check;
mod fours;
mod lookup;
mod query;
mod slots;

use fours::{any_in_fours, pack_fours};
use lookup::{DenseLookup, HashedLookup};

use query::{AnyHit, Closest};
use slots::{reorder, slot_order};

/// `closest_hit` stops after a cell only if the best hit lies before the
/// cell's exit by more than this fraction of `|t_exit|` (a few ulps): a hit
/// on, or within rounding of, the plane between two cells may be tied with a
/// lower-index primitive in the next cell, which must be tested too.
pub(crate) const EXIT_MARGIN: Real = 8.0 * Real::EPSILON;

/// Fewer unbounded (or set-aside) primitives than this are tested one by
/// one: a floor's two triangles cost less alone than gathered four-wide.
const ONE_BY_ONE_BELOW: usize = 4;

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
/// The grid owns one array of its primitives, reordered once at build time
/// into cell order (by the first cell, in storage order, that references
/// each; pbrt-v4's `BVHAggregate` swaps in its `orderedPrims` the same
/// way), so that the primitives of neighbouring cells lie in neighbouring
/// memory; beside it, the primitive index of each slot. The references name
/// slots; hits name primitive indices (the given order), and ties go to the
/// lower primitive index, exactly as in [`crate::Exhaustive`].
///
/// The grid is immutable after [`Grid::build`] and `Sync`; per-query working
/// memory (the mailbox) is the caller's [`GridScratch`].
#[derive(Clone, Debug)]
pub struct Grid<P: Primitive> {
    /// The primitives in slot order: the gridded ones in the order in
    /// which the cells, in storage order, first reference them, then the
    /// unbounded ones.
    prims: Vec<P>,
    /// What the primitives share ([`Primitive::Shared`]).
    shared: P::Shared,
    config: GridConfig,
    geom: Geom,
    cells: Cells,
    /// The cells' references: slots.
    refs: Box<[u32]>,
    /// The primitive index of each slot.
    ids: Box<[u32]>,
    /// The slots of the primitives kept outside the cells.
    unbounded: Box<[u32]>,
    /// One cell, whose references every query that meets the grid box
    /// tests without walking ([`GridConfig::direct`]).
    direct: bool,
    /// A direct grid's primitives four by four in reference order, laid
    /// out for [`Primitive::four_may_hit`] (when [`Primitive::PACKS_FOUR`];
    /// else empty): testing them needs no gathering.
    fours: Box<[P::Four]>,
    spread: [Box<[u64]>; 3],
    blocks: BlockMap,
    /// One bit per cell key: set when the cell holds references.
    occ: Box<[u64]>,
    /// A sparse dense grid's distance from each cell to the nearest
    /// occupied one ([`crate::empty_space`]), which the queries' walk
    /// skips empty space by; empty when the grid has none.
    far: Box<[u8]>,
    /// The nested grids of crowded cells.
    nested: Nested,
    /// The group boxes of the other crowded cells ([`crate::groups`]).
    groups: Groups,
    stats: GridStats,
}

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

/// A closure as a [`CellFn`] (for the public visitor).
struct FnCell<F>(F);

impl<'a, B, F: FnMut(CellVisit, &'a [u32]) -> ControlFlow<B>> CellFn<'a> for FnCell<F> {
    type Break = B;
    #[inline(always)]
    fn call(&mut self, visit: CellVisit, refs: &'a [u32]) -> ControlFlow<B> {
        (self.0)(visit, refs)
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
    /// Builds a grid over `prims` (which it keeps, reordered into cell
    /// order; their given order defines the primitive indices of hits).
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
    pub fn build(prims: Vec<P>, config: &GridConfig) -> Self
    where
        P: Send,
        P::Shared: Default,
    {
        Self::build_shared(prims, P::Shared::default(), config)
    }

    /// [`Grid::build`] over primitives that refer to `shared` (a mesh's
    /// vertices; [`Primitive::Shared`]), which the grid keeps beside them.
    ///
    /// # Panics
    ///
    /// As [`Grid::build`].
    #[must_use]
    pub fn build_shared(prims: Vec<P>, shared: P::Shared, config: &GridConfig) -> Self
    where
        P: Send,
    {
        let (start, budget, b) = Self::index(&prims, &shared, config);
        let parallel = config.parallel_build;
        Self::assemble(start, budget, b, prims.len(), shared, config, |ids| {
            reorder(prims, ids, parallel)
        })
    }

    /// [`Grid::build`] over primitives the caller keeps (a scene's shared
    /// array): each primitive is cloned once, straight into its slot, with
    /// no copy in the given order on the way.
    ///
    /// # Panics
    ///
    /// As [`Grid::build`].
    #[must_use]
    pub fn build_from_slice(prims: &[P], config: &GridConfig) -> Self
    where
        P: Clone + Send,
        P::Shared: Default,
    {
        let shared = P::Shared::default();
        let (start, budget, b) = Self::index(prims, &shared, config);
        let parallel = config.parallel_build;
        Self::assemble(start, budget, b, prims.len(), shared, config, |ids| {
            crate::par::map_range(ids.len(), parallel, |s| {
                // The reads jump around: ask for a primitive some slots ahead.
                if let Some(&p) = ids.get(s + 32) {
                    crate::mem::prefetch(&prims[p as usize]);
                }
                prims[ids[s] as usize].clone()
            })
        })
    }

    /// The cells and references over `prims`, with the build's start and
    /// memory budget.
    fn index(
        prims: &[P],
        shared: &P::Shared,
        config: &GridConfig,
    ) -> (Instant, usize, build::Built) {
        assert!(
            u32::try_from(prims.len()).is_ok(),
            "at most u32::MAX primitives"
        );
        let start = Instant::now();
        let n = prims.len();
        let budget = config
            .budget_for(n, std::mem::size_of::<P>())
            .max(Self::min_budget(n));
        (start, budget, build::build(prims, shared, config, budget))
    }

    /// The grid from its index `b` over `n` primitives; `order` gives the
    /// primitives in slot order, given the primitive of each slot.
    fn assemble(
        start: Instant,
        budget: usize,
        b: build::Built,
        n: usize,
        shared: P::Shared,
        config: &GridConfig,
        order: impl FnOnce(&[u32]) -> Vec<P>,
    ) -> Self {
        let (ids, unbounded) = slot_order(b.ids, &b.unbounded, n);
        let prims = order(&ids);
        let mut grid = Self {
            prims,
            shared,
            config: *config,
            geom: b.geom,
            cells: b.cells,
            refs: b.refs,
            ids,
            unbounded,
            direct: false,
            fours: Box::new([]),
            spread: b.spread,
            blocks: BlockMap::default(),
            occ: Box::new([]),
            far: Box::new([]),
            nested: Nested::default(),
            groups: Groups::default(),
            stats: GridStats::default(),
        };
        grid.blocks = grid.block_map();
        grid.occ = grid.occupancy_bits();
        grid.far = grid.far_map(b.occupied, budget);
        let (min_refs, cost) = grid.nest_threshold(b.occupied, b.max_refs);
        let flat_bytes = grid.index_bytes();
        let crowded = grid.runs(min_refs as usize);
        let params = NestParams {
            min_refs: min_refs as usize,
            m: geom::sanitize_m(config.nest_m.unwrap_or(config.m)),
            budget: budget.saturating_sub(flat_bytes),
            parallel: config.parallel_build,
            slab: config.slab,
            cost,
            groups: config.cell_groups,
        };
        let nested = Nested::build(
            &grid.prims,
            &grid.shared,
            &grid.geom,
            &grid.refs,
            crowded,
            &params,
        );
        grid.nested = nested;
        if config.cell_groups {
            grid.groups = grid.group_boxes(budget);
        }
        grid.direct =
            config.direct(n) && grid.geom.cell_count() == 1 && grid.nested.subs.is_empty();
        if grid.direct && P::PACKS_FOUR {
            grid.fours = pack_fours(&grid.prims, &grid.shared, &grid.refs);
        }
        let build_time = start.elapsed();
        let cells = grid.geom.cell_count();
        let table_bytes = match &grid.cells {
            Cells::Empty => 0,
            Cells::Dense { offsets } => std::mem::size_of_val(&**offsets),
            Cells::Hashed { table } => table.bytes(),
        };
        let levels = grid.nested.level_stats();
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
            bytes: grid.index_bytes(),
            table_bytes,
            unbounded_prims: grid.unbounded.len() as u64,
            nested_cells: grid.nested.subs.len() as u64,
            nest_levels: levels.len() as u32,
            levels,
            grouped_cells: grid.groups.cells() as u64,
            nest_min_refs: if grid.nested.subs.is_empty() {
                0
            } else {
                min_refs
            },
            budget,
            build_time,
        };
        grid
    }

    /// The smallest memory budget a grid over `n` primitives is given: one
    /// cell holding each primitive once, its maps and some slack.
    fn min_budget(n: usize) -> usize {
        16 * n + 4096
    }

    /// The group boxes of the cells of at least [`GROUP_MIN_REFS`]
    /// references without a nested grid, when they fit in what `budget`
    /// leaves (none otherwise).
    fn group_boxes(&self, budget: usize) -> Groups {
        let mut runs: Vec<Run> = self
            .cells
            .runs(self.geom.dims, GROUP_MIN_REFS)
            .into_iter()
            .filter(|&(_, s, len)| self.nested.root.find(len as usize, s).is_none())
            .map(|(idx, s, len)| (s, len, idx))
            .collect();
        runs.sort_unstable();
        let bytes = Groups::bytes_for(self.refs.len(), &runs);
        if self.index_bytes() + bytes > budget {
            return Groups::default();
        }
        Groups::build(&self.prims, &self.shared, &self.refs, &runs, &self.geom)
    }

    /// Heap bytes of the grid's index: everything but the primitives.
    fn index_bytes(&self) -> usize {
        let table_bytes = match &self.cells {
            Cells::Empty => 0,
            Cells::Dense { offsets } => std::mem::size_of_val(&**offsets),
            Cells::Hashed { table } => table.bytes(),
        };
        let planes = self.geom.planes_bytes();
        let spread: usize = self
            .spread
            .iter()
            .map(|s| std::mem::size_of_val(&**s))
            .sum::<usize>()
            + self.blocks.bytes()
            + std::mem::size_of_val(&*self.occ)
            + std::mem::size_of_val(&*self.far);
        table_bytes
            + std::mem::size_of_val(&*self.refs)
            + planes
            + spread
            + std::mem::size_of_val(&*self.unbounded)
            + std::mem::size_of_val(&*self.ids)
            + self.groups.bytes()
            + self.nested.bytes()
            + std::mem::size_of_val(&*self.fours)
    }

    /// The `nest_min_refs` of this build, and whether the cost model
    /// decides cell by cell: the configured one, or, with
    /// [`GridConfig::auto`] and none configured, the fewest references
    /// the build plans a nested grid for ([`crate::cost::min_refs`]), if
    /// some cell reaches it (0: no nesting).
    fn nest_threshold(&self, occupied: u64, max_refs: u32) -> (u32, bool) {
        let c = &self.config;
        if c.nest_min_refs > 0 || !c.auto || occupied == 0 {
            return (c.nest_min_refs, false);
        }
        let t = crate::cost::min_refs();
        if max_refs >= t {
            (t, true)
        } else {
            (0, false)
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

    /// The primitives in slot order (cell order; see [`Grid`]):
    /// [`Hit::slot`] and the references of [`Grid::visit_cells`] index it.
    #[must_use]
    pub fn primitives(&self) -> &[P] {
        &self.prims
    }

    /// The primitive index of each slot.
    #[must_use]
    pub fn primitive_ids(&self) -> &[u32] {
        &self.ids
    }

    /// Gives the primitives back, in their given order.
    #[must_use]
    pub fn into_primitives(self) -> Vec<P> {
        let mut v: Vec<(u32, P)> = self.ids.iter().copied().zip(self.prims).collect();
        v.sort_unstable_by_key(|&(id, _)| id);
        v.into_iter().map(|(_, p)| p).collect()
    }

    /// Indices of the primitives kept outside the cells (non-finite
    /// boxes), ascending.
    #[must_use]
    pub fn unbounded_primitives(&self) -> Vec<u32> {
        self.unbounded
            .iter()
            .map(|&s| self.ids[s as usize])
            .collect()
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
    /// it out (a slot).
    ///
    /// # Panics
    ///
    /// If `reference` is not a slot of this grid.
    #[must_use]
    pub fn primitive_of(&self, reference: u32) -> u32 {
        self.ids[reference as usize]
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

    /// The occupied cells with at least `min` references (none for 0): each
    /// cell's index, where its run starts among the references, and the run.
    fn runs(&self, min: usize) -> Vec<([u32; 3], u32, &[u32])> {
        self.cells
            .runs(self.geom.dims, min)
            .into_iter()
            .map(|(idx, s, len)| (idx, s, &self.refs[s as usize..(s + len) as usize]))
            .collect()
    }

    /// Whether the queries take the two-level walk: when enough blocks are
    /// empty, and always with the hashed table, whose probe for an empty
    /// cell costs far more than the occupancy bit.
    #[inline(always)]
    fn skips(&self) -> bool {
        self.blocks.useful || matches!(self.cells, Cells::Hashed { .. })
    }

    /// The distance map of a dense grid with `occupied` cells, when one
    /// pays: when at least a tenth of the cells is empty, the grid has at
    /// most [`empty_space::MAX_CELLS`] cells and the map (a byte a cell)
    /// fits the memory `budget` beside the rest of the index.
    fn far_map(&self, occupied: u64, budget: usize) -> Box<[u8]> {
        let cells = self.geom.cell_count();
        let sparse = occupied.saturating_mul(10) < cells.saturating_mul(9);
        let fits = (cells as usize).saturating_add(self.index_bytes()) <= budget;
        if !(matches!(self.cells, Cells::Dense { .. })
            && sparse
            && fits
            && cells as usize <= empty_space::MAX_CELLS)
        {
            return Box::new([]);
        }
        empty_space::far_map(self.geom.dims, |c| bit(&self.occ, c as u64))
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
    /// are slots: [`Grid::primitives`] indexes them and
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
        // The primitives' ray data only for a ray that has something to
        // test: one that enters the grid, or any with unbounded primitives.
        let slab = SlabRay::new(ray);
        let (dda, direct) = self.enter(ray, &slab, t_min, t_max);
        if dda.is_none() && !direct && self.unbounded.is_empty() {
            return None;
        }
        let data = P::ray_data(ray);
        let mut q = Closest::<P, C, MB> {
            prims: &self.prims,
            shared: &self.shared,
            ids: &self.ids,
            refs: &self.refs,
            children: &self.nested.root,
            groups: Some(&self.groups),
            subs: &self.nested.subs,
            ray,
            slab,
            data: &data,
            t_min,
            t_lim: t_max,
            best: None,
            stamps: &mut [],
            stamp: 0,
            counters,
        };
        if self.unbounded.len() < ONE_BY_ONE_BELOW {
            for &r in self.unbounded.iter() {
                q.test(r);
            }
        } else {
            q.test_each(&self.unbounded);
        }
        if direct {
            q.counters.cell();
            if self.fours.is_empty() {
                q.test_each(&self.refs);
            } else {
                q.test_fours(&self.fours, &self.refs);
            }
        }
        let Some(dda) = dda else {
            return q.best;
        };
        if MB {
            q.stamp = scratch.begin(self.prims.len());
            q.stamps = &mut scratch.stamps;
        }
        let _ = self.walk_occupied(dda, &mut q);
        q.best
    }

    /// Where a query over `[t_min, t_max]` enters the grid: the walk's
    /// start, or for a direct grid whether the ray meets its box.
    #[inline(always)]
    fn enter(&self, ray: &Ray, pre: &SlabRay, t_min: Real, t_max: Real) -> (Option<Dda<'_>>, bool) {
        let g = &self.geom;
        if self.direct {
            (None, g.slab_hit(&g.entry, ray, pre, t_min, t_max).is_some())
        } else {
            (Dda::new_then(g, ray, pre, t_min, t_max, || ()), false)
        }
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
        // Ray data only for a ray with something to test (as in `closest`).
        let slab = SlabRay::new(ray);
        let (dda, direct) = self.enter(ray, &slab, t_min, t_max);
        if dda.is_none() && !direct && self.unbounded.is_empty() {
            return false;
        }
        let data = P::ray_data(ray);
        if !self.unbounded.is_empty() {
            counters.tests(self.unbounded.len());
            let (prims, shared) = (&*self.prims, &self.shared);
            let hit = if self.unbounded.len() < ONE_BY_ONE_BELOW {
                any_hits_each(prims, shared, &self.unbounded, ray, &data, t_min, t_max)
            } else {
                P::any_hits(prims, shared, &self.unbounded, ray, &data, t_min, t_max)
            };
            if hit {
                return true;
            }
        }
        if direct {
            counters.cell();
            counters.tests(self.refs.len());
            if !self.fours.is_empty() {
                return any_in_fours(
                    &self.prims,
                    &self.shared,
                    &self.fours,
                    &self.refs,
                    ray,
                    &data,
                    t_min,
                    t_max,
                );
            }
            return P::any_hits(
                &self.prims,
                &self.shared,
                &self.refs,
                ray,
                &data,
                t_min,
                t_max,
            );
        }
        let Some(dda) = dda else {
            return false;
        };
        let mut q = AnyHit::<P, C, MB> {
            prims: &self.prims,
            shared: &self.shared,
            refs: &self.refs,
            children: &self.nested.root,
            groups: Some(&self.groups),
            subs: &self.nested.subs,
            ray,
            slab,
            data: &data,
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
        self.walk_occupied(dda, &mut q).is_break()
    }

    /// Walks a query's cells with the walk that suits the grid: sparse
    /// grids skip empty space (by the distance map when they have one, else
    /// by empty blocks), dense ones walk every cell.
    #[inline(always)]
    fn walk_occupied<'a, F: CellFn<'a>>(
        &'a self,
        dda: Dda<'_>,
        q: &mut F,
    ) -> ControlFlow<F::Break> {
        if let (Cells::Dense { offsets }, false) = (&self.cells, self.far.is_empty()) {
            let l = DenseLookup::new(self.geom.dims, &self.occ, offsets, &self.refs);
            dda.walk_far(&l, self.geom.dims, &self.far, q)
        } else if self.skips() {
            with_lookup!(self, l => dda.walk_skip(&l, &self.blocks, q), ControlFlow::Continue(()))
        } else {
            with_lookup!(self, l => dda.walk(&l, q), ControlFlow::Continue(()))
        }
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

    fn shared(&self) -> &P::Shared {
        &self.shared
    }

    #[inline]
    fn primitive_id(&self, slot: u32) -> u32 {
        self.ids[slot as usize]
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

impl<P: Primitive> Grid<P> {
    /// The cell storage in use ([`GridConfig::storage`]).
    #[must_use]
    pub fn storage(&self) -> CellStorage {
        self.config.storage
    }
}

#[cfg(test)]
pub(crate) mod tests;
