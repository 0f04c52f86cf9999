use gridrt_bbox::{gamma, Ray, Real, Vec3};

use super::SurfacePoint;

/// An infinite plane. It has no finite bounds, so it never goes into the
/// grid: the renderer tests planes one by one after the grid query, with the
/// same tie rule (planes come after every grid primitive in index order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point on the plane.
    pub point: Vec3,
    /// Unit normal (the front side).
    pub normal: Vec3,
}

impl Plane {
    /// A plane through `point` with normal direction `normal` (normalised
    /// here; a zero normal gives a plane that is never hit).
    #[inline]
    #[must_use]
    pub fn new(point: Vec3, normal: Vec3) -> Self {
        Self {
            point,
            normal: normal.try_normalize().unwrap_or(Vec3::ZERO),
        }
    }

    /// The crossing with `t` in `[t_min, t_max]`; none for a ray parallel to
    /// the plane (also one lying in it).
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<Real> {
        let denom = ray.dir.dot(self.normal);
        if denom == 0.0 || denom.is_nan() {
            return None;
        }
        let t = (self.point - ray.origin).dot(self.normal) / denom;
        (t >= t_min && t <= t_max).then_some(t)
    }

    /// The hit point with a bound on its distance from the plane: the
    /// rounding of `t` moves the point along the ray by at most a few ULPs
    /// of `|o|` and `|q|` in the normal's direction.
    #[inline]
    pub(crate) fn surface(&self, ray: &Ray, t: Real) -> SurfacePoint {
        let p = ray.at(t);
        SurfacePoint {
            p,
            p_err: (ray.origin.abs() + self.point.abs() + p.abs()) * gamma(8),
            n: self.normal,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_front_and_back_and_not_parallel() {
        let pl = Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
        assert_eq!(pl.normal, Vec3::Y);
        let down = Ray::new(Vec3::ZERO, -Vec3::Y);
        assert_eq!(pl.intersect(&down, 0.0, 10.0), Some(1.0));
        let up = Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::Y);
        assert_eq!(pl.intersect(&up, 0.0, 10.0), Some(2.0));
        assert_eq!(
            pl.intersect(&Ray::new(Vec3::ZERO, Vec3::X), 0.0, 10.0),
            None
        );
        assert_eq!(
            pl.intersect(&Ray::new(Vec3::new(0.0, -1.0, 0.0), Vec3::X), 0.0, 10.0),
            None
        );
        assert_eq!(pl.intersect(&down, 0.0, 0.5), None);
    }
}
