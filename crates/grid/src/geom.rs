//! The grid's geometry: its box, the number of cells per axis, and the cell
//! planes that both insertion and traversal use, so the two always agree on
//! where a cell begins and ends.

use crate::morton;
use gridrt_bbox::math::{LaneChoice, Lanes, Vec3Lanes};
use gridrt_bbox::{Aabb, Ray, Real, SlabRay, SlabTest, Vec3};

/// The insertion pad, in units of `Real::EPSILON` times the largest extent
/// of the outermost grid box (nested grids narrow it: [`crate::nested`]).
/// It absorbs the rounding that grows with the distance a ray travels (a
/// primitive's hit `t`, the traversal's plane crossings), which does not
/// depend on where the scene lies: by the bound of [`RAY_ULPS`], it covers
/// rays that start within 8 extents of every point of the box.
///
/// Nothing in the pad follows the coordinates' magnitude: the rounding of
/// absolute positions is made exact instead: a box's cells are found by
/// comparing its distance to the stored planes with the pad whenever the
/// coordinates are large against the pad ([`Geom::cell_range`]), boxes
/// handed to [`crate::Primitive::overlaps_box`] and the grid's entry box
/// are widened with outward rounding ([`Geom::widen`]), and the walk's entry cell is made consistent
/// with its own plane crossings ([`crate::dda`]), so a scene moved far from
/// the origin keeps the references it has at the origin.
pub(crate) const PAD_ULPS: Real = 64.0;

/// The rounding a ray brings to a hit point and to the walk's plane
/// crossings, in units of `Real::EPSILON` times `D`, the largest
/// coordinate distance between the ray's origin and the points it meets:
/// the vertices a primitive test translates to the origin, the planes the
/// walk crosses. A pad `p` covers the rays with `RAY_ULPS · ε · D <= p`
/// (for the outermost grid, whose pad is [`PAD_ULPS`] of its extent, the
/// rays from within 8 extents of every point of its box); the constant
/// holds the bound's slack.
pub(crate) const RAY_ULPS: Real = 8.0;

/// The rays a nested grid's pad covers ([`RAY_ULPS`]): those whose origin
/// lies within `far`, in every coordinate, of every point of `span`, the
/// box of the grid's references; every ray when the pad is its parent's.
/// A ray from farther away walks a wide grid or tests the parent cell's
/// references instead ([`crate::nested`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Reach {
    lo: Vec3,
    hi: Vec3,
    far: Real,
}

impl Reach {
    /// The reach of pad `pad` over the box `span`, in a grid of pad
    /// `parent`: unbounded when `pad` is not narrower, since the nested
    /// grid then covers every ray its parent does.
    pub(crate) fn new(span: &Aabb, pad: Real, parent: Real) -> Self {
        Self {
            lo: span.min,
            hi: span.max,
            far: if pad < parent {
                pad / (RAY_ULPS * Real::EPSILON)
            } else {
                Real::INFINITY
            },
        }
    }

    /// Whether the pad covers a ray from `origin` (never for a NaN origin).
    #[inline(always)]
    pub(crate) fn covers(&self, origin: Vec3) -> bool {
        let d = (origin - self.lo).abs().max((origin - self.hi).abs());
        d.x <= self.far && d.y <= self.far && d.z <= self.far
    }
}

/// Hard ceiling on the cell count whatever `GridConfig::max_cells` says:
/// dense offsets and cell keys are `u32`.
pub(crate) const HARD_MAX_CELLS: u64 = 1 << 31;

