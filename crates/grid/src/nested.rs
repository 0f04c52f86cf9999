//! Nested grids in crowded cells, recursively: the remedy for the "teapot
//! in a stadium" (a small, detailed object in a large, mostly empty scene),
//! after Ize, Shirley & Parker (2007) and the two-level grids of Kalojanov,
//! Billeter & Slusallek (2011). The grid's resolution follows the whole
//! scene, so the cells around a detailed object hold hundreds or thousands
//! of primitives. A cell with at least `min_refs` references gets a dense
//! grid of its own (with [`crate::GridConfig::auto`], only where the cost
//! model of [`crate::cost`] says it pays), over the **tight** box of its
//! references clipped to the cell, with a resolution from the cell's own
//! reference count (the lecture's formula, about `m³` cells per
//! reference); its crowded cells get grids of their own in turn.
//!
//! **Stopping rule.** A nested cell is subdivided again only if (1) it
//! holds at least `min_refs` references, (2) at most [`PROGRESS`] of its
//! parent cell's, or else they cover at most [`SHRINK`] of its area (a
//! subdivision that neither separated them nor shrank the space around
//! them, as around the common vertex of a fan or in a stack of coincident
//! triangles, is not repeated), (3) the depth is below [`MAX_DEPTH`], and
//! (4) the memory budget has taken every grid planned before it: the first
//! nested grid the budget cannot take ends the build (planning the rest,
//! as a scene of many detailed objects would ask, would cost more build
//! time than the grids built); a plan whose references alone would not
//! fit in what is left of the budget is refused (as one that does not
//! pay) before its cells are counted, a step per reference and cell it
//! covers (billions around the common vertex of a fan of 10⁵ triangles).
//! A grid is not built at all when its cells would hold on average more
//! than [`SEPARATION`] of the references (nothing separates them: walking
//! it would cost more than testing them), or when
//! more than [`MAX_HEAVY`] of its cells would each hold more than
//! [`PROGRESS`] of them (an unseparated core, as around the common vertex
//! of a fan: a ray crossing two such cells would test more than the cell
//! holds, and more than the exhaustive baseline on a scene of one fan). Every
//! rule only ever stops subdividing: a cell without a nested grid tests its
//! references, so the answers never depend on where the recursion ended.
//!
//! **Build**, breadth first and deterministic: each level's candidates are
//! planned in parallel (box, resolution, reference count per nested cell),
//! granted in order against the budget until one does not fit (whatever
//! the thread count, the same grids are built), then filled in parallel.
//! All nested grids live in one arena; the children of one grid are
//! contiguous in it and found from the start of the parent cell's run of
//! references by one popcount.
//!
//! **The pad follows the grid**, not the scene. The rounding a pad must
//! cover grows with the distance from the ray's origin to what it meets
//! ([`geom::RAY_ULPS`]), so the outermost grid's pad, which covers rays
//! from anywhere in a scene thousands of times larger than a detailed
//! object, would be as wide as the object's nested cells and put each
//! primitive in the cells around its own. A nested grid's pad is a
//! sixteenth of its cells' width ([`PAD_CELLS`]), no less than the
//! outermost rule applied to its references' own box, in a cell of at
//! most [`CHEAP_REFS`] references no less than an eighth of its parent's
//! ([`PAD_STEP`]), and the parent's own when it would be more than half of
//! it ([`PAD_SNAP`]). A grid with its parent's pad covers every ray its
//! parent does; a narrower pad covers the rays from within its [`Reach`].
//! A ray from farther away tests the parent cell's references instead of
//! walking it, or, in a cell of more than [`CHEAP_REFS`] references,
//! walks the first of the cell's chain of wide grids that covers it
//! ([`Sub::wide`]): the same references, each grid with a pad
//! [`WIDE_STEP`] times the previous one's up to the parent's, in cells at
//! least [`WIDE_CELL_PADS`] pads wide. The chain ends where the box fits
//! in one cell of the next pad: a ray beyond every reach tests the cell's
//! references only if it meets the nested grid's box widened by the
//! parent's pad ([`Sub::outer`]), which holds every hit of them in the
//! cell. Exact either way; so rays near a detailed object walk cells
//! fitted to it, a telephoto view of it from far outside the scene walks
//! coarser cells instead of testing the whole object, and a far ray that
//! crosses the cell beside the object tests none of it.
//!
//! **Correctness** is the outer grid's argument one level down. A nested
//! grid spans every point of its cell that lies in one of its references'
//! padded boxes, so every hit inside the cell; its pad covers the rays
//! that walk it; every reference is in every nested cell its padded box
//! overlaps; and the nested walk stops under the outer walk's rule. So it
//! finds the nearest hit inside the cell, ties included.

