//! Nested grids in crowded cells, the remedy for the "teapot in a stadium"
//! (a small, detailed object in a large, mostly empty scene): the grid's
//! resolution follows the whole scene, so the cells around the detailed
//! object hold dozens of primitives each. A cell with at least
//! [`GridConfig::nest_min_refs`] references gets a small dense grid of its
//! own, built from those references by the lecture's formula over the part
//! of the cell that they cover; `closest_hit` and `any_hit` walk it instead
//! of testing the cell's references one by one. The cell keeps its
//! references too, so every other use of the cell (the public walk, the
//! self-checks) is unchanged.
//!
//! Correctness is the outer grid's argument one level down. The nested grid
//! spans every point of the cell that lies in one of its references' boxes,
//! so every hit inside the cell; it is widened by the outer grid's pad (not
//! a smaller one of its own); every reference is in every nested cell its
//! padded box overlaps; and the nested walk stops under the outer walk's
//! rule. So it finds the nearest hit inside the cell, ties included.

use crate::geom::{self, Geom};
use crate::grid::dense_occupancy;
use crate::par::map_indices;
use crate::{GridConfig, Primitive};
use gridrt_bbox::Aabb;

/// Most cells of one nested grid.
const MAX_SUB_CELLS: u64 = 1 << 12;

/// The nested grid of one crowded cell.
#[derive(Clone, Debug)]
pub(crate) struct Sub {
    /// Where the cell's run starts in the outer grid's references: the key
    /// the walk finds the nested grid by.
    pub start: u32,
    pub geom: Geom,
    /// `offsets[c]..offsets[c + 1]` are sub-cell `c`'s references
    /// (row-major), indices of the outer grid's primitives.
    pub offsets: Box<[u32]>,
    pub refs: Box<[u32]>,
    /// One bit per sub-cell: set when it holds references.
    pub occ: Box<[u64]>,
}

/// The nested grids of a grid, sorted by [`Sub::start`].
#[derive(Clone, Debug, Default)]
pub(crate) struct Nested {
    pub subs: Box<[Sub]>,
    /// One bit per index of the outer grid's references, set where the run
    /// of a cell with a nested grid starts; `subs` are in the order of
    /// these bits.
    starts: Box<[u64]>,
    /// `rank[w]`: the set bits of `starts[..w]`, so that a start's nested
    /// grid is found by one popcount instead of a search.
    rank: Box<[u32]>,
    /// Cells with fewer references have no nested grid (0: none has).
    pub min_refs: usize,
}

impl Nested {
    /// Nested grids for the crowded cells `(index, start, references)`.
    /// `refs` is the length of the outer grid's reference array.
    pub(crate) fn build<P: Primitive>(
        prims: &[P],
        outer: &Geom,
        refs: usize,
        crowded: Vec<([u32; 3], u32, &[u32])>,
        config: &GridConfig,
    ) -> Self {
        if crowded.is_empty() {
            return Self::default();
        }
        let m = geom::sanitize_m(config.nest_m.unwrap_or(config.m));
        let mut subs = map_indices(crowded.len(), config.parallel_build, |i| {
            let (idx, start, refs) = crowded[i];
            Sub::build(prims, outer, idx, start, refs, m)
        });
        subs.sort_unstable_by_key(|s| s.start);
        let mut starts = vec![0u64; refs.div_ceil(64)];
        for s in &subs {
            starts[s.start as usize >> 6] |= 1 << (s.start & 63);
        }
        let rank = starts
            .iter()
            .scan(0u32, |n, w| {
                let r = *n;
                *n += w.count_ones();
                Some(r)
            })
            .collect();
        Self {
            starts: starts.into_boxed_slice(),
            rank,
            subs: subs.into_boxed_slice(),
            min_refs: config.nest_min_refs as usize,
        }
    }

    /// The nested grid of the cell whose run of `len` references starts at
    /// index `start` of the outer grid's references, if it has one.
    #[inline(always)]
    pub(crate) fn find(&self, len: usize, start: u32) -> Option<&Sub> {
        if self.min_refs == 0 || len < self.min_refs {
            return None;
        }
        let w = start as usize >> 6;
        let bits = *self.starts.get(w)?;
        // The bits up to and including the start's own.
        let below = bits & (u64::MAX >> (63 - (start & 63)));
        if below >> (start & 63) == 0 {
            return None;
        }
        self.subs
            .get(self.rank[w] as usize + below.count_ones() as usize - 1)
    }

    /// Heap bytes of all nested grids.
    pub(crate) fn bytes(&self) -> usize {
        std::mem::size_of_val(&*self.starts)
            + std::mem::size_of_val(&*self.rank)
            + self
                .subs
                .iter()
                .map(|s| {
                    std::mem::size_of::<Sub>()
                        + std::mem::size_of_val(&*s.offsets)
                        + std::mem::size_of_val(&*s.refs)
                        + std::mem::size_of_val(&*s.occ)
                        + s.geom
                            .planes
                            .iter()
                            .map(|p| 2 * std::mem::size_of_val(&**p))
                            .sum::<usize>()
                })
                .sum::<usize>()
    }
}

impl Sub {
    /// The nested grid of outer cell `idx`, whose references `refs` start
    /// at `start` in the outer grid's reference array.
    fn build<P: Primitive>(
        prims: &[P],
        outer: &Geom,
        idx: [u32; 3],
        start: u32,
        refs: &[u32],
        m: f64,
    ) -> Self {
        let boxes: Vec<Aabb> = refs.iter().map(|&p| prims[p as usize].bounds()).collect();
        let cell = cover(outer, idx, boxes.iter().copied());
        let e = cell.extent();
        let ext = [geom::wide(e.x), geom::wide(e.y), geom::wide(e.z)];
        let dims = geom::resolution(ext, refs.len(), m, MAX_SUB_CELLS);
        let geom = Geom::new(cell, dims).with_pad(outer.pad);
        let count = geom.cell_count() as usize;
        let ranges: Vec<([u32; 3], [u32; 3])> = boxes.iter().map(|b| geom.cell_range(b)).collect();
        let each = |f: &mut dyn FnMut(usize, u32)| {
            for (&p, &range) in refs.iter().zip(&ranges) {
                geom.for_each_cell(range, |c| f(c, p));
            }
        };
        // Count, prefix-sum into starts, fill (references keep their order).
        let mut offsets = vec![0u32; count + 1];
        each(&mut |c, _| offsets[c + 1] += 1);
        for c in 0..count {
            offsets[c + 1] += offsets[c];
        }
        let mut next: Vec<u32> = offsets[..count].to_vec();
        let mut out = vec![0u32; offsets[count] as usize];
        each(&mut |c, p| {
            out[next[c] as usize] = p;
            next[c] += 1;
        });
        Self {
            start,
            geom,
            occ: dense_occupancy(&offsets),
            offsets: offsets.into_boxed_slice(),
            refs: out.into_boxed_slice(),
        }
    }
}

/// What the nested grid of outer cell `idx` spans: the cell's box widened
/// by the pad, shrunk to the union of its references' `boxes`. (Should the
/// two miss each other by rounding on some axis, no hit of these
/// references lies in the cell along it, and the flat box left is as good
/// as any.)
pub(crate) fn cover(outer: &Geom, idx: [u32; 3], boxes: impl Iterator<Item = Aabb>) -> Aabb {
    let union = boxes.fold(Aabb::EMPTY, Aabb::union);
    let cell = outer.padded_cell_box(idx);
    let lo = cell.min.max(union.min);
    Aabb::new(lo, cell.max.min(union.max).max(lo))
}
