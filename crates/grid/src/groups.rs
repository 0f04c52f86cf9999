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
//!
//! A group's box is clipped to the cell's padded box, and stored in a byte
//! per plane on a frame of the cell's own (the union of its clipped group
//! boxes cut into 255 steps per axis), rounded outwards: a block of four
//! boxes takes 24 bytes instead of 96. Clipping loses no hit: the walk
//! reaches the cell whose stretch of the ray holds the hit's `t`, the
//! primitive is in that cell (its padded box meets the cell's padded box
//! there), and there its clipped box holds the hit point; a hit that lies
//! beyond the cell is found in the cell that holds it, as with nested
//! grids. The decoded planes are computed at build time with the
//! operations the query uses (`base + q · step`, no fused multiply-add),
//! and each byte is moved outwards until its plane holds the box.

use crate::cells::Cells;
use crate::geom::{hull, Geom};
use crate::nested::Children;
use crate::{morton, Primitive};
use gridrt_bbox::math::{LaneChoice, Lanes};
use gridrt_bbox::{gamma, Aabb, Ray, Real};

/// Cells with fewer references test them all: with fewer than three
/// groups, the boxes could save a group test or two at most.
pub(crate) const GROUP_MIN_REFS: usize = 12;

/// How many steps a frame's axis is cut into.
const STEPS: u8 = 255;

/// A cell's frame for its group boxes: plane `q` of axis `a` lies at
/// `base[a] + q · step[a]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    base: [Real; 3],
    step: [Real; 3],
}

impl Frame {
    /// The frame spanning `span`: its plane 0 is `span.min`, its plane
    /// [`STEPS`] at or above `span.max`; `None` unless both are finite
    /// and so is the step (it is not past `Real::MAX / 255`).
    fn spanning(span: &Aabb) -> Option<Self> {
        let mut step = [0.0; 3];
        for (a, st) in step.iter_mut().enumerate() {
            let (lo, hi) = (span.min[a], span.max[a]);
            let mut s = (hi - lo) / Real::from(STEPS);
            if !(lo.is_finite() && hi.is_finite() && s.is_finite() && lo <= hi) {
                return None;
            }
            while lo + Real::from(STEPS) * s < hi {
                s = crate::geom::next_up(s);
            }
            *st = s;
        }
        Some(Self {
            base: span.min.to_array(),
            step,
        })
    }

    /// Plane `q` of axis `a`, as the query computes it.
    #[inline(always)]
    fn plane(&self, a: usize, q: u8) -> Real {
        self.base[a] + Real::from(q) * self.step[a]
    }

    /// Where `x` lies in steps of axis `a` from the base (0 on an axis
    /// of no extent), truncated and clamped to the bytes: a first guess,
    /// which the callers correct against the planes. (Truncating instead
    /// of `floor` or `ceil` costs at most one more correcting step; both
    /// are library calls on x86-64 without SSE4.1.)
    fn guess(&self, a: usize, x: Real) -> u8 {
        let steps = if self.step[a] > 0.0 {
            (x - self.base[a]) / self.step[a]
        } else {
            0.0
        };
        steps.clamp(0.0, Real::from(STEPS)) as u8
    }

    /// The byte of the highest plane at or below `x` (`x` at or above
    /// `base`).
    fn below(&self, a: usize, x: Real) -> u8 {
        let mut q = self.guess(a, x);
        while q > 0 && self.plane(a, q) > x {
            q -= 1;
        }
        q
    }

    /// The byte of the lowest plane at or above `x` (`x` at most the
    /// span's max).
    fn above(&self, a: usize, x: Real) -> u8 {
        let mut q = self.guess(a, x);
        while q < STEPS && self.plane(a, q) < x {
            q += 1;
        }
        q
    }

    /// The frame in lanes, for a cell's blocks.
    #[inline(always)]
    pub(crate) fn lanes(&self) -> FrameLanes {
        FrameLanes {
            base: self.base.map(Lanes::splat),
            step: self.step.map(Lanes::splat),
        }
    }
}

/// A [`Frame`] splatted into lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameLanes {
    base: [Lanes; 3],
    step: [Lanes; 3],
}

/// The boxes of four consecutive groups on their cell's [`Frame`], a byte
/// per plane: `lo[a][g]` and `hi[a][g]` for axis `a` of group `g`. Lanes
/// past a cell's last group hold any box, and the query masks them out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GroupBlock {
    lo: [[u8; 4]; 3],
    hi: [[u8; 4]; 3],
}

