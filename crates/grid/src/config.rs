use gridrt_bbox::{Real, SlabTest};
use std::time::Duration;

/// How the grid stores its cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CellStorage {
    /// Only occupied cells get space: an open-addressing hash table keyed by
    /// the Morton code of the cell's (i, j, k), as the lecture asks, with
    /// the references in one flat array in Morton order. Pays when most
    /// cells are empty.
    Hashed,
    /// One offset per cell, occupied or not (a CSR offset array of
    /// `cells + 1` entries over row-major cells). One load per cell visited,
    /// 4 bytes per cell.
    #[default]
    Dense,
}

/// Parameters of a grid build.
///
/// # Resolution
///
/// With `n` primitives in a grid box of extents `w_x, w_y, w_z`, the lecture's
/// formula gives the cell size `s = cbrt(w_x·w_y·w_z / n)` and
/// `n_a = floor(m·w_a / s) + 1` cells along axis `a` (about `m³` cells per
/// primitive). An axis of zero extent, or one thin enough to get one cell
/// anyway, is left out of `s` (`s = sqrt(w_x·w_y / n)` for a flat scene), so
/// flat scenes are not cut into millions of slivers; a single point gets one
/// cell. The cell count is then capped:
///
/// - at most [`GridConfig::max_cells`] cells (itself clamped to `1..=2³¹`):
///   past it, every `n_a` is scaled down by the same factor;
/// - at most `2²¹` cells per axis (21-bit Morton coordinates);
/// - at most `max(4·max_cells, 64·n)` references (and below `2³¹`): if huge
///   primitives over a fine grid would need more, the resolution is halved
///   until they fit.
///
/// # Defaults
///
/// Chosen by measurement (build plus one 400×400 trace of Suffern's random
/// spheres for N = 10⁴…10⁶ and of a 1,024,000-triangle mesh; see the
/// crate's README): `m = 0.75` (about 0.4 cells per primitive, where the
/// lecture's `m = 2` gives about 8: cells are what the walk pays for, the
/// build's memory and time grow with m³, and primitives that test four at
/// a time through [`crate::Primitive::closest_hits`] make a cell's
/// several references cheap), [`CellStorage::Dense`] (the hashed
/// table is smaller for sparse scenes but every lookup probes a random
/// slot), box insertion (exact insertion drops about a tenth of the tests
/// on a triangle mesh, gains no trace time and makes the build ten times
/// slower) and no mailbox (it saves a third of
/// the tests but its stamp array costs about as much as it saves). The
/// lecture's `m = 2` stays one field away:
///
/// ```
/// use gridrt_grid::GridConfig;
/// let lecture = GridConfig { m: 2.0, ..GridConfig::default() };
/// assert_eq!(lecture.m, 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridConfig {
    /// The lecture's multiplier `m`: about `m³` cells per primitive. Values
    /// that are not finite and positive are treated as the lecture's 2.
    pub m: Real,
    /// Sparse hashed cells or a dense table.
    pub storage: CellStorage,
    /// Ask each primitive whether it really touches a cell
    /// ([`crate::Primitive::overlaps_box`], given the cell's box widened by
    /// a few ulps) instead of inserting it into every cell its bounding box
    /// overlaps. Fewer references, slower build.
    pub exact_insertion: bool,
    /// Skip primitives already tested by the same ray (mailboxing, with
    /// per-ray ids in the caller's [`crate::GridScratch`]).
    pub mailbox: bool,
    /// The most cells a grid may have; the resolution is scaled down
    /// uniformly to stay below it, so memory stays bounded. Clamped to
    /// `1..=2³¹`.
    pub max_cells: u64,
    /// Build in parallel (needs the `rayon` feature; ignored without it).
    pub parallel_build: bool,
    /// Explicit cells per axis, overriding `m` (zeros count as one; the caps
    /// still apply). For tests and experiments.
    pub dims: Option<[u32; 3]>,
    /// Cells with at least this many references get a nested grid of their
    /// own, which `closest_hit` and `any_hit` walk instead of testing every
    /// reference (the remedy for a detailed object in a large empty scene);
    /// 0 turns nesting off.
    pub nest_min_refs: u32,
    /// The multiplier `m` of the nested grids (about `m³` nested cells per
    /// reference of the crowded cell); `None`: the same as [`Self::m`].
    /// A coarse outer grid, so that a detailed object falls into few
    /// cells, with finer nested grids, so that a ray tests few of its
    /// triangles, can pay (the crate README measures it on a mesh).
    /// Values that are not finite and positive are treated as the
    /// lecture's 2.
    pub nest_m: Option<Real>,
    /// Let the build decide, cell by cell, from the flat grid it has
    /// built, which cells get nested grids (the default): when
    /// [`Self::nest_min_refs`] is 0, each cell of at least
    /// [`crate::cost::min_refs`] references gets one only where the cost
    /// model of [`crate::cost`] expects a ray crossing the cell to pay less
    /// with it (the same rule one level down, recursively; see the crate
    /// README for the rule and the measurements behind it). An explicit
    /// `nest_min_refs` wins and nests every cell it admits; `auto: false`
    /// with `nest_min_refs: 0` is the flat grid.
    pub auto: bool,
    /// The most bytes the grid's index may take ([`GridStats::bytes`]):
    /// cells, references, slot ids, maps and nested grids. `None`: [`DEFAULT_BUDGET_FACTOR`]
    /// times the primitives' own size (`n · size_of::<P>()`), and at least
    /// [`MIN_BUDGET`]. The flat grid's cells and references are capped to
    /// fit it, and the nested grids take only what is left: reaching the
    /// budget stops subdividing, never fails. A budget below what one
    /// reference per primitive needs (a single cell) is raised to that.
    pub memory_budget: Option<usize>,
    /// The ray–box test that decides where a ray enters the grid (and each
    /// nested grid): [`SlabTest::Robust`] (the default) or the textbook
    /// test, which can cull a ray lying in a face of the grid's box (an
    /// origin on the plane and a zero direction component give
    /// `0·∞ = NaN`). The textbook test is there to measure what the robust
    /// one costs.
    pub slab: SlabTest,
    /// Keep the boxes of groups of four references in the flat grid's
    /// cells of at least 12 without a nested grid (sorted along a Morton
    /// curve first), so that a ray tests only the groups it meets (the
    /// default; the crate README measures it). Within the memory budget:
    /// a grid that would exceed it keeps none.
    pub cell_groups: bool,
    /// Keep a few primitives far larger than the rest (a ground under a
    /// model) out of the cells, tested by every query like unbounded ones,
    /// so that the grid spans the rest only (the default; the crate README
    /// gives the rule). Off, every finite box is gridded.
    pub set_aside_outsized: bool,
}

