//! The 3D-DDA of Amanatides & Woo (1987), "A fast voxel traversal algorithm
//! for ray tracing": from the cell where the ray enters the grid, step to the
//! neighbour across whichever cell plane the ray crosses first.
//!
//! Plane crossings are computed from the stored cell planes,
//! `t = (plane − origin) · inv_dir`, not by accumulating `Δt`: each crossing
//! carries the rounding of one subtraction and one product, however long
//! the walk, and insertion uses the very same planes.

use crate::geom::Geom;
use gridrt_bbox::math::{LaneChoice, Vec3Lanes};
use gridrt_bbox::{Ray, Real, SlabRay};
use std::ops::ControlFlow;

const INF: Real = Real::INFINITY;

/// The larger of two values, `b` when they are unordered (cheaper than
/// `Real::max`, whose NaN rule costs a few instructions in the hot loop).
#[inline(always)]
fn max(a: Real, b: Real) -> Real {
    if a > b {
        a
    } else {
        b
    }
}

/// One cell on a ray's path: its index and the parametric interval
/// `[t_enter, t_exit]` the ray spends in it (clipped to the query range).
///
/// Consecutive visits share their boundary: the `t_exit` of one is the
/// `t_enter` of the next, and `t_enter <= t_exit` always.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellVisit {
    /// The cell's `(i, j, k)`, each below the grid's cell count on that axis.
    pub index: [u32; 3],
    /// Where the ray enters the cell (or the query's `t_min`).
    pub t_enter: Real,
    /// Where the ray leaves the cell (or the query's `t_max`).
    pub t_exit: Real,
}

/// How the walk finds a cell's references: a key per cell that can be
/// stepped to a neighbour without recomputation (row-major index or Morton
/// code), and the lookup of a key's references.
pub(crate) trait CellLookup<'a> {
    /// The key of cell `idx`, and per-axis constants for stepping keys in
    /// the directions `neg`.
    fn start(&self, idx: [u32; 3], neg: [bool; 3]) -> (u64, [u64; 3]);
    /// The key of the neighbour across `axis` (in the walk's direction).
    fn step(st: &[u64; 3], key: u64, axis: usize) -> u64;
    /// The references of the cell with this key (empty if unoccupied).
    fn refs(&self, key: u64) -> &'a [u32];
    /// Whether the cell with this key holds references: one bit per key,
    /// far smaller than the cell table, so that empty cells cost no miss.
    fn occupied(&self, key: u64) -> bool;
}

/// What the walk does with each cell. A trait rather than a closure so that
/// the query bodies are always inlined into the walk's loop.
pub(crate) trait CellFn<'a> {
    /// The value a visit stops with.
    type Break;
    /// Visits one cell; `Break` ends the walk.
    fn call(&mut self, visit: CellVisit, refs: &'a [u32]) -> ControlFlow<Self::Break>;
}

/// [`Dda::walk_far`] leaves the cube of empty cells around an empty cell
/// only when the cell is farther than this from an occupied one: closer,
/// the cube's exit costs more than the one or two steps it saves.
const SKIP_FROM: u32 = 2;

/// Log2 of the edge, in cells, of the blocks that [`Dda::walk_skip`] skips when empty.
pub(crate) const MACRO_BITS: u32 = 3;

/// One bit per block of `2^MACRO_BITS` cells per axis: set when some cell
/// of the block holds a reference.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockMap {
    /// The grid's cells per axis.
    pub cells: [u32; 3],
    /// Blocks per axis.
    pub dims: [u32; 3],
    /// Occupancy bits, block `(i, j, k)` at bit `i + dims[0]·(j + dims[1]·k)`.
    pub bits: Box<[u64]>,
    /// Whether skipping pays: enough of the blocks are empty.
    pub useful: bool,
}

