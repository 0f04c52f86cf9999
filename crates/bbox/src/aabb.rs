use crate::math::{gamma, LaneChoice, Real, Vec3, Vec3Lanes};
use crate::Ray;

/// An axis-aligned box `[min.x, max.x] × [min.y, max.y] × [min.z, max.z]`.
///
/// Invariant: the box is *empty* exactly when `min[a] > max[a]` on some axis.
/// [`Aabb::EMPTY`] has `min = +∞` and `max = −∞`, so a union needs no special
/// case for the first box (pbrt's `Bounds3()`). A box with `min == max` on an
/// axis is not empty: it is a zero-thickness box (a flat mesh, a point).
/// All queries treat the box as **closed**: its faces belong to it.
///
/// ```
/// use gridrt_bbox::{Aabb, Vec3};
/// let b = Aabb::EMPTY.grow(Vec3::ZERO).grow(Vec3::new(1.0, 2.0, 3.0));
/// assert_eq!(b, Aabb::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)));
/// assert_eq!(b.longest_axis(), 2);
/// assert!(b.contains(Vec3::new(1.0, 2.0, 3.0)));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: Vec3,
    /// The corner with the largest coordinates.
    pub max: Vec3,
}

impl Default for Aabb {
    /// The empty box.
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box: `min = +∞`, `max = −∞`. The identity of [`Aabb::union`].
    pub const EMPTY: Self = Self {
        min: Vec3::splat(Real::INFINITY),
        max: Vec3::splat(Real::NEG_INFINITY),
    };

    /// A box from its two corners, taken as given (`min` is not sorted
    /// against `max`; pass `min > max` on an axis and the box is empty).
    #[inline]
    #[must_use]
    pub const fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The smallest box holding every point; [`Aabb::EMPTY`] for none.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let b = Aabb::from_points([Vec3::new(1.0, 5.0, -1.0), Vec3::new(-2.0, 0.0, 4.0)]);
    /// assert_eq!(b, Aabb::new(Vec3::new(-2.0, 0.0, -1.0), Vec3::new(1.0, 5.0, 4.0)));
    /// assert_eq!(Aabb::from_points([]), Aabb::EMPTY);
    /// ```
    #[must_use]
    pub fn from_points<I: IntoIterator<Item = Vec3>>(points: I) -> Self {
        points.into_iter().fold(Self::EMPTY, Self::grow)
    }