/// The `nest_min_refs` of the hierarchy that nests every crowded cell
/// (the CLI's `--accel hierarchy`), beside [`GridConfig::auto`]'s
/// cell-by-cell choice.
pub const HIERARCHY_MIN_REFS: u32 = 48;

/// [`GridConfig::auto`]: a scene of at most this many primitives gets no
/// cells; every ray tests them all, four at a time where the primitive
/// can. Below it, entering a grid's box and walking its cells cost more
/// than the tests they save (measured in the crate README).
pub const AUTO_DIRECT_MAX: usize = 40;

/// The default memory budget, in units of the primitives' own size.
pub const DEFAULT_BUDGET_FACTOR: usize = 8;

/// The smallest default memory budget (4 MiB), so that small scenes are
/// never starved.
pub const MIN_BUDGET: usize = 4 << 20;

impl GridConfig {
    /// Whether a grid over `n` primitives built with this configuration
    /// tests them all directly ([`AUTO_DIRECT_MAX`]): `auto`, with neither
    /// nesting, the cells per axis nor the mailbox set.
    #[must_use]
    pub fn direct(&self, n: usize) -> bool {
        self.auto
            && self.nest_min_refs == 0
            && self.dims.is_none()
            && !self.mailbox
            && n <= AUTO_DIRECT_MAX
    }