impl BlockMap {
    /// The map of a grid with `dims` cells, from its occupied cells.
    pub(crate) fn new(dims: [u32; 3], occupied: impl Iterator<Item = [u32; 3]>) -> Self {
        Self::with(dims, |bd, bits| {
            for c in occupied {
                let b = Self::linear(bd, c.map(|i| i >> MACRO_BITS));
                bits[b >> 6] |= 1 << (b & 63);
            }
        })
    }

    /// The map of a dense grid from its offsets (`offsets[c]..offsets[c + 1]`
    /// are cell `c`'s references, row-major). The offsets never decrease, so
    /// a run of cells is occupied exactly when the offsets at its two ends
    /// differ: one comparison per row of a block, none per cell.
    pub(crate) fn from_dense(dims: [u32; 3], offsets: &[u32]) -> Self {
        let [nx, ny, nz] = dims.map(|n| n as usize);
        let w = 1usize << MACRO_BITS;
        Self::with(dims, |bd, bits| {
            for k in 0..nz {
                for j in 0..ny {
                    let row = &offsets[(k * ny + j) * nx..][..=nx];
                    let first =
                        Self::linear(bd, [0, (j >> MACRO_BITS) as u32, (k >> MACRO_BITS) as u32]);
                    for (bi, x0) in (0..nx).step_by(w).enumerate() {
                        if row[x0] != row[(x0 + w).min(nx)] {
                            let b = first + bi;
                            bits[b >> 6] |= 1 << (b & 63);
                        }
                    }
                }
            }
        })
    }

    /// The map of a grid with `dims` cells whose bits `mark(block dims, bits)` sets.
    fn with(dims: [u32; 3], mark: impl FnOnce([u32; 3], &mut [u64])) -> Self {
        let bd = dims.map(|n| n.div_ceil(1 << MACRO_BITS));
        let count = bd.iter().map(|&n| n as usize).product::<usize>();
        let mut bits = vec![0u64; count.div_ceil(64)];
        mark(bd, &mut bits);
        let set: usize = bits.iter().map(|w| w.count_ones() as usize).sum();
        // Skipping costs a little per block crossed; it pays once a fair share is empty.
        let useful = count > 1 && set * 10 < count * 9;
        Self {
            cells: dims,
            dims: bd,
            bits: bits.into_boxed_slice(),
            useful,
        }
    }

    #[inline(always)]
    fn linear(bd: [u32; 3], b: [u32; 3]) -> usize {
        b[0] as usize + bd[0] as usize * (b[1] as usize + bd[1] as usize * b[2] as usize)
    }

    /// Whether block `b` holds a reference (`b` must be inside the map).
    #[inline(always)]
    pub(crate) fn occupied(&self, b: [u32; 3]) -> bool {
        let i = Self::linear(self.dims, b);
        debug_assert!(i >> 6 < self.bits.len());
        // SAFETY: the walk only asks for blocks of cells inside the grid.
        unsafe { self.bits.get_unchecked(i >> 6) >> (i & 63) & 1 != 0 }
    }

    /// Heap bytes.
    pub(crate) fn bytes(&self) -> usize {
        std::mem::size_of_val(&*self.bits)
    }
}

/// The walk's state between two steps.
#[derive(Clone, Debug)]
pub(crate) struct Dda<'g> {
    /// Per axis, the next plane in the walk's direction, in `Geom::walk`
    /// (whose ends are `∓∞` sentinels, so no bounds test is needed: past the
    /// last interior plane the crossing is `+∞`).
    next: [*const Real; 3],
    /// The start of each axis' walk planes.
    base: [*const Real; 3],
    /// `+1` or `−1`: how `next` and the index move along each axis.
    dir: [isize; 3],
    org: [Real; 3],
    inv: [Real; 3],
    pub idx: [u32; 3],
    /// Whether the walk goes down along each axis.
    pub neg: [bool; 3],
    /// The next plane crossing per axis, `+∞` if none.
    t_next: [Real; 3],
    t_enter: Real,
    t_end: Real,
    _geom: std::marker::PhantomData<&'g Geom>,
}

