use crate::math::{gamma, Real, Vec3};
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
    #[must_use]
    pub fn from_points<I: IntoIterator<Item = Vec3>>(points: I) -> Self {
        points.into_iter().fold(Self::EMPTY, Self::grow)
    }

    /// True when the box holds no point (`min > max` on some axis).
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// The smallest box holding both boxes.
    #[inline]
    #[must_use]
    pub fn union(self, other: Self) -> Self {
        Self::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// The smallest box holding this box and the point.
    #[inline]
    #[must_use]
    pub fn grow(self, p: Vec3) -> Self {
        Self::new(self.min.min(p), self.max.max(p))
    }

    /// `max − min`: the box's size per axis (zero for an empty box).
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
    #[inline]
    #[must_use]
    pub fn centroid(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The total area of the six faces (zero for an empty box).
    #[inline]
    #[must_use]
    pub fn surface_area(&self) -> Real {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// True when the point lies in the closed box.
    #[inline]
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// True when the closed boxes share at least one point (touching counts).
    #[inline]
    #[must_use]
    pub fn overlaps(&self, other: &Self) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// The axis (0 = x, 1 = y, 2 = z) along which the box is longest; x on ties.
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
    /// - An empty box is always missed; a zero-thickness box is hit.
    /// - `t_min == t_max` asks whether the single point `ray.at(t_min)` is in
    ///   the box.
    ///
    /// ```
    /// use gridrt_bbox::{Aabb, Ray, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// // A ray lying in the face x = 0, direction (0, 0, -0).
    /// let r = Ray::new(Vec3::new(0.0, 0.5, 2.0), Vec3::new(-0.0, 0.0, -1.0));
    /// assert_eq!(b.hit(&r, 0.0, 10.0).map(|t| t.0), Some(1.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn hit(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
        debug_assert!(!t_min.is_nan() && !t_max.is_nan(), "t range must not be NaN");
        if self.is_empty() {
            return None;
        }
        let widen = 2.0 * gamma(3);
        let mut t0 = t_min;
        let mut t1 = t_max;
        for a in 0..3 {
            let o = ray.origin[a];
            let inv = ray.inv_dir[a];
            if inv.is_infinite() {
                // Parallel to the slab: inside it for all t, or never.
                if o < self.min[a] || o > self.max[a] {
                    return None;
                }
                continue;
            }
            let mut near = (self.min[a] - o) * inv;
            let mut far = (self.max[a] - o) * inv;
            if near > far {
                std::mem::swap(&mut near, &mut far);
            }
            far += far.abs() * widen;
            if near > t0 {
                t0 = near;
            }
            if far < t1 {
                t1 = far;
            }
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }
}