mod check;
#[cfg(test)]
mod tests;

use crate::cells::dense_occupancy;
use crate::cost;
use crate::geom::{self, Geom, Reach, PAD_ULPS};
use crate::groups::GROUP_MIN_REFS;
use crate::par::map_indices;
use crate::{NestLevel, Primitive};
use gridrt_bbox::{Aabb, Ray, Real, SlabRay};
use std::borrow::Cow;

/// Most cells of one nested grid.
pub(crate) const MAX_SUB_CELLS: u64 = 1 << 16;

/// Most levels of nested grids below the flat grid.
pub(crate) const MAX_DEPTH: u32 = 4;

/// A nested cell is subdivided again only if it holds at most this
/// fraction of its parent cell's references.
pub(crate) const PROGRESS: f64 = 0.5;

/// A nested cell holding more than [`PROGRESS`] of its parent cell's
/// references is subdivided again only if they cover at most this fraction
/// of its area: a small, detailed object that the parent grid, stretched
/// over a large cell, left in one of its cells (the references did not
/// separate, but the space around them shrank).
pub(crate) const SHRINK: f64 = 0.25;

/// A nested grid's pad, as a fraction of its narrowest cell width.
pub(crate) const PAD_CELLS: Real = 1.0 / 16.0;

/// A nested grid's pad is at least its parent's divided by this when its
/// cell holds at most [`CHEAP_REFS`] references.
pub(crate) const PAD_STEP: Real = 8.0;

/// A ray from beyond a nested grid's reach tests the cell's references
/// instead of walking it (if it meets [`Sub::outer`]) when they are at
/// most this many; a more crowded
/// cell keeps wide grids for such rays ([`Sub::wide`]), and its nested
/// grid's pad has no floor but its own references' ([`pad_of`]).
pub(crate) const CHEAP_REFS: usize = 512;

/// A pad within this factor of the parent's is the parent's: the grid
/// then covers every ray its parent does, at the cost of a slightly wider
/// pad, where a slightly narrower one would leave far rays a wide grid
/// nearly as large as itself.
pub(crate) const PAD_SNAP: Real = 2.0;

/// A crowded cell whose nested grid's pad is narrower than its parent's
/// also gets a chain of wide grids for the rays from beyond the nested
/// grid's reach, each with cells at least this many pads wide ...
pub(crate) const WIDE_CELL_PADS: Real = 4.0;

/// ... and a pad this many times the previous one's, up to the parent's
/// (the last, which covers every ray).
pub(crate) const WIDE_STEP: Real = 2.0;

/// A nested grid is built only if its occupied cells hold on average at
/// most this fraction of the parent cell's references.
pub(crate) const SEPARATION: f64 = 0.75;

/// A nested grid is built only if at most this many of its cells hold more
/// than [`PROGRESS`] of the parent cell's references: where references
/// never separate (the spokes of a fan around their common vertex, a stack
/// of coincident triangles straddling a cell plane), several cells would
/// each hold nearly all of them, and a ray crossing two of them would test
/// more primitives than the cell holds.
pub(crate) const MAX_HEAVY: usize = 1;

/// References whose nested grids are planned and filled together (the
/// plans of one batch hold a cell range for each).
const BATCH_REFS: usize = 1 << 16;

/// How the hierarchy is built.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NestParams {
    /// Cells with fewer references get no nested grid.
    pub min_refs: usize,
    /// The nested grids' multiplier (about `m³` cells per reference).
    pub m: f64,
    /// Bytes the nested grids may take in all.
    pub budget: usize,
    pub parallel: bool,
    /// The slab test of the walk's entry ([`crate::GridConfig::slab`]).
    pub slab: gridrt_bbox::SlabTest,
    /// Build a nested grid only where the cost model expects it to pay
    /// ([`crate::GridConfig::auto`], [`crate::cost`]).
    pub cost: bool,
    /// The outermost grid's crowded cells left flat get group boxes
    /// ([`crate::GridConfig::cell_groups`]): the cost model weighs those.
    pub groups: bool,
}