impl<'g> Dda<'g> {
    /// Starts a walk over `[t_min, t_max]`; `None` when the ray misses the
    /// grid in that range (or the range is empty or NaN).
    ///
    /// The entry point is found with the robust (conservative) `Aabb::hit`
    /// on the grid box widened by the insertion pad (or the textbook test
    /// when [`crate::GridConfig::slab`] asks for it). Its cell index is
    /// clamped to `[0, n − 1]`, so an entry exactly on the grid's max face
    /// starts in the last cell. An axis along which the ray does not move (a
    /// direction component of ±0, or one whose reciprocal overflows, such as
    /// a denormal) is never stepped: its next crossing is `+∞`, whatever the
    /// sign of the zero.
    #[inline(always)]
    pub(crate) fn new(g: &'g Geom, ray: &Ray, t_min: Real, t_max: Real) -> Option<Self> {
        Self::new_then(g, ray, &SlabRay::new(ray), t_min, t_max, || ())
    }

    /// [`Dda::new`] for the ray prepared as `pre`, calling `entered` once
    /// the ray is known to cross the
    /// grid's box, before the set-up reads the grid's planes: where a
    /// nested grid prefetches its arrays, so that the rays that miss its
    /// box (most, in a sparse scene) do not.
    #[inline(always)]
    pub(crate) fn new_then(
        g: &'g Geom,
        ray: &Ray,
        pre: &SlabRay,
        t_min: Real,
        t_max: Real,
        entered: impl FnOnce(),
    ) -> Option<Self> {
        if g.is_empty() || !(t_min <= t_max) {
            return None;
        }
        let (t0, t1) = g.slab_hit(&g.entry, ray, pre, t_min, t_max)?;
        entered();
        Some(Self::start_lanes(g, ray, t0, t1).unwrap_or_else(|| Self::start_exact(g, ray, t0, t1)))
    }

