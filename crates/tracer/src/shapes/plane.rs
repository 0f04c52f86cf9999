use glam::BVec3;
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
    /// The axis `k` of the normal's largest component, as a lane mask, and
    /// the normal with that lane zeroed: [`Plane::surface`] solves the hit
    /// point's coordinate `k` from the other two.
    solve: BVec3,
    /// `normal` with lane `k` set to zero.
    in_plane_normal: Vec3,
    /// `point[k]` and `normal[k]`.
    point_k: Real,
    normal_k: Real,
}

impl Plane {
    /// A plane through `point` with normal direction `normal` (normalised
    /// here; a zero normal gives a plane that is never hit).
    #[inline]
    #[must_use]
    pub fn new(point: Vec3, normal: Vec3) -> Self {
        let normal = normal.try_normalize().unwrap_or(Vec3::ZERO);
        let k = normal.abs().max_position();
        let solve = BVec3::new(k == 0, k == 1, k == 2);
        Self {
            point,
            normal,
            solve,
            in_plane_normal: Vec3::select(solve, Vec3::ZERO, normal),
            point_k: point[k],
            normal_k: normal[k],
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
        let num = (self.point - ray.origin).dot(self.normal);
        // Opposite signs put the plane behind the origin: decided before
        // dividing, so that a quotient underflowing to -0 cannot pass for
        // a hit at 0 (an origin a tiny step off the plane, leaving it), and
        // no subnormal quotient is computed (a microcode assist of about
        // 100 cycles on x86, for every shadow ray leaving a floor at 0).
        if num != 0.0 && (num < 0.0) != (denom < 0.0) && t_min >= 0.0 {
            return None;
        }
        let t = num / denom;
        (t >= t_min && t <= t_max).then_some(t)
    }

    /// The hit point with a bound on its distance from the plane.
    ///
    /// The point along the ray is moved onto the plane along the normal's
    /// largest axis `k`: its coordinate `k` is solved from the other two
    /// with the plane's equation. The bound is then the rounding of that
    /// one solve, a few ulps of the point's distance from `point` in the
    /// plane plus half an ulp of the coordinate itself, instead of ulps of
    /// the ray origin and of the point along every axis. Far from the world
    /// origin this keeps secondary rays' origins within the rounding of
    /// the geometry, so they do not start above a small object lying on
    /// the plane (light leaking under it). For an axis-aligned plane the
    /// coordinate is `point`'s own, exactly.
    #[inline]
    pub(crate) fn surface(&self, ray: &Ray, t: Real) -> SurfacePoint {
        let p = ray.at(t);
        // The two in-plane terms, with lane k zero: their sum in lane order
        // is exactly `a + b` of the two other axes, whichever axis k is.
        let d = (p - self.point) * self.in_plane_normal;
        let pk = self.point_k - d.element_sum() / self.normal_k;
        let err = d.abs().element_sum() / self.normal_k.abs() * gamma(5) + pk.abs() * gamma(1);
        SurfacePoint {
            p: Vec3::select(self.solve, Vec3::splat(pk), p),
            p_err: Vec3::select(self.solve, Vec3::splat(err), Vec3::ZERO),
            n: self.normal,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::float::to_f64;

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

    #[test]
    fn far_hit_point_error_stays_within_the_geometry_rounding() {
        // A floor 10⁵ from the origin seen from 10⁵ away: the point's
        // error bound along the normal is about one ulp of its coordinate,
        // not ulps of every coordinate of the origin and the point.
        let far = Vec3::splat(1e5);
        let floor = Plane::new(far, Vec3::Y);
        let r = Ray::new(far + Vec3::new(0.0, 3.0, 8.0), Vec3::new(0.1, -1.0, -0.7));
        let t = floor.intersect(&r, 0.0, Real::INFINITY).unwrap();
        let sp = floor.surface(&r, t);
        assert_eq!(sp.p.y, far.y);
        let ulp = far.y * Real::EPSILON;
        assert!(sp.n.abs().dot(sp.p_err) <= ulp, "{:?}", sp.p_err);
        // A slanted plane: the point is within its bound of the plane.
        let slant = Plane::new(far, Vec3::new(0.3, 1.0, -0.2));
        let t = slant.intersect(&r, 0.0, Real::INFINITY).unwrap();
        let sp = slant.surface(&r, t);
        let f = |v: Vec3| glam::DVec3::new(to_f64(v.x), to_f64(v.y), to_f64(v.z));
        let dist = (f(sp.p) - f(far)).dot(f(slant.normal));
        assert!(
            dist.abs() <= f(slant.normal).abs().dot(f(sp.p_err)),
            "{dist}"
        );
        assert!(sp.p_err.max_element() < 8.0 * ulp, "{:?}", sp.p_err);
    }
}