    /// True when the box holds no point (`min > max` on some axis).
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// assert!(Aabb::EMPTY.is_empty());
    /// assert!(Aabb::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 1.0)).is_empty());
    /// assert!(!Aabb::new(Vec3::ONE, Vec3::ONE).is_empty()); // a point box
    /// ```
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// The smallest box holding both boxes.
    ///
    /// An empty operand is ignored, whatever its corners: a box inverted on
    /// one axis only (say `min.x > max.x` but a wide y range) holds no point,
    /// so it must not widen the result on its other axes.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// let b = Aabb::new(Vec3::splat(2.0), Vec3::splat(3.0));
    /// assert_eq!(a.union(b), Aabb::new(Vec3::ZERO, Vec3::splat(3.0)));
    /// assert_eq!(a.union(Aabb::EMPTY), a);
    /// ```
    #[inline]
    #[must_use]
    pub fn union(self, other: Self) -> Self {
        if other.is_empty() {
            return self;
        }
        if self.is_empty() {
            return other;
        }
        Self::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// The smallest box holding this box and the point.
    ///
    /// Growing an empty box (of any corners) gives the point box `[p, p]`.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let p = Vec3::new(1.0, -2.0, 3.0);
    /// assert_eq!(Aabb::EMPTY.grow(p), Aabb::new(p, p));
    /// assert!(Aabb::EMPTY.grow(p).grow(Vec3::ZERO).contains(p));
    /// ```
    #[inline]
    #[must_use]
    pub fn grow(self, p: Vec3) -> Self {
        if self.is_empty() {
            return Self::new(p, p);
        }
        Self::new(self.min.min(p), self.max.max(p))
    }

    /// `max − min`: the box's size per axis (zero for an empty box).
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 2.0));
    /// assert_eq!(b.extent(), Vec3::new(2.0, 3.0, 0.0));
    /// assert_eq!(Aabb::EMPTY.extent(), Vec3::ZERO);
    /// ```
    #[inline]
    #[must_use]
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// The centre of the box (meaningless for an empty box).
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 2.0));
    /// assert_eq!(b.centroid(), Vec3::new(0.0, 1.5, 2.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn centroid(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The total area of the six faces (zero for an empty box).
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
    /// assert_eq!(b.surface_area(), 22.0);
    /// assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn surface_area(&self) -> Real {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// True when the point lies in the closed box.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// assert!(b.contains(Vec3::ONE)); // corners belong to the box
    /// assert!(!b.contains(Vec3::new(0.5, 0.5, 1.5)));
    /// assert!(!Aabb::EMPTY.contains(Vec3::ZERO));
    /// ```
    #[inline]
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// True when the closed boxes share at least one point (touching counts).
    /// An empty box overlaps nothing, not even itself.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// let touching = Aabb::new(Vec3::new(1.0, 0.0, 0.0), Vec3::splat(2.0));
    /// assert!(a.overlaps(&touching) && touching.overlaps(&a));
    /// assert!(!a.overlaps(&Aabb::EMPTY));
    /// ```
    #[inline]
    #[must_use]
    pub fn overlaps(&self, other: &Self) -> bool {
        // For a box empty on one axis only, the corner test alone can pass
        // (`min.x > max.x` with both inside `other`'s x range), hence the
        // explicit emptiness checks.
        !self.is_empty()
            && !other.is_empty()
            && self.min.cmple(other.max).all()
            && other.min.cmple(self.max).all()
    }

    /// The axis (0 = x, 1 = y, 2 = z) along which the box is longest; the
    /// lowest axis on ties.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Vec3};
    /// assert_eq!(Aabb::new(Vec3::ZERO, Vec3::new(1.0, 3.0, 2.0)).longest_axis(), 1);
    /// assert_eq!(Aabb::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 2.0)).longest_axis(), 1);
    /// assert_eq!(Aabb::new(Vec3::ZERO, Vec3::ONE).longest_axis(), 0);
    /// ```
    #[inline]
    #[must_use]
    pub fn longest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// Robust slab test: the parametric interval `(t_enter, t_exit)` where the
    /// ray lies in the box, clipped to `[t_min, t_max]`, or `None` on a miss.
    ///
    /// The interval is **conservative**: the exit is widened by 2·γ(3) of its
    /// magnitude (Ize 2013, "Robust BVH Ray Traversal"; pbrt-v4
    /// `Bounds3::IntersectP`), so a ray that truly touches the box is never
    /// culled by rounding. Hard cases are handled on purpose:
    ///
    /// - A direction component of ±0 (or one so small that its reciprocal
    ///   overflows) means the ray never crosses that slab: it hits only if its
    ///   origin lies within the slab, faces included. We test that directly
    ///   instead of computing `0·∞ = NaN`, so an origin exactly on a slab
    ///   plane, or a ray lying in a face, always resolves the same way.
    /// - A tiny but normal-reciprocal direction component can make a slab's
    ///   t values overflow to ±∞; they are still ordered, never NaN. With
    ///   `t_max = ∞` the answer may then be `(∞, ∞)`: the ray does reach the
    ///   box, but beyond the largest finite [`Real`].
    /// - An empty box is always missed; a zero-thickness box is hit.
    /// - `t_min == t_max` asks whether the single point `ray.at(t_min)` is in
    ///   the box; `t_min > t_max` is always a miss.
    ///
    /// On a hit, `t_min <= t_enter <= t_exit <= t_max` and neither is NaN
    /// (given a non-NaN range). A ray or box with NaN components gets an
    /// unspecified answer, but never a NaN interval.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Ray, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// // A ray lying in the face x = 0, direction (-0, 0, -1).
    /// let r = Ray::new(Vec3::new(0.0, 0.5, 2.0), Vec3::new(-0.0, 0.0, -1.0));
    /// assert_eq!(b.hit(&r, 0.0, 10.0).map(|t| t.0), Some(1.0));
    /// // The same ray moved to x = -1 misses: it runs beside the face.
    /// let r = Ray::new(Vec3::new(-1.0, 0.5, 2.0), Vec3::new(-0.0, 0.0, -1.0));
    /// assert_eq!(b.hit(&r, 0.0, 10.0), None);
    /// ```
    ///
    /// Always inlined: every grid query starts with it, and as a call it
    /// was a few per cent of a query's time.
    #[inline(always)]
    #[must_use]
    pub fn hit(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
        self.hit_prepared(&SlabRay::new(ray), t_min, t_max)
    }

    /// [`Aabb::hit`] for a ray prepared once for many boxes: the same
    /// operations in the same order, so the very same answer.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Ray, SlabRay, Vec3};
    /// let r = Ray::new(Vec3::new(0.0, 0.5, 2.0), Vec3::new(-0.0, 0.0, -1.0));
    /// let pre = SlabRay::new(&r);
    /// for b in [Aabb::new(Vec3::ZERO, Vec3::ONE), Aabb::new(Vec3::X, Vec3::splat(2.0))] {
    ///     assert_eq!(b.hit_prepared(&pre, 0.0, 10.0), b.hit(&r, 0.0, 10.0));
    /// }
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn hit_prepared(&self, ray: &SlabRay, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
        debug_assert!(
            !t_min.is_nan() && !t_max.is_nan(),
            "t range must not be NaN"
        );
        let widen = 2.0 * gamma(3);
        // The three slabs at once in SIMD lanes (straight-line code, no early
        // exits, so that a loop of tests pipelines well; `cargo bench -p
        // gridrt-bbox` measures it), then folded into the range axis by axis.
        let (lo, hi) = (Vec3Lanes::from(self.min), Vec3Lanes::from(self.max));
        let (o, inv) = (ray.origin, ray.inv);
        let empty = lo.cmpgt(hi).any();
        let t_lo = (lo - o) * inv;
        let t_hi = (hi - o) * inv;
        // Swapped where `t_lo > t_hi`: one choice each.
        let near = t_hi.min_lt(t_lo);
        let far = t_lo.max_gt(t_hi);
        // Widen the exit by 2·γ(3) of its magnitude. A tiny direction
        // component can overflow `far` to −∞, and then `far + |far|·w` is
        // −∞ + ∞ = NaN, which the comparisons below would silently skip (a
        // false hit): `max_gt` returns its second operand, −∞, when the
        // first is NaN, on every target (`max` propagates the NaN on some).
        let mut far = (far + far.abs() * widen).max_gt(far);
        let mut near = near;
        if ray.parallel {
            // Parallel to a slab (an infinite reciprocal): inside it for all
            // t, or never. The range test is false for a NaN origin too.
            let parallel = inv.abs().cmpeq(Vec3Lanes::INFINITY);
            let inside = lo.cmple(o) & o.cmple(hi);
            let (all, none) = (Vec3Lanes::INFINITY, Vec3Lanes::NEG_INFINITY);
            near = Vec3Lanes::select(parallel, Vec3Lanes::select(inside, none, all), near);
            far = Vec3Lanes::select(parallel, Vec3Lanes::select(inside, all, none), far);
        }
        // Written so that a NaN `near` or `far` leaves t0/t1 unchanged.
        let (mut t0, mut t1) = (t_min, t_max);
        for (near, far) in near.to_array().into_iter().zip(far.to_array()) {
            t0 = if near > t0 { near } else { t0 };
            t1 = if far < t1 { far } else { t1 };
        }
        if empty {
            return None;
        }
        if t0 <= t1 {
            Some((t0, t1))
        } else {
            None
        }
    }

    /// The textbook slab test (Williams et al. 2005; Suffern's `BBox::hit`):
    /// the reciprocals go straight into min/max, with no special case and
    /// no widening. For measuring what [`Aabb::hit`] costs, behind
    /// [`SlabTest::Textbook`]; never the default.
    ///
    /// What it risks: an origin exactly on a slab plane with a zero
    /// direction component computes `0·∞ = NaN`, and how `min`/`max`
    /// treat that NaN decides the answer (a ray lying in a face of the box
    /// can be culled); the exit is not widened, so a ray that touches the
    /// box within rounding can be culled too.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Ray, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
    /// assert_eq!(b.hit_textbook(&r, 0.0, 10.0), Some((1.0, 2.0)));
    /// ```
    #[inline]
    #[must_use]
    pub fn hit_textbook(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
        let t_lo = (self.min - ray.origin) * ray.inv_dir;
        let t_hi = (self.max - ray.origin) * ray.inv_dir;
        let near = t_lo.min(t_hi).max_element().max(t_min);
        let far = t_lo.max(t_hi).min_element().min(t_max);
        (near <= far).then_some((near, far))
    }

    /// The slab test `test` names: [`Aabb::hit`] or [`Aabb::hit_textbook`].
    #[inline]
    #[must_use]
    pub fn hit_with(
        &self,
        test: SlabTest,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
    ) -> Option<(Real, Real)> {
        match test {
            SlabTest::Robust => self.hit(ray, t_min, t_max),
            SlabTest::Textbook => self.hit_textbook(ray, t_min, t_max),
        }
    }
}