/// Cells per axis, cell planes and the insertion pad of one grid.
#[derive(Clone, Debug)]
pub(crate) struct Geom {
    /// The union of the primitives' (finite) boxes; `Aabb::EMPTY` when none.
    pub bounds: Aabb,
    /// Cells per axis; all zero for an empty grid, otherwise at least one.
    pub dims: [u32; 3],
    /// `dims[a] + 1` plane coordinates per axis, nondecreasing, from
    /// `bounds.min[a]` to `bounds.max[a]`. Cell `i` spans `[planes[i], planes[i+1]]`.
    pub planes: [Box<[Real]>; 3],
    /// `dims[a] / extent[a]`, or 0 when the extent is 0.
    pub inv_cell: [Real; 3],
    /// Absolute widening applied to primitive boxes (see [`PAD_ULPS`]).
    pub pad: Real,
    /// Whether [`Geom::cell_range`] corrects its estimate against the
    /// stored planes: when the grid's coordinates are so large against the
    /// pad that the estimate's rounding (an ulp or two of the coordinates)
    /// could exceed it.
    exact_planes: bool,
    /// The grid box widened by the pad: what a ray must hit to enter.
    pub entry: Aabb,
    /// The slab test that decides the entry ([`crate::GridConfig::slab`]).
    pub slab: SlabTest,
    /// `bounds.min`, `inv_cell` and `dims − 1` per axis in SIMD lanes, for
    /// the build's cell ranges and the walk's set-up.
    pub lanes: [Vec3Lanes; 3],
    /// The planes as the walk sees them: `planes` with the two outer faces
    /// replaced by `−∞` and `+∞`, so that the crossing after the last
    /// interior plane is `+∞` in either direction.
    pub walk: [Box<[Real]>; 3],
    /// The longest box edge a gridded primitive may have: primitives with a
    /// longer one (a ground far larger than the model on it) are kept out
    /// of the cells with the unbounded ones ([`crate::build`]); `+∞` when
    /// none is.
    pub outsized: Real,
}

impl Geom {
    /// A grid with no cells: every query misses it.
    pub(crate) fn empty() -> Self {
        Self {
            bounds: Aabb::EMPTY,
            dims: [0; 3],
            planes: [Box::new([]), Box::new([]), Box::new([])],
            inv_cell: [0.0; 3],
            pad: 0.0,
            exact_planes: false,
            entry: Aabb::EMPTY,
            slab: SlabTest::Robust,
            lanes: [Vec3Lanes::ZERO; 3],
            walk: [Box::new([]), Box::new([]), Box::new([])],
            outsized: Real::INFINITY,
        }
    }

    /// Heap bytes of the cell planes, as stored and as the walk sees them.
    pub(crate) fn planes_bytes(&self) -> usize {
        self.planes
            .iter()
            .chain(&self.walk)
            .map(|p| std::mem::size_of_val(&**p))
            .sum()
    }

    /// The geometry for a finite, non-empty `bounds` and the given cell counts.
    pub(crate) fn new(bounds: Aabb, dims: [u32; 3]) -> Self {
        debug_assert!(!bounds.is_empty() && dims.iter().all(|&n| n >= 1));
        let ext = bounds.extent();
        let mut planes: [Box<[Real]>; 3] = [Box::new([]), Box::new([]), Box::new([])];
        let mut inv_cell = [0.0; 3];
        for a in 0..3 {
            let n = dims[a] as usize;
            let (lo, hi, w) = (bounds.min[a], bounds.max[a], ext[a]);
            let cell = w / n as Real;
            inv_cell[a] = if w > 0.0 { n as Real / w } else { 0.0 };
            let mut p: Vec<Real> = (0..=n).map(|i| (lo + i as Real * cell).min(hi)).collect();
            p[n] = hi;
            planes[a] = p.into_boxed_slice();
        }
        let pad = PAD_ULPS * Real::EPSILON * ext.max_element();
        let walk = planes.clone().map(|p| {
            let mut w = p.into_vec();
            let n = w.len() - 1;
            w[0] = Real::NEG_INFINITY;
            w[n] = Real::INFINITY;
            w.into_boxed_slice()
        });
        let last = Vec3::from_array(dims.map(|n| (n - 1) as Real));
        let mut g = Self {
            bounds,
            dims,
            planes,
            inv_cell,
            pad,
            exact_planes: false,
            entry: bounds,
            slab: SlabTest::Robust,
            lanes: [bounds.min, Vec3::from_array(inv_cell), last].map(Vec3Lanes::from),
            walk,
            outsized: Real::INFINITY,
        };
        g.set_pad(pad);
        g
    }

    /// Whether the cells hold a primitive with box `b`: [`is_gridded`] and
    /// no edge longer than [`Geom::outsized`].
    #[inline(always)]
    pub(crate) fn holds(&self, b: &Aabb) -> bool {
        gridded(b).is_some_and(|(min, max)| !(longest_edge(min, max) > self.outsized))
    }