/// The nested grid of one crowded cell.
#[derive(Clone, Debug)]
pub(crate) struct Sub {
    /// Where the cell's run starts in its parent grid's references: the key
    /// the walk finds the nested grid by.
    pub start: u32,
    pub geom: Geom,
    /// The rays its pad covers.
    pub reach: Reach,
    /// Its box widened by its parent's pad (rounded outwards): every hit
    /// in the parent's cell of the references it holds lies in it, for
    /// the rays the parent covers. A ray beyond the reach of the whole
    /// chain of wide grids tests those references only if it meets it.
    pub outer: Aabb,
    /// The hull of `outer` and of the entry box of every grid of the chain
    /// ([`cull_box`]): a ray that misses it finds nothing in the cell but
    /// the `direct` references ([`Sub::misses`]).
    pub cull: Aabb,
    /// `offsets[c]..offsets[c + 1]` are nested cell `c`'s references
    /// (row-major), indices of the outer grid's primitives.
    pub offsets: Box<[u32]>,
    pub refs: Box<[u32]>,
    /// The cell's references that span most of it (a floor under a
    /// detailed object, a wall): tested on entering the cell, and left
    /// out of the nested grid, which then spans only the others.
    pub direct: Box<[u32]>,
    /// One bit per nested cell: set when it holds references.
    pub occ: Box<[u64]>,
    /// The nested grids of this grid's own crowded cells.
    pub children: Children,
    /// 1 for a grid nested in the flat grid's cell, 2 one level down, …
    pub depth: u32,
    /// The same references in coarser cells with a [`WIDE_STEP`] times
    /// wider pad, for the rays beyond `reach` (none where the cell holds at
    /// most [`CHEAP_REFS`] references, which such a ray tests instead, or
    /// the pad is the parent's). It has no children, and a wide grid of its
    /// own until the pad is the parent's: a chain of reaches, so that a ray
    /// walks the finest grid whose pad covers it.
    pub wide: Option<Box<Sub>>,
}

impl Sub {
    /// The grid a ray walks in this one's cell: the first of this one and
    /// its chain of wide grids whose pad covers the ray, if any.
    #[inline(always)]
    pub(crate) fn for_ray(&self, ray: &gridrt_bbox::Ray) -> Option<&Sub> {
        let mut s = self;
        while !s.reach.covers(ray.origin) {
            s = s.wide.as_deref()?;
        }
        Some(s)
    }

    /// Whether a ray over `[t_min, t_max]` certainly finds nothing in its
    /// cell: it has no direct references and the ray misses [`Sub::cull`].
    /// The robust slab test of a box inside another misses whenever the
    /// other's does (its crossings round monotonically), so every path of
    /// the walk would end at its first box test; deciding it before the
    /// walk's call spares a ray passing beside a small detailed object in a
    /// large cell the call and the choice of a grid in the chain.
    #[inline(always)]
    pub(crate) fn misses(&self, ray: &Ray, pre: &SlabRay, t_min: Real, t_max: Real) -> bool {
        self.direct.is_empty()
            && self
                .geom
                .slab_hit(&self.cull, ray, pre, t_min, t_max)
                .is_none()
    }

    /// The references of its cell `refs` that a ray beyond the reach of
    /// every grid of the chain ([`Sub::for_ray`] is `None`) tests over
    /// `[t_min, t_max]`: all of them if it meets [`Sub::outer`], else only
    /// those tested on entry, which lie outside that box.
    #[inline(always)]
    pub(crate) fn far_refs<'r>(
        &'r self,
        refs: &'r [u32],
        ray: &Ray,
        pre: &SlabRay,
        t_min: Real,
        t_max: Real,
    ) -> &'r [u32] {
        match self.geom.slab_hit(&self.outer, ray, pre, t_min, t_max) {
            Some(_) => refs,
            None => &self.direct,
        }
    }

    /// Its chain of wide grids, finest first.
    pub(crate) fn wide_grids(&self) -> impl Iterator<Item = &Sub> {
        std::iter::successors(self.wide.as_deref(), |w| w.wide.as_deref())
    }

    /// Heap bytes of this grid and of its chain of wide grids.
    fn bytes(&self) -> usize {
        std::mem::size_of::<Sub>()
            + std::mem::size_of_val(&*self.offsets)
            + std::mem::size_of_val(&*self.refs)
            + std::mem::size_of_val(&*self.direct)
            + std::mem::size_of_val(&*self.occ)
            + self.children.bytes()
            + self.geom.planes_bytes()
            + self.wide.as_ref().map_or(0, |w| w.bytes())
    }
}

/// Which cells of one grid (the flat grid or a nested one) have a nested
/// grid, and where those are in the arena ([`Nested::subs`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct Children {
    /// One bit per index of the grid's references, set where the run of a
    /// cell with a nested grid starts.
    starts: Box<[u64]>,
    /// `rank[w]`: the set bits of `starts[..w]`.
    rank: Box<[u32]>,
    /// The arena index of the first child (the children are contiguous,
    /// in the order of their starts).
    base: u32,
    /// Cells with fewer references have none (0 with no children: the
    /// empty bitmap answers).
    min_refs: usize,
}

