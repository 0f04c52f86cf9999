//! Bounds of groups of four references in a cell that holds many.
//!
//! A cell of a regular grid over a surface mesh holds a patch of it, a few
//! dozen triangles in a detailed model; a ray that crosses the cell, or
//! leaves the surface from inside it, passes near a few of them only. So
//! the build sorts such a cell's references along a Morton curve of their
//! boxes' centres (before the slots are numbered, so that a group's
//! primitives also lie side by side), cuts the run into groups of four and
//! keeps each group's box, widened by the grid's insertion pad; a query
//! tests the ray against four group boxes at once and tests the references
//! of the groups it meets within the query's range, which shrinks to the
//! best hit so far.
//!
//! The boxes keep the grid exact for the same reason its cells do: a
//! primitive reports its hit at a point inside its box up to rounding that
//! the pad covers, so a ray that hits a primitive meets its group's padded
//! box at that `t`, and the slab test (the robust one of
//! [`Aabb::hit`](gridrt_bbox::Aabb::hit), in lanes) is conservative.

use crate::cells::Cells;
use crate::nested::Children;
use crate::{morton, Primitive};
use gridrt_bbox::math::Lanes;
use gridrt_bbox::{gamma, Aabb, Ray, Real};

/// Cells with fewer references test them all: with fewer than three
/// groups, the boxes could save a group test or two at most.
pub(crate) const GROUP_MIN_REFS: usize = 12;

/// The boxes of four consecutive groups, coordinate by coordinate (lane
/// `g` is group `g`). Lanes past a cell's last group hold an empty box,
/// and the query masks them out.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GroupBlock {
    lo: [Lanes; 3],
    hi: [Lanes; 3],
}

impl GroupBlock {
    /// The lanes (bit `g` for group `g`) whose box the ray meets within
    /// `[t_min, t_max]`: [`Aabb::hit`](gridrt_bbox::Aabb::hit)'s robust
    /// test, the same operations in lanes, so a NaN leaves a group in.
    /// `t_max` is widened like the exits: it is the best hit's `t`, and a
    /// primitive hit at the same `t` has its box's entry there, which
    /// rounding may put a little after it.
    #[inline(always)]
    pub(crate) fn hit_mask(&self, ray: &RaySlabs, t_min: Real, t_max: Real) -> u32 {
        let mut t0 = Lanes::splat(t_min);
        let mut t1 = Lanes::splat(t_max) + Lanes::splat(t_max.abs()) * ray.widen;
        for a in 0..3 {
            let (lo, hi, o) = (self.lo[a], self.hi[a], ray.origin[a]);
            let (near, far) = if ray.parallel[a] {
                // Inside the slab for every t, or never.
                let inside = lo.cmple(o) & o.cmple(hi);
                (
                    Lanes::select(inside, Lanes::NEG_INFINITY, Lanes::INFINITY),
                    Lanes::select(inside, Lanes::INFINITY, Lanes::NEG_INFINITY),
                )
            } else {
                let t_lo = (lo - o) * ray.inv[a];
                let t_hi = (hi - o) * ray.inv[a];
                let swap = t_lo.cmpgt(t_hi);
                let near = Lanes::select(swap, t_hi, t_lo);
                let far = Lanes::select(swap, t_lo, t_hi);
                // `−∞ + ∞` is NaN; keep `far` then, as the scalar `max` does.
                let wide = far + far.abs() * ray.widen;
                (near, Lanes::select(wide.cmpgt(far), wide, far))
            };
            t0 = Lanes::select(near.cmpgt(t0), near, t0);
            t1 = Lanes::select(far.cmplt(t1), far, t1);
        }
        (!t0.cmpgt(t1).bitmask()) & 0xf
    }
}

/// What the group test needs of a ray, in lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RaySlabs {
    origin: [Lanes; 3],
    inv: [Lanes; 3],
    /// Axes along which the ray does not move (an infinite reciprocal).
    parallel: [bool; 3],
    widen: Lanes,
}

impl RaySlabs {
    #[inline(always)]
    pub(crate) fn new(ray: &Ray) -> Self {
        let o = ray.origin;
        let inv = ray.inv_dir;
        Self {
            origin: [o.x, o.y, o.z].map(Lanes::splat),
            inv: [inv.x, inv.y, inv.z].map(Lanes::splat),
            parallel: [inv.x, inv.y, inv.z].map(Real::is_infinite),
            widen: Lanes::splat(2.0 * gamma(3)),
        }
    }
}