    /// The walk from the entry `t0` (to `t1`) of the three axes at once, in
    /// SIMD lanes: [`Dda::start_exact`]'s answer whenever its corrections
    /// have nothing to correct (the entry point lies in the cell of the
    /// guess from the cell size, and the ray does not cross that cell's
    /// entry-side plane after `t0`), else `None`. The same operations on
    /// the same operands as there, lane by lane, so the very same values.
    ///
    /// The walk planes stand for the cell planes in the tests: they differ
    /// only in the outer two, which are `∓∞` there, and those tests then
    /// hold or fail as the guards of [`Geom::cell_of`] and of the entry
    /// correction make them.
    #[inline(always)]
    fn start_lanes(g: &'g Geom, ray: &Ray, t0: Real, t1: Real) -> Option<Self> {
        let [min, inv_cell, last] = g.lanes;
        let (o, d, inv) = (
            Vec3Lanes::from(ray.origin),
            Vec3Lanes::from(ray.dir),
            Vec3Lanes::from(ray.inv_dir),
        );
        let moving = inv.is_finite_mask() & inv.cmpne(Vec3Lanes::ZERO);
        let p = Vec3Lanes::select(moving, o + d * t0, o);
        // `Geom::cell_of`'s guess: 0 for NaN and negatives, at most `last`.
        let f = (p - min) * inv_cell;
        let guess = Vec3Lanes::select(f.cmpgt(Vec3Lanes::ZERO), f.min_lt(last), Vec3Lanes::ZERO);
        // SAFETY: each lane is in `[0, dims − 1]` (below 2^31): finite and
        // in range of the conversion, which truncates as `as` does.
        let idx = guess
            .to_array()
            .map(|v| unsafe { v.to_int_unchecked::<i32>() } as u32);
        let base = [g.walk[0].as_ptr(), g.walk[1].as_ptr(), g.walk[2].as_ptr()];
        // SAFETY: `idx[a] <= dims[a] − 1`, and the walk planes have
        // `dims[a] + 1` entries.
        let (lo, hi) = unsafe {
            (
                Vec3Lanes::from_array(std::array::from_fn(|a| *base[a].add(idx[a] as usize))),
                Vec3Lanes::from_array(std::array::from_fn(|a| *base[a].add(idx[a] as usize + 1))),
            )
        };
        // The cell of `p` on every axis (as `cell_of` corrects it).
        if (p.cmplt(lo) | p.cmpge(hi)).any() {
            return None;
        }
        let walks = moving & last.cmpgt(Vec3Lanes::ZERO);
        let down = walks & inv.cmplt(Vec3Lanes::ZERO);
        // The entry-side plane, crossed after `t0`: the cell before.
        let entry_side = Vec3Lanes::select(down, hi, lo);
        if (walks & ((entry_side - o) * inv).cmpgt(Vec3Lanes::splat(t0))).any() {
            return None;
        }
        let t_next = Vec3Lanes::select(
            walks,
            (Vec3Lanes::select(down, lo, hi) - o) * inv,
            Vec3Lanes::INFINITY,
        );
        let (walks, down) = (walks.bitmask(), down.bitmask());
        let bit = |m: u32, a: usize| m >> a & 1 != 0;
        Some(Dda {
            // The plane after the cell (before it walking down); the first
            // for an axis not walked, as in `start_exact`. SAFETY: as above,
            // `idx[a] + 1 <= dims[a]`.
            next: std::array::from_fn(|a| unsafe {
                let k = idx[a] as usize + usize::from(!bit(down, a));
                base[a].add(if bit(walks, a) { k } else { 0 })
            }),
            base,
            dir: std::array::from_fn(|a| if bit(down, a) { -1 } else { 1 }),
            org: ray.origin.to_array(),
            inv: ray.inv_dir.to_array(),
            idx,
            neg: std::array::from_fn(|a| bit(down, a)),
            t_next: t_next.to_array(),
            t_enter: t0,
            t_end: if t1 < Real::MAX { t1 } else { Real::MAX },
            _geom: std::marker::PhantomData,
        })
    }

    /// The walk from the entry `t0` (to `t1`), one axis at a time: the
    /// entry cell from [`Geom::cell_of`], corrected for the rounding of the
    /// entry point.
    #[cold]
    fn start_exact(g: &'g Geom, ray: &Ray, t0: Real, t1: Real) -> Self {
        // Built in locals and assembled at the end, so that the walk's
        // state is written once into the caller's slot, not copied there.
        let base = [g.walk[0].as_ptr(), g.walk[1].as_ptr(), g.walk[2].as_ptr()];
        let (org, inv) = (ray.origin.to_array(), ray.inv_dir.to_array());
        let mut next = base;
        let mut dir = [1; 3];
        let mut idx = [0; 3];
        let mut neg = [false; 3];
        let mut t_next = [INF; 3];
        for a in 0..3 {
            let o = org[a];
            let inv = inv[a];
            let moving = inv.is_finite() && inv != 0.0;
            // A non-moving axis keeps the origin's coordinate (never 0·∞).
            let p = if moving { o + ray.dir[a] * t0 } else { o };
            let mut i = g.cell_of(a, p);
            if moving && g.dims[a] > 1 {
                // The sign of the reciprocal, not `dir >= 0`: −0.0 never gets here,
                // and a tiny negative component must walk down.
                let down = inv < 0.0;
                // The entry point carries the rounding of its coordinates
                // (an ulp of where the scene lies): if the ray crosses the
                // entry-side plane of the cell found after `t0`, in the
                // walk's own arithmetic, it starts in the cell before.
                let w = &g.walk[a];
                if down {
                    while i < g.dims[a] - 1 && (w[i as usize + 1] - o) * inv > t0 {
                        i += 1;
                    }
                } else {
                    while i > 0 && (w[i as usize] - o) * inv > t0 {
                        i -= 1;
                    }
                }
                neg[a] = down;
                dir[a] = if down { -1 } else { 1 };
                let k = i as usize + usize::from(!down);
                // `k <= n`: the walk planes have `n + 1` entries.
                next[a] = g.walk[a][k..].as_ptr();
                t_next[a] = (g.walk[a][k] - o) * inv;
            }
            idx[a] = i;
        }
        Dda {
            next,
            base,
            dir,
            org,
            inv,
            idx,
            neg,
            t_next,
            t_enter: t0,
            // Keep the end finite so that a `+∞` crossing never compares below it.
            t_end: if t1 < Real::MAX { t1 } else { Real::MAX },
            _geom: std::marker::PhantomData,
        }
    }

