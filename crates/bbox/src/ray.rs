use crate::math::{Real, Vec3};

/// A ray `origin + t·dir`.
///
/// `dir` is **not** normalised: `t` is measured in units of `dir`. The
/// reciprocal `inv_dir` is computed once when the ray is built; a zero
/// component (of either sign) gives an infinite reciprocal of the same sign,
/// which the slab test and the grid traversal handle on purpose.
///
/// The valid `t` range is not part of the ray: queries take it as arguments
/// (pbrt's `Intersect(ray, tMax)`), so one ray can be reused across ranges.
///
/// ```
/// use gridrt_bbox::{Ray, Vec3};
/// let r = Ray::new(Vec3::ZERO, Vec3::new(2.0, 0.0, -0.0));
/// assert_eq!(r.at(1.5), Vec3::new(3.0, 0.0, 0.0));
/// assert_eq!(r.inv_dir.z, -f32::INFINITY as gridrt_bbox::Real);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Ray {
    /// Where the ray starts (t = 0).
    pub origin: Vec3,
    /// The direction; not normalised.
    pub dir: Vec3,
    /// `1 / dir`, per component, with IEEE semantics (`1/±0 = ±∞`).
    pub inv_dir: Vec3,
}

impl Ray {
    /// Builds a ray and precomputes the reciprocal direction.
    #[inline]
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self {
            origin,
            dir,
            inv_dir: Vec3::ONE / dir,
        }
    }

    /// The point at parameter `t`.
    #[inline]
    #[must_use]
    pub fn at(&self, t: Real) -> Vec3 {
        self.origin + self.dir * t
    }
}