    /// The same geometry with the extent part of the insertion pad widened
    /// to at least `pad` (a nested grid's, [`crate::nested`]).
    pub(crate) fn with_pad(mut self, pad: Real) -> Self {
        self.set_pad(self.pad.max(pad));
        self
    }

    /// Sets the pad, and with it the entry box and whether
    /// [`Geom::cell_range`] must check the planes: its estimate is off by
    /// at most about two ulps of the coordinates (the widened coordinate,
    /// the plane) plus a few ulps of the extent, which the pad covers when
    /// `8 ε |x|` is below it for every coordinate `x` of the grid box.
    fn set_pad(&mut self, pad: Real) {
        self.pad = pad;
        let b = self.bounds;
        let mag = b.min.abs().max(b.max.abs()).max_element();
        self.exact_planes = !(8.0 * Real::EPSILON * mag < pad);
        self.entry = self.widen(&b);
    }

    /// Box `b` widened by the pad, rounded outwards: the result holds every
    /// point within `pad` of `b`, however large its coordinates.
    #[inline(always)]
    pub(crate) fn widen(&self, b: &Aabb) -> Aabb {
        let p = Vec3::splat(self.pad);
        Aabb::new(
            (b.min - p).to_array().map(next_down).into(),
            (b.max + p).to_array().map(next_up).into(),
        )
    }