    /// The axis whose plane the ray crosses next, and the crossing.
    #[inline(always)]
    fn next_axis(&self) -> (usize, Real) {
        let [tx, ty, tz] = self.t_next;
        if tx < ty {
            if tx < tz {
                (0, tx)
            } else {
                (2, tz)
            }
        } else if ty < tz {
            (1, ty)
        } else {
            (2, tz)
        }
    }

    /// Moves to the neighbour across axis `a`'s next plane. Only called
    /// when that crossing is finite (an interior plane).
    #[inline(always)]
    fn advance(&mut self, a: usize) {
        self.idx[a] = self.idx[a].wrapping_add(self.dir[a] as u32);
        // SAFETY: a finite crossing comes from an interior plane, at index
        // 1..n of the n + 1 walk planes, so one step either way stays within
        // them (the sentinels at 0 and n are never stepped past).
        unsafe {
            self.next[a] = self.next[a].offset(self.dir[a]);
            self.t_next[a] = (*self.next[a] - self.org[a]) * self.inv[a];
        }
    }

    /// Visits the current cell and every following one until `f` breaks or
    /// the ray leaves the grid or the range: the hot loop of every query.
    /// The state lives in locals and each axis has its own constant-indexed
    /// step, so it stays in registers.
    #[inline(always)]
    pub(crate) fn walk<'a, C: CellLookup<'a>, F: CellFn<'a>>(
        self,
        cells: &C,
        f: &mut F,
    ) -> ControlFlow<F::Break> {
        let Dda {
            mut next,
            dir,
            org,
            inv,
            mut idx,
            neg,
            t_next,
            mut t_enter,
            t_end,
            ..
        } = self;
        let (mut key, st) = cells.start(idx, neg);
        let [mut tx, mut ty, mut tz] = t_next;
        macro_rules! step {
            ($a:literal, $t:ident) => {{
                idx[$a] = idx[$a].wrapping_add(dir[$a] as u32);
                key = C::step(&st, key, $a);
                // SAFETY: as in `advance`: the crossing was finite, so `next`
                // pointed at an interior plane and one step stays in bounds.
                unsafe {
                    next[$a] = next[$a].offset(dir[$a]);
                    $t = (*next[$a] - org[$a]) * inv[$a];
                }
            }};
        }
        loop {
            let (a, tn) = if tx < ty {
                if tx < tz {
                    (0, tx)
                } else {
                    (2, tz)
                }
            } else if ty < tz {
                (1, ty)
            } else {
                (2, tz)
            };
            let last_cell = !(tn <= t_end);
            let t_exit = max(if last_cell { t_end } else { tn }, t_enter);
            f.call(
                CellVisit {
                    index: idx,
                    t_enter,
                    t_exit,
                },
                cells.refs(key),
            )?;
            if last_cell {
                return ControlFlow::Continue(());
            }
            t_enter = t_exit;
            match a {
                0 => step!(0, tx),
                1 => step!(1, ty),
                _ => step!(2, tz),
            }
        }
    }

    /// [`Dda::walk`] for the queries, which need only the occupied cells.
    /// Two levels: across empty blocks of 2^[`MACRO_BITS`] cells per axis
    /// the walk steps block by block (one plane crossing per block instead
    /// of one per cell, and no cell lookups), which pays in sparse scenes (a
    /// mesh in a large box, a teapot in a stadium); inside occupied blocks
    /// it steps cell by cell and recognises empty cells by one bit. `f` sees
    /// every occupied cell, in order; the empty ones it does not see cannot
    /// change a query's answer since they hold nothing. (A visit's `t_enter`
    /// after a skipped stretch may be early; its `t_exit`, which the queries
    /// use, is exact.)
    #[inline(always)]
    pub(crate) fn walk_skip<'a, C: CellLookup<'a>, F: CellFn<'a>>(
        self,
        cells: &C,
        blocks: &BlockMap,
        f: &mut F,
    ) -> ControlFlow<F::Break> {
        let Dda {
            mut next,
            base,
            dir,
            org,
            inv,
            mut idx,
            neg,
            t_next,
            mut t_enter,
            t_end,
            ..
        } = self;
        let (mut key, st) = cells.start(idx, neg);
        let [mut tx, mut ty, mut tz] = t_next;
        let n = blocks.cells;
        let moving = [tx != INF, ty != INF, tz != INF];
        let mut blk = idx.map(|i| i >> MACRO_BITS);
        // Block level: the plane index of each axis' next block face and its crossing.
        let mut face = [0usize; 3];
        let mut bt = [INF; 3];
        macro_rules! step {
            ($a:literal, $t:ident) => {{
                idx[$a] = idx[$a].wrapping_add(dir[$a] as u32);
                key = C::step(&st, key, $a);
                // SAFETY: as in `advance`: the crossing was finite, so `next`
                // pointed at an interior plane and one step stays in bounds.
                unsafe {
                    next[$a] = next[$a].offset(dir[$a]);
                    $t = (*next[$a] - org[$a]) * inv[$a];
                }
            }};
        }
        // The crossing of plane `k` of axis `a`.
        macro_rules! plane_t {
            ($a:expr, $k:expr) => {{
                debug_assert!($k <= n[$a] as usize);
                // SAFETY: `k <= n`, and the walk planes have `n + 1` entries.
                (unsafe { *base[$a].add($k) } - org[$a]) * inv[$a]
            }};
        }
        // Enters block level from the current block (whose cells are skipped).
        macro_rules! to_blocks {
            () => {{
                for a in 0..3 {
                    if moving[a] {
                        face[a] = if neg[a] {
                            (blk[a] << MACRO_BITS) as usize
                        } else {
                            (((blk[a] + 1) << MACRO_BITS).min(n[a])) as usize
                        };
                        bt[a] = plane_t!(a, face[a]);
                    }
                }
            }};
        }
        // Steps axis `$a` across its planes crossed before `$tx`.
        macro_rules! catch_up {
            ($a:literal, $t:ident, $tx:expr) => {{
                while $t < $tx {
                    step!($a, $t);
                }
            }};
        }
        let mut fine = blocks.occupied(blk);
        if !fine {
            to_blocks!();
        }
        loop {
            if !fine {
                // Block by block until an occupied block (or the end of the ray).
                let t_x = loop {
                    let [bx, by, bz] = bt;
                    let (a, t) = if bx < by {
                        if bx < bz {
                            (0, bx)
                        } else {
                            (2, bz)
                        }
                    } else if by < bz {
                        (1, by)
                    } else {
                        (2, bz)
                    };
                    if !(t <= t_end) {
                        return ControlFlow::Continue(());
                    }
                    // A finite crossing is an interior face: the next block exists.
                    blk[a] = blk[a].wrapping_add(dir[a] as u32);
                    face[a] = if neg[a] {
                        face[a] - (1 << MACRO_BITS)
                    } else {
                        (face[a] + (1 << MACRO_BITS)).min(n[a] as usize)
                    };
                    bt[a] = plane_t!(a, face[a]);
                    if blocks.occupied(blk) {
                        break t;
                    }
                };
                // Down to cells: each moving axis starts at the block's first
                // cell along the walk and catches up to the crossing `t_x`.
                for a in 0..3 {
                    if moving[a] {
                        let first = blk[a] << MACRO_BITS;
                        let i = if neg[a] {
                            (first + (1 << MACRO_BITS) - 1).min(n[a] - 1)
                        } else {
                            first
                        };
                        idx[a] = i;
                        // SAFETY: `i + off <= n`: within the walk planes.
                        next[a] = unsafe { base[a].add(i as usize + usize::from(!neg[a])) };
                    }
                }
                if moving[0] {
                    tx = plane_t!(0, idx[0] as usize + usize::from(!neg[0]));
                }
                if moving[1] {
                    ty = plane_t!(1, idx[1] as usize + usize::from(!neg[1]));
                }
                if moving[2] {
                    tz = plane_t!(2, idx[2] as usize + usize::from(!neg[2]));
                }
                key = cells.start(idx, neg).0;
                catch_up!(0, tx, t_x);
                catch_up!(1, ty, t_x);
                catch_up!(2, tz, t_x);
                t_enter = max(t_x, t_enter);
                fine = true;
            }
            let (a, tn) = if tx < ty {
                if tx < tz {
                    (0, tx)
                } else {
                    (2, tz)
                }
            } else if ty < tz {
                (1, ty)
            } else {
                (2, tz)
            };
            let last_cell = !(tn <= t_end);
            let t_exit = max(if last_cell { t_end } else { tn }, t_enter);
            if cells.occupied(key) {
                f.call(
                    CellVisit {
                        index: idx,
                        t_enter,
                        t_exit,
                    },
                    cells.refs(key),
                )?;
            }
            if last_cell {
                return ControlFlow::Continue(());
            }
            t_enter = t_exit;
            let crossed = match a {
                0 => {
                    step!(0, tx);
                    idx[0] >> MACRO_BITS != blk[0]
                }
                1 => {
                    step!(1, ty);
                    idx[1] >> MACRO_BITS != blk[1]
                }
                _ => {
                    step!(2, tz);
                    idx[2] >> MACRO_BITS != blk[2]
                }
            };
            if crossed {
                blk = idx.map(|i| i >> MACRO_BITS);
                if !blocks.occupied(blk) {
                    to_blocks!();
                    fine = false;
                }
            }
        }
    }
}