impl Children {
    /// The map of children starting at `starts` (ascending) in a grid of
    /// `refs` references, the first at arena index `base`.
    pub(crate) fn new(refs: usize, starts: &[u32], base: usize, min_refs: usize) -> Self {
        if starts.is_empty() {
            return Self::default();
        }
        let mut bits = vec![0u64; refs.div_ceil(64)];
        for &s in starts {
            bits[s as usize >> 6] |= 1 << (s & 63);
        }
        let rank = bits
            .iter()
            .scan(0u32, |n, w| {
                let r = *n;
                *n += w.count_ones();
                Some(r)
            })
            .collect();
        Self {
            starts: bits.into_boxed_slice(),
            rank,
            base: base as u32,
            min_refs,
        }
    }

    /// The arena index of the nested grid of the cell whose run of `len`
    /// references starts at `start`, if it has one.
    #[inline(always)]
    pub(crate) fn find(&self, len: usize, start: u32) -> Option<usize> {
        if len < self.min_refs {
            return None;
        }
        let w = start as usize >> 6;
        let bits = *self.starts.get(w)?;
        // The bits up to and including the start's own.
        let below = bits & (u64::MAX >> (63 - (start & 63)));
        if below >> (start & 63) == 0 {
            return None;
        }
        Some(self.base as usize + self.rank[w] as usize + below.count_ones() as usize - 1)
    }

    /// Whether no cell has a nested grid.
    pub(crate) fn is_empty(&self) -> bool {
        self.starts.is_empty()
    }

    /// Heap bytes of a map over `refs` references.
    pub(crate) fn bytes_for(refs: usize) -> usize {
        refs.div_ceil(64) * (8 + 4)
    }

    /// Heap bytes.
    pub(crate) fn bytes(&self) -> usize {
        std::mem::size_of_val(&*self.starts) + std::mem::size_of_val(&*self.rank)
    }
}

/// All nested grids of a grid.
#[derive(Clone, Debug, Default)]
pub(crate) struct Nested {
    /// The flat grid's cells with a nested grid.
    pub root: Children,
    /// Every nested grid, level by level.
    pub subs: Box<[Sub]>,
}

/// An inclusive range of cells per axis, as [`Geom::cell_range`] gives it.
type CellRange = ([u32; 3], [u32; 3]);

/// Cells of a grid as `(index, start, references)`: where each one's run
/// of references starts, and the run.
type CellRuns<'r> = Vec<([u32; 3], u32, &'r [u32])>;

/// A nested grid's offsets per cell and its references' cell ranges.
type Layout = (Vec<u32>, Vec<(u32, CellRange)>);

/// A crowded cell waiting for its nested grid.
struct Candidate {
    /// The arena index of the grid holding the cell (`None`: the flat grid).
    parent: Option<usize>,
    idx: [u32; 3],
    start: u32,
    len: u32,
    depth: u32,
    /// More than [`PROGRESS`] of its parent cell's references: nested only
    /// if they cover at most [`SHRINK`] of the cell's area.
    must_shrink: bool,
}

/// A nested grid planned but not filled: its geometry, its counted
/// offsets and each reference's cell range.
struct Plan {
    geom: Geom,
    reach: Reach,
    /// [`Sub::outer`].
    outer: Aabb,
    offsets: Vec<u32>,
    /// The references in the nested grid, each with its cell range.
    ranges: Vec<(u32, CellRange)>,
    direct: Vec<u32>,
    /// The plan of its first wide grid ([`Sub::wide`]), holding the next.
    wide: Option<Box<Plan>>,
}

impl Plan {
    /// Heap bytes of the nested grid this plan fills (its map of children
    /// counted as if it had some).
    fn bytes(&self) -> usize {
        let refs = *self.offsets.last().unwrap_or(&0) as usize;
        std::mem::size_of::<Sub>()
            + 4 * self.offsets.len()
            + 4 * refs
            + 4 * self.direct.len()
            + 8 * (self.offsets.len() - 1).div_ceil(64)
            + self.geom.planes_bytes()
            + Children::bytes_for(refs)
            + self.wide.as_ref().map_or(0, |w| w.bytes())
    }
}