    /// True when the grid has no cells.
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.dims[0] == 0
    }

    /// `dims[0]·dims[1]·dims[2]`.
    #[inline]
    pub(crate) fn cell_count(&self) -> u64 {
        self.dims.iter().map(|&n| u64::from(n)).product()
    }

    /// The cell along `axis` that holds coordinate `x`, clamped to
    /// `[0, dims[axis] − 1]`. The guess from the cell size is corrected
    /// against the stored planes, so the answer satisfies
    /// `planes[i] <= x < planes[i + 1]` whenever `x` is inside the grid
    /// (a point on the grid's max face goes to the last cell). NaN maps to 0.
    #[inline(always)]
    pub(crate) fn cell_of(&self, axis: usize, x: Real) -> u32 {
        let planes = &*self.planes[axis];
        let last = self.dims[axis] - 1;
        debug_assert!(planes.len() == last as usize + 2);
        // SAFETY: `planes` has `dims[axis] + 1 >= 2` entries; every index used
        // below stays in `0..=last + 1`.
        unsafe {
            let f = (x - *planes.get_unchecked(0)) * self.inv_cell[axis];
            // The guess from the cell size (NaN and negatives give 0).
            let mut i = if f > 0.0 {
                if f < last as Real {
                    f as u32
                } else {
                    last
                }
            } else {
                0
            };
            // Corrected against the stored planes (rarely more than one step).
            while i > 0 && x < *planes.get_unchecked(i as usize) {
                i -= 1;
            }
            while i < last && x >= *planes.get_unchecked(i as usize + 1) {
                i += 1;
            }
            i
        }
    }

    /// Box `b` under the slab test of this grid's queries ([`Geom::slab`]):
    /// the robust one on `pre`, the ray prepared once per query.
    #[inline(always)]
    pub(crate) fn slab_hit(
        &self,
        b: &Aabb,
        ray: &Ray,
        pre: &SlabRay,
        t_min: Real,
        t_max: Real,
    ) -> Option<(Real, Real)> {
        match self.slab {
            SlabTest::Robust => b.hit_prepared(pre, t_min, t_max),
            SlabTest::Textbook => b.hit_textbook(ray, t_min, t_max),
        }
    }

    /// The inclusive cell range `[lo, hi]` per axis that a primitive box
    /// (widened by the pad) overlaps. The box must be finite and non-empty.
    ///
    /// Computed from the cell size alone, without [`Geom::cell_of`]'s
    /// correction against the stored planes (the build's hottest line): the
    /// two can disagree only for a coordinate within an ulp or two of a
    /// plane (and a few ulps of the grid's extent), which the pad's two
    /// parts cover, so such a primitive is in the cells on both sides.
    #[inline(always)]
    pub(crate) fn cell_range(&self, b: &Aabb) -> ([u32; 3], [u32; 3]) {
        // In lanes, each operation rounded as in `Vec3`s, so the very
        // values of a scalar computation; `max_gt` takes NaN to 0 on every
        // target (its second operand), as a scalar clamp does.
        let [min, inv, last] = self.lanes;
        let pad = Vec3Lanes::splat(self.pad);
        let (x0, x1) = (Vec3Lanes::from(b.min) - pad, Vec3Lanes::from(b.max) + pad);
        let clamp = |v: Vec3Lanes| v.max_gt(Vec3Lanes::ZERO).min_lt(last);
        let mut lo = truncate(clamp((x0 - min) * inv));
        let mut hi = truncate(clamp((x1 - min) * inv));
        if self.exact_planes {
            self.exact_ranges(&mut lo, &mut hi, b);
        }
        (lo, hi)
    }

    /// [`Geom::exact_range`] on the three axes of box `b`, whose guessed
    /// ranges are `[lo, hi]`: the first test of each of its four loops
    /// inline, and the loops only on an axis where one of them moves a
    /// guess (seldom: a guess is off by a cell only for a box within a pad
    /// or so of a plane).
    #[inline(always)]
    fn exact_ranges(&self, lo: &mut [u32; 3], hi: &mut [u32; 3], b: &Aabb) {
        let pad = self.range_pad();
        for a in 0..3 {
            let p = &*self.planes[a];
            let (l, h, last) = (lo[a], hi[a], self.dims[a] - 1);
            let (x0, x1) = (b.min[a], b.max[a]);
            let (down, up) = (reaches_down(p, x0, pad), reaches_up(p, x1, pad));
            let settled = (l == 0 || !down(l - 1))
                && (l == last || down(l))
                && (h == last || !up(h + 1))
                && (h == 0 || up(h));
            if settled {
                hi[a] = h.max(l);
            } else {
                (lo[a], hi[a]) = self.exact_range(a, l, h, x0, x1);
            }
        }
    }

    /// The pad that [`Geom::exact_range`] compares the differences of a
    /// box's faces and the planes with: enlarged by `4ε`, see there.
    #[inline(always)]
    fn range_pad(&self) -> Real {
        self.pad * (1.0 + 4.0 * Real::EPSILON)
    }

    /// The cells along `axis` that the interval `[x0, x1]` widened by the
    /// pad overlaps, found from the guesses `lo` and `hi` by comparing with
    /// the stored planes: cell `i` is in when `x0 − planes[i + 1] <= pad`
    /// and `planes[i] − x1 <= pad`. Each difference is rounded once, by a
    /// relative `ε/2` at most, so comparing with the pad enlarged by `4ε`
    /// can only let in a cell too many, never leave one out; and no
    /// widened coordinate is rounded to an ulp of where the scene lies.
    #[inline(never)]
    fn exact_range(&self, axis: usize, mut lo: u32, mut hi: u32, x0: Real, x1: Real) -> (u32, u32) {
        let p = &*self.planes[axis];
        let last = self.dims[axis] - 1;
        let pad = self.range_pad();
        let (down, up) = (reaches_down(p, x0, pad), reaches_up(p, x1, pad));
        while lo > 0 && down(lo - 1) {
            lo -= 1;
        }
        while lo < last && !down(lo) {
            lo += 1;
        }
        while hi < last && up(hi + 1) {
            hi += 1;
        }
        while hi > 0 && !up(hi) {
            hi -= 1;
        }
        (lo, hi.max(lo))
    }

    /// Calls `f` with the row-major index of every cell of the inclusive
    /// range `[lo, hi]` (as [`Geom::cell_range`] gives it).
    #[inline]
    pub(crate) fn for_each_cell(&self, (lo, hi): ([u32; 3], [u32; 3]), mut f: impl FnMut(usize)) {
        let [nx, ny, _] = self.dims.map(|d| d as usize);
        for k in lo[2] as usize..=hi[2] as usize {
            for j in lo[1] as usize..=hi[1] as usize {
                for i in lo[0] as usize..=hi[0] as usize {
                    f(i + nx * (j + ny * k));
                }
            }
        }
    }

    /// The box of cell `idx`, widened by the pad: the region a primitive
    /// must touch to be inserted into the cell under exact insertion.
    #[inline]
    pub(crate) fn padded_cell_box(&self, idx: [u32; 3]) -> Aabb {
        self.widen(&self.cell_box(idx))
    }

    /// The `(i, j, k)` of the cell with row-major index `c`.
    pub(crate) fn index_of(&self, c: usize) -> [u32; 3] {
        let c = c as u32;
        let [nx, ny, _] = self.dims;
        [c % nx, (c / nx) % ny, c / (nx * ny)]
    }

    /// The unpadded box of cell `idx`.
    pub(crate) fn cell_box(&self, idx: [u32; 3]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for (a, &i) in idx.iter().enumerate() {
            b.min[a] = self.planes[a][i as usize];
            b.max[a] = self.planes[a][i as usize + 1];
        }
        b
    }
}