impl Dda<'_> {
    /// [`Dda::walk`] for the queries over a dense grid of `dims` cells with
    /// a chessboard distance map `far` ([`crate::empty_space`]): `f` sees
    /// the occupied cells only, in order (told by their occupancy bit). In
    /// an empty cell `far` cells from the nearest occupied one, every cell
    /// within `far − 1` of it along each axis is empty, so when `far`
    /// exceeds [`SKIP_FROM`] the walk leaves that cube at once: it finds
    /// the first crossing of the cube's far faces and brings each axis up
    /// to it plane by plane (the walk's own crossings, so it lands in the
    /// cell the cell-by-cell walk would reach), with no cell looked up on
    /// the way. The skipped cells hold nothing, so the answers are those
    /// of [`Dda::walk`].
    #[inline(always)]
    pub(crate) fn walk_far<'a, C: CellLookup<'a>, F: CellFn<'a>>(
        self,
        cells: &C,
        dims: [u32; 3],
        far: &[u8],
        f: &mut F,
    ) -> ControlFlow<F::Break> {
        let Dda {
            mut next,
            base,
            dir,
            org,
            inv,
            mut idx,
            neg,
            t_next,
            mut t_enter,
            t_end,
            ..
        } = self;
        let (mut key, st) = cells.start(idx, neg);
        let [mut tx, mut ty, mut tz] = t_next;
        let moving = [tx != INF, ty != INF, tz != INF];
        macro_rules! step {
            ($a:literal, $t:ident) => {{
                idx[$a] = idx[$a].wrapping_add(dir[$a] as u32);
                key = C::step(&st, key, $a);
                // SAFETY: as in `advance`: the crossing was finite, so `next`
                // pointed at an interior plane and one step stays in bounds.
                unsafe {
                    next[$a] = next[$a].offset(dir[$a]);
                    $t = (*next[$a] - org[$a]) * inv[$a];
                }
            }};
        }
        loop {
            let occupied = cells.occupied(key);
            if !occupied {
                debug_assert!((key as usize) < far.len());
                // SAFETY: the walk's keys are cells of the grid, one entry each.
                let d = u32::from(unsafe { *far.get_unchecked(key as usize) });
                if d > SKIP_FROM {
                    // The cube of cells within `d − 1` is empty: its exit is
                    // the first crossing of its far faces (a face on the
                    // grid's boundary is a `±∞` sentinel plane, crossed at
                    // `+∞`).
                    let r = d - 1;
                    let mut t_x = INF;
                    for a in 0..3 {
                        if moving[a] {
                            let face = if neg[a] {
                                idx[a].saturating_sub(r)
                            } else {
                                idx[a].saturating_add(r + 1).min(dims[a])
                            };
                            // SAFETY: `face <= dims[a]`, and the walk planes
                            // have `dims[a] + 1` entries.
                            let p = unsafe { *base[a].add(face as usize) };
                            t_x = t_x.min((p - org[a]) * inv[a]);
                        }
                    }
                    if !(t_x <= t_end) {
                        return ControlFlow::Continue(());
                    }
                    // Every crossing before `t_x` is inside the cube.
                    while tx < t_x {
                        step!(0, tx);
                    }
                    while ty < t_x {
                        step!(1, ty);
                    }
                    while tz < t_x {
                        step!(2, tz);
                    }
                }
            }
            let (a, tn) = if tx < ty {
                if tx < tz {
                    (0, tx)
                } else {
                    (2, tz)
                }
            } else if ty < tz {
                (1, ty)
            } else {
                (2, tz)
            };
            let last_cell = !(tn <= t_end);
            let t_exit = max(if last_cell { t_end } else { tn }, t_enter);
            if occupied {
                f.call(
                    CellVisit {
                        index: idx,
                        t_enter,
                        t_exit,
                    },
                    cells.refs(key),
                )?;
            }
            if last_cell {
                return ControlFlow::Continue(());
            }
            t_enter = t_exit;
            match a {
                0 => step!(0, tx),
                1 => step!(1, ty),
                _ => step!(2, tz),
            }
        }
    }
}

