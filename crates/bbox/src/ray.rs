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
/// assert_eq!(r.inv_dir.z, gridrt_bbox::Real::NEG_INFINITY);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "RayParts", into = "RayParts")
)]
pub struct Ray {
    /// Where the ray starts (t = 0).
    pub origin: Vec3,
    /// The direction; not normalised.
    pub dir: Vec3,
    /// `1 / dir`, per component, with IEEE semantics (`1/±0 = ±∞`).
    pub inv_dir: Vec3,
}

/// What a [`Ray`] is serialised as: the rest is derived from it.
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct RayParts {
    origin: Vec3,
    dir: Vec3,
}

#[cfg(feature = "serde")]
impl From<RayParts> for Ray {
    fn from(p: RayParts) -> Self {
        Self::new(p.origin, p.dir)
    }
}

#[cfg(feature = "serde")]
impl From<Ray> for RayParts {
    fn from(r: Ray) -> Self {
        Self {
            origin: r.origin,
            dir: r.dir,
        }
    }
}

impl Ray {
    /// Builds a ray and precomputes the reciprocal direction.
    ///
    /// `dir` is stored as given (not normalised); it may have zero
    /// components of either sign.
    ///
    /// ```
    /// use gridrt_bbox::{Ray, Real, Vec3};
    /// let r = Ray::new(Vec3::ONE, Vec3::new(4.0, -0.0, 0.5));
    /// assert_eq!(r.inv_dir, Vec3::new(0.25, Real::NEG_INFINITY, 2.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self {
            origin,
            dir,
            inv_dir: Vec3::ONE / dir,
        }
    }

    /// The point at parameter `t`: `origin + t·dir`.
    ///
    /// ```
    /// use gridrt_bbox::{Ray, Vec3};
    /// let r = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
    /// assert_eq!(r.at(0.0), r.origin);
    /// assert_eq!(r.at(-0.5), Vec3::new(1.0, -1.0, 0.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn at(&self, t: Real) -> Vec3 {
        self.origin + self.dir * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inv_dir_keeps_the_sign_of_zero() {
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, -0.0, 2.0));
        assert_eq!(r.inv_dir.x, Real::INFINITY);
        assert_eq!(r.inv_dir.y, Real::NEG_INFINITY);
        assert_eq!(r.inv_dir.z, 0.5);
    }

    #[test]
    fn inv_dir_of_a_tiny_denormal_overflows_to_infinity() {
        let tiny = Real::MIN_POSITIVE / 16.0;
        assert!(tiny > 0.0 && !tiny.is_normal());
        let r = Ray::new(Vec3::ZERO, Vec3::new(tiny, -tiny, 1.0));
        assert_eq!(r.inv_dir.x, Real::INFINITY);
        assert_eq!(r.inv_dir.y, Real::NEG_INFINITY);
    }

    #[test]
    fn dir_is_not_normalised_and_at_follows_it() {
        let d = Vec3::new(3.0, 0.0, 4.0);
        let r = Ray::new(Vec3::new(1.0, 1.0, 1.0), d);
        assert_eq!(r.dir, d);
        assert_eq!(r.at(2.0), Vec3::new(7.0, 1.0, 9.0));
        assert_eq!(r.at(0.0), r.origin);
    }
}