    /// The memory budget for `n` primitives of `prim_size` bytes each
    /// ([`GridConfig::memory_budget`]), before the floor of one reference
    /// per primitive.
    #[must_use]
    pub fn budget_for(&self, n: usize, prim_size: usize) -> usize {
        self.memory_budget.unwrap_or_else(|| {
            n.saturating_mul(prim_size)
                .saturating_mul(DEFAULT_BUDGET_FACTOR)
                .max(MIN_BUDGET)
        })
    }
}

/// What a built grid looks like, for reports and tests.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridStats {
    /// Cells per axis.
    pub dims: [u32; 3],
    /// `dims[0]·dims[1]·dims[2]`.
    pub cells: u64,
    /// Cells holding at least one reference.
    pub occupied_cells: u64,
    /// Primitive references over all cells.
    pub references: u64,
    /// `references / occupied_cells` (0 for an empty grid).
    pub mean_refs_per_occupied: f64,
    /// The most references in one cell.
    pub max_refs_per_cell: u32,
    /// Heap bytes held by the grid's tables (not the primitives).
    pub bytes: usize,
    /// Of `bytes`, the cell table alone (dense offsets or hash slots).
    pub table_bytes: usize,
    /// Primitives kept outside the cells and tested by every query: those
    /// whose box is not finite, and outsized ones (see the crate README).
    pub unbounded_prims: u64,
    /// Nested grids in all, over every level ([`GridConfig::nest_min_refs`]).
    pub nested_cells: u64,
    /// The deepest level of nested grids (0: the flat grid alone).
    pub nest_levels: u32,
    /// The nested grids level by level, the ones in the flat grid's cells
    /// first (empty without nesting): how many grids, cells and
    /// references each level holds, which shows where the hierarchy stopped
    /// separating the primitives.
    pub levels: Vec<NestLevel>,
    /// Cells of the flat grid whose references are tested by groups of
    /// four with a box each ([`GridConfig::cell_groups`]).
    pub grouped_cells: u64,
    /// The `nest_min_refs` the build used (given, or with
    /// [`GridConfig::auto`] the cost model's [`crate::cost::min_refs`];
    /// 0: no nesting).
    pub nest_min_refs: u32,
    /// The memory budget the build kept to ([`GridConfig::memory_budget`]).
    pub budget: usize,
    /// Wall-clock time of the build.
    pub build_time: Duration,
}

/// The nested grids of one level of the hierarchy, summed
/// ([`GridStats::levels`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NestLevel {
    /// Nested grids at this level.
    pub grids: u64,
    /// Their cells.
    pub cells: u64,
    /// Their cells holding at least one reference.
    pub occupied_cells: u64,
    /// Their references over all cells.
    pub references: u64,
    /// References tested on entering a grid instead (a floor or a wall
    /// spanning most of the parent cell).
    pub direct_refs: u64,
    /// The most references in one cell of the level.
    pub max_refs_per_cell: u32,
    /// Wide grids beside the level's grids: the same references with
    /// wider pads (a chain per grid, up to the parent's pad), walked by
    /// rays from too far for a grid's own pad.
    pub wide_grids: u64,
    /// Their references.
    pub wide_references: u64,
}

impl Default for GridConfig {
    fn default() -> Self {
        Self {
            m: 0.75,
            storage: CellStorage::Dense,
            exact_insertion: false,
            mailbox: false,
            max_cells: 1 << 26,
            parallel_build: true,
            dims: None,
            nest_min_refs: 0,
            nest_m: None,
            auto: true,
            memory_budget: None,
            slab: SlabTest::Robust,
            cell_groups: true,
            set_aside_outsized: true,
        }
    }
}