/// The group boxes of one grid's crowded cells.
#[derive(Clone, Debug, Default)]
pub(crate) struct Groups {
    /// Which runs of the grid's references have groups: `find` gives the
    /// cell's rank among them.
    map: Children,
    /// Per such cell, in rank order, the index of its first block.
    first: Box<[u32]>,
    blocks: Box<[GroupBlock]>,
}

impl Groups {
    /// The boxes of the groups of four of each run of `runs` (start and
    /// length in `refs`, by ascending start, each of at least
    /// [`GROUP_MIN_REFS`]), widened by `pad`.
    pub(crate) fn build<P: Primitive>(
        prims: &[P],
        shared: &P::Shared,
        refs: &[u32],
        runs: &[(u32, u32)],
        pad: Real,
    ) -> Self {
        if runs.is_empty() {
            return Self::default();
        }
        let starts: Vec<u32> = runs.iter().map(|&(s, _)| s).collect();
        let map = Children::new(refs.len(), &starts, 0, GROUP_MIN_REFS);
        let mut first = Vec::with_capacity(runs.len());
        let mut blocks = Vec::new();
        for &(start, len) in runs {
            let run = &refs[start as usize..(start + len) as usize];
            first.push(blocks.len() as u32);
            for sixteen in run.chunks(16) {
                let mut lo = [Lanes::INFINITY; 3];
                let mut hi = [Lanes::NEG_INFINITY; 3];
                for (g, group) in sixteen.chunks(4).enumerate() {
                    let b = group.iter().fold(Aabb::EMPTY, |b, &r| {
                        b.union(prims[r as usize].bounds(shared))
                    });
                    for a in 0..3 {
                        lo[a][g] = b.min[a] - pad;
                        hi[a][g] = b.max[a] + pad;
                    }
                }
                blocks.push(GroupBlock { lo, hi });
            }
        }
        Self {
            map,
            first: first.into_boxed_slice(),
            blocks: blocks.into_boxed_slice(),
        }
    }

    /// The group blocks of the cell whose run of `len` references starts
    /// at `start`, if it has groups.
    #[inline(always)]
    pub(crate) fn of(&self, len: usize, start: u32) -> Option<&[GroupBlock]> {
        let rank = self.map.find(len, start)?;
        debug_assert!(rank < self.first.len());
        // SAFETY: `find` gives ranks of the runs given to `build`, one
        // `first` entry each.
        let first = unsafe { *self.first.get_unchecked(rank) } as usize;
        let count = len.div_ceil(16);
        debug_assert!(first + count <= self.blocks.len());
        // SAFETY: `build` made `len.div_ceil(16)` blocks for this run.
        Some(unsafe { self.blocks.get_unchecked(first..first + count) })
    }

    /// The heap bytes of the groups of `runs` in a grid of `refs`
    /// references.
    pub(crate) fn bytes_for(refs: usize, runs: &[(u32, u32)]) -> usize {
        let blocks: usize = runs
            .iter()
            .map(|&(_, len)| (len as usize).div_ceil(16))
            .sum();
        Children::bytes_for(refs)
            + runs.len() * std::mem::size_of::<u32>()
            + blocks * std::mem::size_of::<GroupBlock>()
    }

    /// Checks that every cell of `runs` (start and length in `refs`) with
    /// groups has one box per group of four, holding its primitives' boxes
    /// widened by `pad`, for tests; `Err` names the first violation.
    pub(crate) fn check<P: Primitive>(
        &self,
        prims: &[P],
        shared: &P::Shared,
        refs: &[u32],
        runs: &[(u32, u32)],
        pad: Real,
    ) -> Result<(), String> {
        let mut cells = 0;
        for &(start, len) in runs {
            let Some(blocks) = self.of(len as usize, start) else {
                continue;
            };
            cells += 1;
            let run = &refs[start as usize..(start + len) as usize];
            for (g, group) in run.chunks(4).enumerate() {
                let block = &blocks[g / 4];
                for &r in group {
                    let b = prims[r as usize].bounds(shared);
                    for a in 0..3 {
                        if !(block.lo[a][g % 4] <= b.min[a] - pad
                            && b.max[a] + pad <= block.hi[a][g % 4])
                        {
                            return Err(format!("run at {start}: group {g} misses slot {r}"));
                        }
                    }
                }
            }
        }
        if cells != self.cells() {
            return Err(format!("{} cells with groups, {cells} found", self.cells()));
        }
        Ok(())
    }