impl Nested {
    /// The nested grids of a grid with geometry `root` and references
    /// `root_refs`, for its crowded cells `(index, start, references)`
    /// (those with at least `p.min_refs` references, in any order).
    pub(crate) fn build<P: Primitive>(
        prims: &[P],
        shared: &P::Shared,
        root: &Geom,
        root_refs: &[u32],
        crowded: Vec<([u32; 3], u32, &[u32])>,
        p: &NestParams,
    ) -> Self {
        let mut used = Children::bytes_for(root_refs.len());
        if crowded.is_empty() || p.min_refs == 0 || used > p.budget {
            return Self::default();
        }
        let mut cands: Vec<Candidate> = crowded
            .iter()
            .map(|&(idx, start, refs)| Candidate {
                parent: None,
                idx,
                start,
                len: refs.len() as u32,
                depth: 1,
                must_shrink: false,
            })
            .collect();
        cands.sort_unstable_by_key(|c| c.start);
        let mut subs: Vec<Sub> = Vec::new();
        let mut root_children = Children::default();
        // The first nested grid the budget cannot take ends the build.
        let mut full = false;
        while !cands.is_empty() {
            let refs_of = |c: &Candidate| -> (&Geom, &[u32]) {
                let (g, all) = match c.parent {
                    None => (root, root_refs),
                    Some(s) => (&subs[s].geom, &subs[s].refs[..]),
                };
                (g, &all[c.start as usize..][..c.len as usize])
            };
            // Planned and filled a batch at a time: a plan holds a cell
            // range per reference (28 bytes), so the plans of a whole
            // level at once would take more than the grids they fill
            // (30 MB beside the dragon's 20 MB of nested grids).
            let mut granted: Vec<usize> = Vec::new();
            let mut filled: Vec<Sub> = Vec::new();
            let mut b0 = 0;
            while b0 < cands.len() {
                let mut b1 = b0;
                let mut refs = 0usize;
                while b1 < cands.len() && (b1 == b0 || refs < BATCH_REFS) {
                    refs += cands[b1].len as usize;
                    b1 += 1;
                }
                let room = p.budget - used;
                let plans = map_indices(b1 - b0, p.parallel, |i| {
                    let c = &cands[b0 + i];
                    let (g, refs) = refs_of(c);
                    plan(prims, shared, g, c, refs, p, room)
                });
                // Granted in order, so the same grids are built whatever
                // the threads and the batches.
                let mut ok: Vec<(usize, Plan)> = Vec::new();
                for (i, plan) in (b0..).zip(plans) {
                    let Some(plan) = plan else { continue };
                    let bytes = plan.bytes();
                    if used + bytes > p.budget {
                        full = true;
                        break;
                    }
                    used += bytes;
                    ok.push((i, plan));
                }
                filled.extend(map_indices(ok.len(), p.parallel, |k| {
                    let (i, plan) = &ok[k];
                    let c = &cands[*i];
                    fill(plan, c.start, c.depth)
                }));
                granted.extend(ok.iter().map(|(i, _)| *i));
                if full {
                    break;
                }
                b0 = b1;
            }
            // Each parent's children, contiguous from `base`.
            let base = subs.len();
            let mut k = 0;
            while k < granted.len() {
                let parent = cands[granted[k]].parent;
                let mut e = k;
                while e < granted.len() && cands[granted[e]].parent == parent {
                    e += 1;
                }
                let starts: Vec<u32> = granted[k..e].iter().map(|&g| cands[g].start).collect();
                match parent {
                    None => {
                        root_children =
                            Children::new(root_refs.len(), &starts, base + k, p.min_refs);
                    }
                    Some(s) => {
                        subs[s].children =
                            Children::new(subs[s].refs.len(), &starts, base + k, p.min_refs);
                    }
                }
                k = e;
            }
            // The next level: the crowded cells of the new grids that the
            // stopping rule lets through (none once the budget is full).
            let mut next = Vec::new();
            for (k, sub) in filled.iter().enumerate() {
                if full || sub.depth >= MAX_DEPTH {
                    continue;
                }
                let parent_len = cands[granted[k]].len as f64;
                for (c, w) in sub.offsets.windows(2).enumerate() {
                    let len = (w[1] - w[0]) as usize;
                    if len >= p.min_refs {
                        next.push(Candidate {
                            parent: Some(base + k),
                            idx: sub.geom.index_of(c),
                            start: w[0],
                            len: len as u32,
                            depth: sub.depth + 1,
                            must_shrink: len as f64 > PROGRESS * parent_len,
                        });
                    }
                }
            }
            subs.extend(filled);
            cands = next;
        }
        Self {
            root: root_children,
            subs: subs.into_boxed_slice(),
        }
    }

    /// Heap bytes of all nested grids and their maps.
    pub(crate) fn bytes(&self) -> usize {
        self.root.bytes() + self.subs.iter().map(Sub::bytes).sum::<usize>()
    }