/// Whether cell `i` of the axis with `planes` reaches down to `x0` widened
/// by `pad`: `x0 − planes[i + 1] <= pad` (the test of a range's low end in
/// [`Geom::exact_range`]).
#[inline(always)]
fn reaches_down(planes: &[Real], x0: Real, pad: Real) -> impl Fn(u32) -> bool + '_ {
    #[inline(always)]
    move |i| x0 - planes[i as usize + 1] <= pad
}

/// Whether cell `i` of the axis with `planes` reaches up to `x1` widened
/// by `pad`: `planes[i] − x1 <= pad` (the test of a range's high end).
#[inline(always)]
fn reaches_up(planes: &[Real], x1: Real, pad: Real) -> impl Fn(u32) -> bool + '_ {
    #[inline(always)]
    move |i| planes[i as usize] - x1 <= pad
}

/// How many cells the inclusive range `[lo, hi]` of [`Geom::cell_range`]
/// holds: how many times [`Geom::for_each_cell`] calls its `f`.
#[inline]
pub(crate) fn range_cells((lo, hi): ([u32; 3], [u32; 3])) -> u64 {
    (0..3)
        .map(|a| u64::from((hi[a] + 1).saturating_sub(lo[a])))
        .product()
}

/// The largest value below `x` (`x` itself for NaN and `−∞`).
#[inline(always)]
pub(crate) fn next_down(x: Real) -> Real {
    -next_up(-x)
}