impl GroupBlock {
    /// The lanes (bit `g` for group `g`) whose box the ray meets within
    /// `[t_min, t_max]`: [`Aabb::hit`](gridrt_bbox::Aabb::hit)'s robust
    /// test, the same operations in lanes, so a NaN leaves a group in.
    /// `t_max` is widened like the exits: it is the best hit's `t`, and a
    /// primitive hit at the same `t` has its box's entry there, which
    /// rounding may put a little after it.
    #[inline(always)]
    pub(crate) fn hit_mask(
        &self,
        frame: &FrameLanes,
        ray: &RaySlabs,
        t_min: Real,
        t_max: Real,
    ) -> u32 {
        let mut t0 = Lanes::splat(t_min);
        let mut t1 = Lanes::splat(t_max) + Lanes::splat(t_max.abs()) * ray.widen;
        for a in 0..3 {
            let plane = |q: [u8; 4]| frame.base[a] + Lanes::from(q.map(Real::from)) * frame.step[a];
            let (lo, hi, o) = (plane(self.lo[a]), plane(self.hi[a]), ray.origin[a]);
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
                // The robust test's swap of `t_lo > t_hi`, one choice each.
                let near = t_hi.min_lt(t_lo);
                let far = t_lo.max_gt(t_hi);
                // `−∞ + ∞` is NaN; keep `far` then, as the scalar `max` does.
                let wide = far + far.abs() * ray.widen;
                (near, wide.max_gt(far))
            };
            t0 = near.max_gt(t0);
            t1 = far.min_lt(t1);
        }
        (!t0.cmpgt(t1).bitmask()) & 0xf
    }

    /// Box `g` as the query decodes it on `frame`.
    fn decoded(&self, frame: &Frame, g: usize) -> Aabb {
        let mut b = Aabb::EMPTY;
        for a in 0..3 {
            b.min[a] = frame.plane(a, self.lo[a][g]);
            b.max[a] = frame.plane(a, self.hi[a][g]);
        }
        b
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
    /// Per such cell, in rank order, its frame.
    frames: Box<[Frame]>,
    blocks: Box<[GroupBlock]>,
}

/// A crowded cell as [`Groups::build`] takes it: its run's start and
/// length in the references, and its `(i, j, k)`.
pub(crate) type Run = (u32, u32, [u32; 3]);

impl Groups {
    /// The boxes of the groups of four of each run of `runs` (by ascending
    /// start, each of at least [`GROUP_MIN_REFS`] references): each
    /// group's primitives' boxes widened by the pad of `geom` and clipped
    /// to the cell's padded box, on the cell's frame.
    pub(crate) fn build<P: Primitive>(
        prims: &[P],
        shared: &P::Shared,
        refs: &[u32],
        runs: &[Run],
        geom: &Geom,
    ) -> Self {
        if runs.is_empty() {
            return Self::default();
        }
        let mut starts = Vec::with_capacity(runs.len());
        let mut first = Vec::with_capacity(runs.len());
        let mut frames = Vec::with_capacity(runs.len());
        let mut blocks = Vec::new();
        let mut boxes = Vec::new();
        for &(start, len, idx) in runs {
            let run = &refs[start as usize..(start + len) as usize];
            let cell = geom.padded_cell_box(idx);
            boxes.clear();
            boxes.extend(
                run.chunks(4)
                    .map(|group| clipped_box(prims, shared, group, geom, &cell)),
            );
            // A cell of absurd extent (past `Real::MAX / 255`) keeps none.
            let span = boxes.iter().fold(Aabb::EMPTY, hull);
            let Some(frame) = Frame::spanning(&span) else {
                continue;
            };
            starts.push(start);
            first.push(blocks.len() as u32);
            frames.push(frame);
            for four in boxes.chunks(4) {
                let mut block = GroupBlock {
                    lo: [[STEPS; 4]; 3],
                    hi: [[0; 4]; 3],
                };
                for (g, b) in four.iter().enumerate() {
                    for a in 0..3 {
                        block.lo[a][g] = frame.below(a, b.min[a]);
                        block.hi[a][g] = frame.above(a, b.max[a]);
                    }
                }
                blocks.push(block);
            }
        }
        Self {
            map: Children::new(refs.len(), &starts, 0, GROUP_MIN_REFS),
            first: first.into_boxed_slice(),
            frames: frames.into_boxed_slice(),
            blocks: blocks.into_boxed_slice(),
        }
    }

    /// The frame and group blocks of the cell whose run of `len`
    /// references starts at `start`, if it has groups.
    #[inline(always)]
    pub(crate) fn of(&self, len: usize, start: u32) -> Option<(&Frame, &[GroupBlock])> {
        let rank = self.map.find(len, start)?;
        debug_assert!(rank < self.first.len() && rank < self.frames.len());
        // SAFETY: `find` gives ranks of the runs given to `build`, one
        // `first` and one `frames` entry each.
        let (first, frame) = unsafe {
            (
                *self.first.get_unchecked(rank) as usize,
                self.frames.get_unchecked(rank),
            )
        };
        let count = len.div_ceil(16);
        debug_assert!(first + count <= self.blocks.len());
        // SAFETY: `build` made `len.div_ceil(16)` blocks for this run.
        Some((frame, unsafe {
            self.blocks.get_unchecked(first..first + count)
        }))
    }