    /// The nested grids summed level by level, level 1 first (as many as
    /// the deepest grid's depth; none without nested grids).
    pub(crate) fn level_stats(&self) -> Vec<NestLevel> {
        let deepest = self.subs.iter().map(|s| s.depth).max().unwrap_or(0);
        let mut levels = vec![NestLevel::default(); deepest as usize];
        for s in self.subs.iter() {
            let l = &mut levels[s.depth as usize - 1];
            let counts = s.offsets.windows(2).map(|w| w[1] - w[0]);
            l.grids += 1;
            l.cells += s.geom.cell_count();
            l.occupied_cells += counts.clone().filter(|&n| n > 0).count() as u64;
            l.references += s.refs.len() as u64;
            l.direct_refs += s.direct.len() as u64;
            l.max_refs_per_cell = l.max_refs_per_cell.max(counts.max().unwrap_or(0));
            for w in s.wide_grids() {
                l.wide_grids += 1;
                l.wide_references += w.refs.len() as u64;
            }
        }
        levels
    }
}

/// Splits the references `refs` of cell `idx` of grid `g` into those that
/// span at least half of the (padded) cell along some axis, to be tested
/// directly, and the others, for the nested grid, which then spans only
/// what the others cover: a wall, a floor or a long sliver crossing a
/// detailed object's cell would otherwise stretch the nested grid over the
/// whole cell, and the object would fall into a few nested cells again.
/// Only when the direct ones are at most an eighth of the references:
/// otherwise none. `boxes` are the references' boxes; the third list
/// holds those of the second.
fn split<'r>(
    cell: &Aabb,
    refs: &'r [u32],
    boxes: Vec<Aabb>,
) -> (Vec<u32>, Cow<'r, [u32]>, Vec<Aabb>) {
    let half = cell.extent() * 0.5;
    let spans = |b: &Aabb| {
        let e = b.max.min(cell.max) - b.min.max(cell.min);
        e.x >= half.x || e.y >= half.y || e.z >= half.z
    };
    let spanning = boxes.iter().filter(|b| spans(b)).count();
    if spanning == 0 || spanning * 8 > refs.len() {
        return (Vec::new(), Cow::Borrowed(refs), boxes);
    }
    let mut direct = Vec::with_capacity(spanning);
    let mut inner = Vec::with_capacity(refs.len() - spanning);
    let mut inner_boxes = Vec::with_capacity(refs.len() - spanning);
    for (&r, b) in refs.iter().zip(boxes) {
        if spans(&b) {
            direct.push(r);
        } else {
            inner.push(r);
            inner_boxes.push(b);
        }
    }
    (direct, Cow::Owned(inner), inner_boxes)
}

/// Plans the nested grid of candidate cell `c` of grid `g`, whose
/// references are `refs`, with `room` bytes of the budget left; `None`
/// when it would not separate them or not fit in `room`, or, if it must
/// shrink, when they cover more than [`SHRINK`] of the cell's area.
fn plan<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    g: &Geom,
    c: &Candidate,
    refs: &[u32],
    p: &NestParams,
    room: usize,
) -> Option<Plan> {
    let idx = c.idx;
    let parent = g.padded_cell_box(idx);
    // Each box computed once: for the flat cost, the split and the plan.
    let all = boxes_of(prims, shared, refs);
    // What a ray crossing the cell costs if it stays flat: in the flat
    // grid, such a cell keeps group boxes.
    let grouped = p.groups && c.parent.is_none() && refs.len() >= GROUP_MIN_REFS;
    let flat = if p.cost && grouped {
        cost::grouped(
            &parent,
            all.chunks(4).map(|four| {
                let b = four.iter().fold(Aabb::EMPTY, geom::hull);
                (clip(b, &parent), four.len())
            }),
        )
    } else {
        refs.len() as f64
    };
    let (direct, inner, boxes) = split(&parent, refs, all);
    let cell = cover(g, idx, boxes.iter().copied());
    if c.must_shrink && geom::wide(cell.surface_area()) > SHRINK * geom::wide(parent.surface_area())
    {
        return None;
    }
    let e = cell.extent();
    let ext = [geom::wide(e.x), geom::wide(e.y), geom::wide(e.z)];
    let dims = geom::resolution(ext, inner.len(), p.m, MAX_SUB_CELLS);
    if dims == [1, 1, 1] {
        return None;
    }
    let mut geom = Geom::new(cell, dims);
    // Whether a grid holding `total` references pays, by the estimate (the
    // pad set below does not enter it).
    let pays = |geom: &Geom, total: u64| {
        !p.cost || cost::pays(flat, cost::nested(&parent, geom, total, direct.len()))
    };
    // Each reference lies in a cell at least, and the estimate grows with
    // the references: with one each it bounds the plan's from below, and
    // most refused plans are refused here, before any cell range.
    if !pays(&geom, inner.len() as u64) {
        return None;
    }
    let span = span_of(cell, &boxes);
    geom = geom.with_pad(pad_of(g.pad, refs.len(), &cell, dims, &span));
    geom.slab = p.slab;
    let reach = Reach::new(&span, geom.pad, g.pad);
    let outer = g.widen(&cell);
    let (offsets, ranges) = layout(&geom, &inner, &boxes, refs.len(), room, |t| pays(&geom, t))?;
    // The chain of wide grids, coarsest first, each holding the next finer.
    let mut wide: Option<Box<Plan>> = None;
    for (mut w, w_reach) in wide_chain(g, refs.len(), &geom, &span).into_iter().rev() {
        w.slab = p.slab;
        let Some((offsets, ranges)) = layout(&w, &inner, &boxes, refs.len(), room, |_| true) else {
            continue;
        };
        wide = Some(Box::new(Plan {
            geom: w,
            reach: w_reach,
            outer,
            offsets,
            ranges,
            direct: direct.clone(),
            wide,
        }));
    }
    Some(Plan {
        geom,
        reach,
        outer,
        offsets,
        ranges,
        direct,
        wide,
    })
}