/// A ray as the robust slab test reads it, prepared once to be tested
/// against many boxes ([`Aabb::hit_prepared`]): its origin and reciprocal
/// direction in SIMD lanes, and whether it is parallel to some slab (an
/// infinite reciprocal), the rare case that needs more than the lanes.
#[derive(Clone, Copy, Debug)]
pub struct SlabRay {
    origin: Vec3Lanes,
    inv: Vec3Lanes,
    parallel: bool,
}

impl SlabRay {
    /// `ray` prepared for the slab test.
    #[inline(always)]
    #[must_use]
    pub fn new(ray: &Ray) -> Self {
        let inv = Vec3Lanes::from(ray.inv_dir);
        Self {
            origin: Vec3Lanes::from(ray.origin),
            inv,
            parallel: inv.abs().cmpeq(Vec3Lanes::INFINITY).any(),
        }
    }
}

/// Which ray–box slab test a query uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SlabTest {
    /// [`Aabb::hit`]: parallel slabs tested directly (no `0·∞`), the exit
    /// widened by 2·γ(3). The default.
    #[default]
    Robust,
    /// [`Aabb::hit_textbook`]: reciprocals straight into min/max. Can cull
    /// rays that lie in a face of the box or graze it.
    Textbook,
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: Real = Real::INFINITY;

    fn unit() -> Aabb {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    /// Empty on the x axis only, but wide on y and z.
    fn inverted_x() -> Aabb {
        Aabb::new(Vec3::new(2.0, -10.0, -10.0), Vec3::new(1.0, 10.0, 10.0))
    }

    #[test]
    fn default_is_empty() {
        assert_eq!(Aabb::default(), Aabb::EMPTY);
        assert!(Aabb::EMPTY.is_empty());
        assert!(inverted_x().is_empty());
        assert!(!unit().is_empty());
        assert!(!Aabb::new(Vec3::ONE, Vec3::ONE).is_empty());
    }

    #[test]
    fn empty_is_the_identity_of_union() {
        assert_eq!(Aabb::EMPTY.union(unit()), unit());
        assert_eq!(unit().union(Aabb::EMPTY), unit());
        assert!(Aabb::EMPTY.union(Aabb::EMPTY).is_empty());
    }

    #[test]
    fn union_ignores_a_box_empty_on_one_axis() {
        assert_eq!(unit().union(inverted_x()), unit());
        assert_eq!(inverted_x().union(unit()), unit());
    }

    #[test]
    fn grow_of_an_empty_box_is_the_point() {
        let p = Vec3::new(0.5, 0.5, 0.5);
        assert_eq!(inverted_x().grow(p), Aabb::new(p, p));
        assert_eq!(Aabb::EMPTY.grow(p), Aabb::new(p, p));
        assert_eq!(unit().grow(p), unit());
        assert_eq!(
            unit().grow(Vec3::splat(2.0)),
            Aabb::new(Vec3::ZERO, Vec3::splat(2.0))
        );
    }

    #[test]
    fn empty_boxes_overlap_nothing() {
        assert!(!inverted_x().overlaps(&unit()));
        assert!(!unit().overlaps(&inverted_x()));
        assert!(!Aabb::EMPTY.overlaps(&Aabb::EMPTY));
        assert!(unit().overlaps(&unit()));
    }

    #[test]
    fn overlaps_counts_touching_and_rejects_gaps() {
        let right = Aabb::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0));
        let gap = Aabb::new(Vec3::new(1.5, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0));
        assert!(unit().overlaps(&right));
        assert!(!unit().overlaps(&gap));
        assert!(!gap.overlaps(&unit()));
    }

    #[test]
    fn measures_of_empty_and_flat_boxes() {
        assert_eq!(Aabb::EMPTY.extent(), Vec3::ZERO);
        assert_eq!(inverted_x().extent(), Vec3::ZERO);
        assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
        let flat = Aabb::new(Vec3::ZERO, Vec3::new(2.0, 3.0, 0.0));
        assert_eq!(flat.surface_area(), 12.0);
        assert_eq!(flat.longest_axis(), 1);
        assert_eq!(
            Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 5.0)).longest_axis(),
            2
        );
    }

    #[test]
    fn contains_is_closed() {
        let b = unit();
        for p in [Vec3::ZERO, Vec3::ONE, Vec3::new(0.0, 1.0, 0.5)] {
            assert!(b.contains(p), "{p:?}");
        }
        for p in [
            Vec3::new(-Real::EPSILON, 0.5, 0.5),
            Vec3::new(0.5, 1.0 + Real::EPSILON, 0.5),
        ] {
            assert!(!b.contains(p), "{p:?}");
        }
    }

    #[test]
    fn textbook_test_culls_a_ray_in_a_face_that_the_robust_test_keeps() {
        // Origin on the plane x = 0 with a zero x component: (0 − 0)·∞ is
        // NaN in the textbook test, and `min`/`max` drop the box.
        let r = Ray::new(Vec3::new(0.0, 0.5, -1.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(unit().hit(&r, 0.0, INF).map(|t| t.0), Some(1.0));
        assert_eq!(unit().hit_textbook(&r, 0.0, INF), None);
        assert_eq!(unit().hit_with(SlabTest::Textbook, &r, 0.0, INF), None);
        assert!(unit().hit_with(SlabTest::Robust, &r, 0.0, INF).is_some());
        // Elsewhere both agree but for the robust exit's widening.
        let r = Ray::new(Vec3::new(0.5, 0.25, -1.0), Vec3::new(0.1, 0.2, 1.0));
        let (a, b) = (
            unit().hit(&r, 0.0, INF).unwrap(),
            unit().hit_textbook(&r, 0.0, INF).unwrap(),
        );
        assert_eq!(a.0, b.0);
        assert!(a.1 >= b.1 && a.1 <= b.1 * (1.0 + 4.0 * gamma(3)));
    }

    #[test]
    fn hit_through_the_middle() {
        let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::new(0.0, 0.0, 2.0));
        let (t0, t1) = unit().hit(&r, 0.0, INF).unwrap();
        assert_eq!(t0, 0.5);
        assert!((1.0..=1.0 + 4.0 * gamma(3)).contains(&t1));
    }

    #[test]
    fn hit_clips_to_the_t_range() {
        let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        assert_eq!(unit().hit(&r, 1.25, 1.5), Some((1.25, 1.5)));
        assert_eq!(unit().hit(&r, 0.0, 0.5), None);
        assert_eq!(unit().hit(&r, 2.5, INF), None);
    }

    #[test]
    fn hit_with_reversed_range_misses_even_for_a_zero_direction() {
        let r = Ray::new(Vec3::splat(0.5), Vec3::ZERO);
        assert_eq!(unit().hit(&r, 0.0, 1.0), Some((0.0, 1.0)));
        assert_eq!(unit().hit(&r, 1.0, 0.0), None);
        let r = Ray::new(Vec3::splat(0.5), Vec3::X);
        assert_eq!(unit().hit(&r, 0.4, 0.3), None);
    }

    #[test]
    fn hit_misses_a_box_empty_on_one_axis() {
        let r = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
        assert_eq!(inverted_x().hit(&r, 0.0, INF), None);
    }
}