    /// How many cells have groups.
    pub(crate) fn cells(&self) -> usize {
        self.first.len()
    }

    /// Heap bytes.
    pub(crate) fn bytes(&self) -> usize {
        self.map.bytes()
            + std::mem::size_of_val(&*self.first)
            + std::mem::size_of_val(&*self.blocks)
    }
}

/// Sorts each run of at least [`GROUP_MIN_REFS`] references of `cells`
/// (whose `refs` are primitive indices) along a Morton curve of the
/// primitives' box centres, so that each group of four is compact; the
/// slots numbered afterwards in order of first reference then put a
/// group's primitives side by side in memory.
pub(crate) fn sort_crowded_runs<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    cells: &Cells,
    dims: [u32; 3],
    refs: &mut [u32],
) {
    let (mut centres, mut keyed) = (Vec::new(), Vec::new());
    for (_, start, len) in cells.runs(dims, GROUP_MIN_REFS) {
        let run = &mut refs[start as usize..(start + len) as usize];
        centres.clear();
        centres.extend(run.iter().map(|&r| {
            let b = prims[r as usize].bounds(shared);
            (b.min + b.max) * 0.5
        }));
        let span = centres
            .iter()
            .fold(Aabb::EMPTY, |s, &c| s.union(Aabb::new(c, c)));
        let (lo, ext) = (span.min, span.extent());
        // 10 bits per axis of the run's own span.
        let q = |a: usize, c: Real| -> u32 {
            if ext[a] > 0.0 {
                (((c - lo[a]) / ext[a]).clamp(0.0, 1.0) * 1023.0) as u32
            } else {
                0
            }
        };
        keyed.clear();
        keyed.extend(
            run.iter()
                .zip(&centres)
                .map(|(&r, c)| (morton::encode3(q(0, c.x), q(1, c.y), q(2, c.z)), r)),
        );
        keyed.sort_unstable();
        for (slot, &(_, r)) in run.iter_mut().zip(&keyed) {
            *slot = r;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_bbox::Vec3;
    use proptest::prelude::*;

    /// A coordinate on a small lattice, so that origins fall on box faces
    /// and direction components are exactly zero.
    fn lattice() -> impl Strategy<Value = Real> {
        (-4i32..=4).prop_map(|i| i as Real * 0.5)
    }

    fn point() -> impl Strategy<Value = Vec3> {
        [lattice(), lattice(), lattice()].prop_map(Vec3::from_array)
    }

    proptest! {
        /// Each lane's verdict is the scalar robust slab test's over the
        /// range whose end is widened as the lanes widen it.
        #[test]
        fn four_boxes_at_once_equal_the_robust_slab_test(
            corners in prop::collection::vec((point(), point()), 4),
            o in point(),
            d in point(),
            t_min in prop::sample::select(vec![0.0 as Real, 0.5, 2.0]),
            t_max in prop::sample::select(vec![Real::INFINITY, 0.0, 1.0, 3.0]),
        ) {
            let boxes: Vec<Aabb> = corners.iter().map(|&(a, b)| Aabb::new(a.min(b), a.max(b))).collect();
            let mut block = GroupBlock { lo: [Lanes::ZERO; 3], hi: [Lanes::ZERO; 3] };
            for (g, b) in boxes.iter().enumerate() {
                for a in 0..3 {
                    block.lo[a][g] = b.min[a];
                    block.hi[a][g] = b.max[a];
                }
            }
            let ray = Ray::new(o, d);
            let mask = block.hit_mask(&RaySlabs::new(&ray), t_min, t_max);
            let end = t_max + t_max.abs() * 2.0 * gamma(3);
            for (g, b) in boxes.iter().enumerate() {
                prop_assert_eq!(mask >> g & 1 == 1, b.hit(&ray, t_min, end).is_some(), "box {}", g);
            }
        }
    }
}