/// Where the references `inner` (boxes `boxes`) of a cell of `cell_refs`
/// references fall in `geom`: the offsets of its cells and each
/// reference's cell range; `None` when the grid would not separate them
/// or, by `pays`, would not pay for the references it holds, or when its
/// references and offsets alone would take more than `room` bytes.
fn layout(
    geom: &Geom,
    inner: &[u32],
    boxes: &[Aabb],
    cell_refs: usize,
    room: usize,
    pays: impl Fn(u64) -> bool,
) -> Option<Layout> {
    let count = geom.cell_count() as usize;
    // Whether `total` references in `occupied` cells are separated enough.
    let separates = |total: u64, occupied: usize| {
        total as f64 <= SEPARATION * cell_refs as f64 * occupied as f64
    };
    let ranges: Vec<(u32, CellRange)> = inner
        .iter()
        .zip(boxes)
        .map(|(&r, b)| (r, geom.cell_range(b)))
        .collect();
    // The references the grid would hold, from the ranges alone: the tests
    // that need no more run before the count per cell, which costs a step
    // per reference and cell (a plan of large triangles over a small cell
    // covers most cells with each, and is refused).
    let total: u64 = ranges.iter().map(|(_, r)| geom::range_cells(*r)).sum();
    // At most every cell is occupied: a bound before the count.
    if !separates(total, count) || !pays(total) {
        return None;
    }
    if 4 * (total + count as u64 + 1) > room as u64 {
        return None;
    }
    let mut offsets = vec![0u32; count + 1];
    for &(_, range) in &ranges {
        geom.for_each_cell(range, |c| offsets[c + 1] += 1);
    }
    let occupied = offsets[1..].iter().filter(|&&n| n > 0).count().max(1);
    if !separates(total, occupied) {
        return None;
    }
    // The unseparated core: a ray that crossed two cells holding more than
    // half of the references each would test more than the cell holds.
    let heavy = PROGRESS * cell_refs as f64;
    if offsets[1..]
        .iter()
        .filter(|&&n| f64::from(n) > heavy)
        .count()
        > MAX_HEAVY
    {
        return None;
    }
    for c in 0..count {
        offsets[c + 1] += offsets[c];
    }
    Some((offsets, ranges))
}

/// The geometries and reaches of the chain of wide grids ([`Sub::wide`])
/// beside the nested grid `narrow`, whose references' boxes span `span`,
/// in a cell of `cell_refs` references of grid `g`, finest first: over the
/// same box, each with a pad [`WIDE_STEP`] times the previous one's (the
/// parent's when within [`PAD_SNAP`] of it, which ends the chain), in no
/// more cells per axis than the nested grid and cells at least
/// [`WIDE_CELL_PADS`] pads wide. None where the cell is cheap to test or
/// the nested pad is the parent's; the chain stops where the box fits in
/// one such cell (a ray beyond the last reach tests the references, if it
/// meets [`Sub::outer`]).
fn wide_chain(g: &Geom, cell_refs: usize, narrow: &Geom, span: &Aabb) -> Vec<(Geom, Reach)> {
    let mut chain = Vec::new();
    if cell_refs <= CHEAP_REFS {
        return chain;
    }
    let ext = narrow.bounds.extent();
    let mut pad = narrow.pad;
    // (A zero pad would never grow; a nested grid has none.)
    while pad > 0.0 && pad < g.pad {
        pad = if pad * WIDE_STEP * PAD_SNAP >= g.pad {
            g.pad
        } else {
            pad * WIDE_STEP
        };
        let dims: [u32; 3] = std::array::from_fn(|a| {
            let fit = (ext[a] / (WIDE_CELL_PADS * pad)).floor();
            // `as` saturates; a NaN (no pad) gives 0 and then 1 cell.
            (fit as u32).clamp(1, narrow.dims[a])
        });
        if dims == [1, 1, 1] {
            break;
        }
        chain.push((
            Geom::new(narrow.bounds, dims).with_pad(pad),
            Reach::new(span, pad, g.pad),
        ));
    }
    chain
}