/// The cells a ray passes through, in order: a non-allocating iterator over
/// [`CellVisit`]s, made by [`crate::Grid::cells_along`].
#[derive(Clone, Debug)]
pub struct CellIter<'g> {
    dda: Option<Dda<'g>>,
}

impl<'g> CellIter<'g> {
    pub(crate) fn new(dda: Option<Dda<'g>>) -> Self {
        Self { dda }
    }
}

impl Iterator for CellIter<'_> {
    type Item = CellVisit;

    #[inline]
    fn next(&mut self) -> Option<CellVisit> {
        let d = self.dda.as_mut()?;
        let (a, tn) = d.next_axis();
        let last = !(tn <= d.t_end);
        let t_exit = max(if last { d.t_end } else { tn }, d.t_enter);
        let visit = CellVisit {
            index: d.idx,
            t_enter: d.t_enter,
            t_exit,
        };
        if last {
            self.dda = None;
        } else {
            d.t_enter = t_exit;
            d.advance(a);
        }
        Some(visit)
    }
}

impl std::iter::FusedIterator for CellIter<'_> {}

// SAFETY: the walk's raw pointers point into the immutable (`Sync`) plane
// arrays of a grid borrowed for `'g`; nothing is written through them.
unsafe impl Send for Dda<'_> {}
// SAFETY: as above.
unsafe impl Sync for Dda<'_> {}

#[cfg(test)]
mod tests;