/// The smallest value above `x` (`x` itself for NaN and `+∞`).
#[inline(always)]
pub(crate) fn next_up(x: Real) -> Real {
    if x.is_nan() || x == Real::INFINITY {
        return x;
    }
    if x == 0.0 {
        return Real::from_bits(1);
    }
    let b = x.to_bits();
    Real::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

/// `x` as an `f64` (a no-op with the `f64` feature).
#[inline]
#[allow(clippy::useless_conversion)]
pub(crate) fn wide(x: Real) -> f64 {
    f64::from(x)
}

/// Replaces a meaningless `m` (NaN, infinite, zero or negative) by the
/// lecture's 2.
pub(crate) fn sanitize_m(m: Real) -> f64 {
    let m = wide(m);
    if m.is_finite() && m > 0.0 {
        m
    } else {
        2.0
    }
}

/// Cells per axis for `n` primitives in a box of extent `ext`, after the
/// lecture: `s = cbrt(wx·wy·wz / n)`, `n_a = floor(m·w_a / s) + 1`.
///
/// Degenerate extents are handled on purpose. An axis of zero extent, or one
/// so thin that it would get a single cell anyway, is left out of `s`, which
/// is then taken from the remaining axes (`s = sqrt(wx·wy / n)` for a flat
/// scene, `wx / n` for a line), so a flat scene does not get a tiny `s` and
/// millions of cells. With no extent at all (one point) the grid has one cell.
/// The total is then scaled down uniformly until it is at most `max_cells`.
pub(crate) fn resolution(ext: [f64; 3], n: usize, m: f64, max_cells: u64) -> [u32; 3] {
    let max_cells = max_cells.clamp(1, HARD_MAX_CELLS);
    let n = n.max(1) as f64;
    let mut active = [false; 3];
    for a in 0..3 {
        active[a] = ext[a].is_finite() && ext[a] > 0.0;
    }
    let mut s = 0.0;
    // Each round drops the axes that would get one cell; at most three rounds.
    for _ in 0..3 {
        let k = active.iter().filter(|&&x| x).count();
        if k == 0 {
            break;
        }
        let prod: f64 = (0..3).filter(|&a| active[a]).map(|a| ext[a]).product();
        s = (prod / n).powf(1.0 / k as f64);
        let mut dropped = false;
        for a in 0..3 {
            if active[a] && !(m * ext[a] / s >= 1.0) {
                active[a] = false;
                dropped = true;
            }
        }
        if !dropped {
            break;
        }
    }
    let mut dims = [1u64; 3];
    for a in 0..3 {
        if active[a] && s > 0.0 {
            let c = (m * ext[a] / s).floor() + 1.0;
            // `as` saturates (and maps NaN to 0); keep within Morton range.
            dims[a] = (c as u64).clamp(1, u64::from(morton::MAX_AXIS_CELLS));
        }
    }
    cap_cells(dims, max_cells)
}

/// Scales `dims` down uniformly until their product is at most `max_cells`
/// (at least one cell per axis).
pub(crate) fn cap_cells(mut dims: [u64; 3], max_cells: u64) -> [u32; 3] {
    let max_cells = max_cells.max(1);
    let total = |d: &[u64; 3]| d[0].saturating_mul(d[1]).saturating_mul(d[2]);
    if total(&dims) > max_cells {
        let f = (max_cells as f64 / total(&dims) as f64).cbrt();
        for d in &mut dims {
            *d = ((*d as f64 * f).floor() as u64).max(1);
        }
        // Rounding may leave the product a little too large: trim the longest axis.
        while total(&dims) > max_cells {
            let a = (0..3).max_by_key(|&a| dims[a]).unwrap_or(0);
            dims[a] -= 1;
        }
    }
    dims.map(|d| d.clamp(1, u64::from(morton::MAX_AXIS_CELLS)) as u32)
}

/// True when a primitive box can be placed in the grid: finite and not empty.
#[inline]
pub(crate) fn is_gridded(b: &Aabb) -> bool {
    gridded(b).is_some()
}

/// The smallest box holding `a` and `b`, each a box of a gridded primitive
/// (finite, `min <= max`: [`is_gridded`]), a box made of such boxes, or
/// [`Aabb::EMPTY`] (whose infinite corners leave the other box as it is).
/// [`Aabb::union`] without its tests for empty boxes, which such boxes
/// never are, for the build's folds over many boxes (3–4% of a triangle
/// scene's build, measured).
#[inline(always)]
pub(crate) fn hull(a: Aabb, b: &Aabb) -> Aabb {
    Aabb::new(a.min.min(b.min), a.max.max(b.max))
}

/// The longest edge of the box with corners `min` and `max` (as
/// [`gridded`] gives them).
#[inline(always)]
pub(crate) fn longest_edge(min: Lanes, max: Lanes) -> Real {
    (max - min).max_element()
}

/// The corners of a primitive box as [`Lanes`], if [`is_gridded`].
#[inline(always)]
pub(crate) fn gridded(b: &Aabb) -> Option<(Lanes, Lanes)> {
    let (min, max) = (b.min.extend(0.0), b.max.extend(0.0));
    let inf = Lanes::INFINITY;
    (min.abs().cmplt(inf) & max.abs().cmplt(inf) & min.cmple(max))
        .all()
        .then_some((min, max))
}

/// The lanes of `v`, each in `[0, 2^21]` (a cell index clamped to the
/// last cell), truncated to integers: one conversion for the three on x86.
#[inline(always)]
fn truncate(v: Vec3Lanes) -> [u32; 3] {
    #[cfg(all(not(feature = "f64"), target_arch = "x86_64"))]
    {
        use std::arch::x86_64::_mm_cvttps_epi32;
        // SAFETY: SSE2 is part of x86-64; `cvttps2dq` truncates each lane,
        // and the lanes fit an `i32`, so the bits are the integers'.
        let i: [i32; 4] = unsafe { std::mem::transmute(_mm_cvttps_epi32(v.into())) };
        [i[0] as u32, i[1] as u32, i[2] as u32]
    }
    #[cfg(not(all(not(feature = "f64"), target_arch = "x86_64")))]
    {
        // SAFETY: finite and within an `i32` (above). (A signed conversion
        // is one instruction, an unsigned one several.)
        let int = |x: Real| unsafe { x.to_int_unchecked::<i32>() as u32 };
        [int(v.x), int(v.y), int(v.z)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reach_covers_origins_within_its_distance_of_every_point() {
        let span = Aabb::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.5));
        let pad = RAY_ULPS * Real::EPSILON * 10.0;
        let r = Reach::new(&span, pad, 2.0 * pad);
        // 9.9 from the far corner on x and y, inside on z.
        assert!(r.covers(Vec3::new(8.9, -7.9, 0.25)));
        assert!(!r.covers(Vec3::new(9.5, 0.0, 0.0)));
        assert!(!r.covers(Vec3::new(0.0, 0.0, -9.6)));
        assert!(!r.covers(Vec3::new(Real::NAN, 0.0, 0.0)));
        assert!(!r.covers(Vec3::new(0.0, Real::INFINITY, 0.0)));
        // A pad as wide as the parent's covers every ray the parent does.
        let all = Reach::new(&span, pad, pad);
        assert!(all.covers(Vec3::splat(1e30)) && !all.covers(Vec3::splat(Real::NAN)));
    }

    #[test]
    fn lecture_formula_on_a_cube() {
        // 1000 objects in a 2-cube: s = cbrt(8/1000) = 0.2, n = floor(2·2/0.2) + 1 = 21.
        let d = resolution([2.0; 3], 1000, 2.0, 1 << 26);
        assert!(d.iter().all(|&n| n == 21 || n == 20), "{d:?}");
    }

    #[test]
    fn flat_scene_uses_two_axes() {
        let d = resolution([1.0, 1.0, 0.0], 100, 2.0, 1 << 26);
        assert_eq!(d[2], 1);
        assert!(d[0] >= 20 && d[0] <= 21, "{d:?}");
        let thin = resolution([1.0, 1.0, 1e-9], 100, 2.0, 1 << 26);
        assert_eq!(thin, d);
    }

    #[test]
    fn point_and_line() {
        assert_eq!(resolution([0.0; 3], 10, 2.0, 1 << 26), [1, 1, 1]);
        assert_eq!(resolution([4.0, 0.0, 0.0], 10, 2.0, 1 << 26), [21, 1, 1]);
    }

    #[test]
    fn cap_is_respected() {
        let d = resolution([1.0; 3], 1_000_000, 2.0, 1000);
        assert!(d.iter().map(|&n| u64::from(n)).product::<u64>() <= 1000);
        assert_eq!(resolution([1.0; 3], 5, 2.0, 0), [1, 1, 1]);
        let huge = resolution([1e30, 1e-30, 1.0], usize::MAX, wide(Real::MAX), u64::MAX);
        assert!(huge.iter().map(|&n| u64::from(n)).product::<u64>() <= HARD_MAX_CELLS);
    }

    #[test]
    fn range_cells_counts_what_for_each_cell_visits() {
        let g = Geom::new(Aabb::new(Vec3::ZERO, Vec3::new(8.0, 4.0, 2.0)), [8, 4, 2]);
        let boxes = [
            Aabb::new(Vec3::splat(0.5), Vec3::splat(0.5)),
            Aabb::new(Vec3::new(1.5, 0.5, 0.5), Vec3::new(6.5, 3.5, 1.5)),
            Aabb::new(Vec3::splat(-10.0), Vec3::splat(10.0)),
            Aabb::EMPTY,
        ];
        for b in boxes {
            let range = g.cell_range(&b);
            let mut visits = 0;
            g.for_each_cell(range, |_| visits += 1);
            assert_eq!(range_cells(range), visits, "{b:?}");
        }
        // An empty range (`hi < lo` on an axis) holds no cell.
        assert_eq!(range_cells(([3, 0, 0], [2, 5, 5])), 0);
    }

    proptest::proptest! {
        /// Where the planes are checked (a grid far from the origin), a
        /// box's range on each axis is exactly the cells its definition
        /// admits, `x0 − planes[i + 1] <= pad` and `planes[i] − x1 <= pad`
        /// (the pad enlarged by `4ε`), whether the box's faces lie on a
        /// plane, a few ulps off one, or in the upper half of a cell.
        #[test]
        fn far_cell_ranges_are_the_cells_the_pad_admits(
            offset in -2.0e5f64..2.0e5,
            ext in proptest::array::uniform3(0.5f64..64.0),
            dims in proptest::array::uniform3(1u32..20),
            faces in proptest::array::uniform3(
                (0u32..21, -3i32..4, 0u32..21, -3i32..4, 0.0f64..1.0, 0.0f64..1.0)
            ),
        ) {
            let min = Vec3::splat(1.0e5 + offset as Real);
            let g = Geom::new(Aabb::new(min, min + Vec3::from_array(ext.map(|e| e as Real))), dims);
            proptest::prop_assume!(g.exact_planes);
            // A coordinate `ulps` ulps from plane `i` or from the point `at`
            // of the way into cell `i` (`at` of 0.5 or more), clamped to
            // the grid.
            let coord = |a: usize, i: u32, ulps: i32, at: f64, on_plane: bool| {
                let p = &g.planes[a];
                let i = i.min(dims[a]) as usize;
                let mut x = if on_plane || i == dims[a] as usize {
                    p[i]
                } else {
                    p[i] + (p[i + 1] - p[i]) * at as Real
                };
                for _ in 0..ulps.unsigned_abs() {
                    x = if ulps > 0 { next_up(x) } else { next_down(x) };
                }
                x.clamp(g.bounds.min[a], g.bounds.max[a])
            };
            let mut b = Aabb::EMPTY;
            for (a, &(i0, u0, i1, u1, at0, at1)) in faces.iter().enumerate() {
                let x0 = coord(a, i0, u0, at0, at0 < 0.5);
                let x1 = coord(a, i1, u1, at1, at1 < 0.5);
                b.min[a] = x0.min(x1);
                b.max[a] = x0.max(x1);
            }
            let (lo, hi) = g.cell_range(&b);
            let pad = g.range_pad();
            for a in 0..3 {
                let p = &g.planes[a];
                let admitted: Vec<u32> = (0..dims[a])
                    .filter(|&i| {
                        b.min[a] - p[i as usize + 1] <= pad && p[i as usize] - b.max[a] <= pad
                    })
                    .collect();
                let want = (admitted[0], *admitted.last().unwrap());
                proptest::prop_assert_eq!(want.1 - want.0 + 1, admitted.len() as u32);
                proptest::prop_assert_eq!((lo[a], hi[a]), want, "axis {} of {:?}", a, b);
            }
        }
    }

    proptest::proptest! {
        /// Near the origin (no plane checks), a box's range on each axis is
        /// the scalar formula's, `(x ∓ pad − min) · inv` clamped to
        /// `[0, dims − 1]` and truncated, for boxes inside, across and
        /// beyond the grid: the lanes round as scalars do.
        #[test]
        fn cell_ranges_are_the_scalar_formulas(
            min in proptest::array::uniform3(-50.0f64..50.0),
            ext in proptest::array::uniform3(0.01f64..64.0),
            dims in proptest::array::uniform3(1u32..40),
            from in proptest::array::uniform3(-1.5f64..2.5),
            size in proptest::array::uniform3(0.0f64..1.5),
        ) {
            let min = Vec3::from_array(min.map(|x| x as Real));
            let g = Geom::new(Aabb::new(min, min + Vec3::from_array(ext.map(|e| e as Real))), dims);
            proptest::prop_assume!(!g.exact_planes);
            let e = g.bounds.extent();
            let at = |f: [f64; 3]| {
                Vec3::from_array(std::array::from_fn(|a| g.bounds.min[a] + e[a] * f[a] as Real))
            };
            let b = Aabb::new(at(from), at(std::array::from_fn(|a| from[a] + size[a])));
            let (lo, hi) = g.cell_range(&b);
            for a in 0..3 {
                let last = (dims[a] - 1) as Real;
                let cell = |x: Real| ((x - g.bounds.min[a]) * g.inv_cell[a]).clamp(0.0, last) as u32;
                let want = (cell(b.min[a] - g.pad), cell(b.max[a] + g.pad));
                proptest::prop_assert_eq!((lo[a], hi[a]), want, "axis {} of {:?}", a, b);
            }
        }
    }

    #[test]
    fn cell_of_agrees_with_planes() {
        let g = Geom::new(Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)), [7, 3, 1]);
        for a in 0..3 {
            let n = g.dims[a];
            for i in 0..n {
                assert_eq!(g.cell_of(a, g.planes[a][i as usize]), i);
            }
            assert_eq!(g.cell_of(a, 1.0), n - 1, "max face clamps to the last cell");
            assert_eq!(g.cell_of(a, -5.0), 0);
            assert_eq!(g.cell_of(a, Real::NAN), 0);
            assert_eq!(g.cell_of(a, Real::INFINITY), n - 1);
        }
    }
}