/// What the references' boxes `boxes` of a nested grid over `cell` span
/// (with the cell): where the rays its pad covers are measured from.
fn span_of(cell: Aabb, boxes: &[Aabb]) -> Aabb {
    boxes.iter().fold(cell, geom::hull)
}

/// The pad of a nested grid over `bounds` with `dims` cells, in a cell of
/// `cell_refs` references of a grid of pad `parent`, whose references'
/// boxes span `span` (the module's notes).
fn pad_of(parent: Real, cell_refs: usize, bounds: &Aabb, dims: [u32; 3], span: &Aabb) -> Real {
    let ext = bounds.extent();
    let cell = (0..3)
        .filter(|&a| dims[a] > 1)
        .map(|a| ext[a] / dims[a] as Real)
        .fold(Real::INFINITY, Real::min);
    let own = PAD_ULPS * Real::EPSILON * span.extent().max_element();
    let floor = if cell_refs <= CHEAP_REFS {
        parent / PAD_STEP
    } else {
        0.0
    };
    let pad = (PAD_CELLS * cell).max(floor).max(own);
    if pad * PAD_SNAP >= parent {
        parent
    } else {
        pad
    }
}

/// Fills a planned nested grid (its references in order).
fn fill(plan: &Plan, start: u32, depth: u32) -> Sub {
    let count = plan.offsets.len() - 1;
    let mut next: Vec<u32> = plan.offsets[..count].to_vec();
    let mut out = vec![0u32; plan.offsets[count] as usize];
    for &(r, range) in &plan.ranges {
        plan.geom.for_each_cell(range, |c| {
            out[next[c] as usize] = r;
            next[c] += 1;
        });
    }
    let wide = plan.wide.as_ref().map(|w| Box::new(fill(w, start, depth)));
    Sub {
        start,
        geom: plan.geom.clone(),
        reach: plan.reach,
        outer: plan.outer,
        cull: cull_box(&plan.outer, &plan.geom, wide.as_deref()),
        occ: dense_occupancy(&plan.offsets),
        offsets: plan.offsets.clone().into_boxed_slice(),
        refs: out.into_boxed_slice(),
        direct: plan.direct.clone().into_boxed_slice(),
        children: Children::default(),
        depth,
        wide,
    }
}

/// The hull of `outer` and of the entry boxes of a grid `geom` and of
/// its chain of wide grids from `wide` ([`Sub::cull`]).
fn cull_box(outer: &Aabb, geom: &Geom, wide: Option<&Sub>) -> Aabb {
    geom::hull(wide.map_or(*outer, |w| w.cull), &geom.entry)
}

/// What the nested grid of cell `idx` of grid `g` spans: the union of its
/// references' `boxes` (their tight bounds), clipped to the cell's box
/// widened by its pad. Should the two miss each other by rounding on some axis, no hit
/// of these references lies in the cell along it, and the flat box left is
/// as good as any.
pub(crate) fn cover(g: &Geom, idx: [u32; 3], boxes: impl Iterator<Item = Aabb>) -> Aabb {
    clip(
        boxes.fold(Aabb::EMPTY, |b, r| geom::hull(b, &r)),
        &g.padded_cell_box(idx),
    )
}

/// The boxes of the references `refs`.
fn boxes_of<P: Primitive>(prims: &[P], shared: &P::Shared, refs: &[u32]) -> Vec<Aabb> {
    refs.iter()
        .map(|&r| prims[r as usize].bounds(shared))
        .collect()
}

/// Box `b` clipped to `cell`: flat where the two miss each other.
fn clip(b: Aabb, cell: &Aabb) -> Aabb {
    let lo = cell.min.max(b.min);
    Aabb::new(lo, cell.max.min(b.max).max(lo))
}