    /// The heap bytes of the groups of `runs` in a grid of `refs`
    /// references.
    pub(crate) fn bytes_for(refs: usize, runs: &[Run]) -> usize {
        let blocks: usize = runs
            .iter()
            .map(|&(_, len, _)| (len as usize).div_ceil(16))
            .sum();
        Children::bytes_for(refs)
            + runs.len() * (std::mem::size_of::<u32>() + std::mem::size_of::<Frame>())
            + blocks * std::mem::size_of::<GroupBlock>()
    }

    /// Checks that every cell of `runs` with groups has one box per group
    /// of four that, as the query decodes it, holds its primitives' boxes
    /// widened by the pad of `geom` and clipped to the cell's padded box,
    /// for tests; `Err` names the first violation.
    pub(crate) fn check<P: Primitive>(
        &self,
        prims: &[P],
        shared: &P::Shared,
        refs: &[u32],
        runs: &[Run],
        geom: &Geom,
    ) -> Result<(), String> {
        let mut cells = 0;
        for &(start, len, idx) in runs {
            let Some((frame, blocks)) = self.of(len as usize, start) else {
                continue;
            };
            cells += 1;
            let run = &refs[start as usize..(start + len) as usize];
            let cell = geom.padded_cell_box(idx);
            for (g, group) in run.chunks(4).enumerate() {
                let want = clipped_box(prims, shared, group, geom, &cell);
                let have = blocks[g / 4].decoded(frame, g % 4);
                for a in 0..3 {
                    if !(have.min[a] <= want.min[a] && want.max[a] <= have.max[a]) {
                        return Err(format!("run at {start}: group {g} misses its primitives"));
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
            + std::mem::size_of_val(&*self.frames)
            + std::mem::size_of_val(&*self.blocks)
    }
}

/// The box of the primitives of `group` widened by the pad of `geom`,
/// clipped to `cell`, their cell's padded box.
fn clipped_box<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    group: &[u32],
    geom: &Geom,
    cell: &Aabb,
) -> Aabb {
    let b = group.iter().fold(Aabb::EMPTY, |b, &r| {
        hull(b, &prims[r as usize].bounds(shared))
    });
    let w = geom.widen(&b);
    let clipped = Aabb::new(w.min.max(cell.min), w.max.min(cell.max));
    // Not empty for a primitive of the cell; should rounding make it so,
    // the cell's box is as exact.
    if clipped.min.cmple(clipped.max).all() {
        clipped
    } else {
        *cell
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
            .fold(Aabb::EMPTY, |s, &c| hull(s, &Aabb::new(c, c)));
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
        /// Each byte-coded box holds the box it codes, and each lane's
        /// verdict is the scalar robust slab test's on the decoded box,
        /// over the range whose end is widened as the lanes widen it.
        #[test]
        fn four_coded_boxes_at_once_equal_the_robust_slab_test(
            corners in prop::collection::vec((point(), point()), 4),
            scale in prop::sample::select(vec![1.0 as Real, 1e-3, 3e4]),
            o in point(),
            d in point(),
            t_min in prop::sample::select(vec![0.0 as Real, 0.5, 2.0]),
            t_max in prop::sample::select(vec![Real::INFINITY, 0.0, 1.0, 3.0]),
        ) {
            let boxes: Vec<Aabb> = corners
                .iter()
                .map(|&(a, b)| Aabb::new(a.min(b) * scale + 0.1, a.max(b) * scale + 0.1))
                .collect();
            let span = boxes.iter().fold(Aabb::EMPTY, |u, b| u.union(*b));
            let frame = Frame::spanning(&span).unwrap();
            let mut block = GroupBlock { lo: [[0; 4]; 3], hi: [[0; 4]; 3] };
            for (g, b) in boxes.iter().enumerate() {
                for a in 0..3 {
                    block.lo[a][g] = frame.below(a, b.min[a]);
                    block.hi[a][g] = frame.above(a, b.max[a]);
                }
            }
            let ray = Ray::new(o * scale, d);
            let mask = block.hit_mask(&frame.lanes(), &RaySlabs::new(&ray), t_min, t_max);
            let end = t_max + t_max.abs() * 2.0 * gamma(3);
            for (g, b) in boxes.iter().enumerate() {
                let coded = block.decoded(&frame, g);
                prop_assert!(coded.min.cmple(b.min).all() && b.max.cmple(coded.max).all(),
                    "box {} {:?} coded as {:?}", g, b, coded);
                prop_assert_eq!(mask >> g & 1 == 1, coded.hit(&ray, t_min, end).is_some(), "box {}", g);
            }
        }
    }
}
