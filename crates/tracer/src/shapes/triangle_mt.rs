//! The textbook Möller–Trumbore ray–triangle test, beside the watertight
//! default, to measure what watertightness costs and what it saves.

use super::{Surface, SurfacePoint, Triangle};
use gridrt_bbox::{Aabb, Ray, Real};
use gridrt_grid::{PrimHit, Primitive};

/// The determinant below which Möller and Trumbore's test calls a ray
/// parallel to the triangle (their paper's `EPSILON`, 10⁻⁶, in the units of
/// `|dir|·|e1|·|e2|`).
pub const MT_EPSILON: Real = 1e-6;

/// A triangle tested with Möller & Trumbore's algorithm ("Fast, Minimum
/// Storage Ray/Triangle Intersection", JGT 1997), as most renderers wrote
/// it before watertight tests: barycentrics from two cross products, each
/// compared with 0 and 1 on its own, and rays with `|det| < MT_EPSILON`
/// rejected as parallel.
///
/// It is **not watertight**: `u` and `v` of two triangles sharing an edge
/// are computed with different roundings, so a ray exactly through the
/// edge can miss both, and the fixed epsilon on the determinant makes
/// small or thin triangles, and short direction vectors, miss outright.
/// It exists to be measured against [`Triangle`]'s watertight test
/// (`TriangleTest::MollerTrumbore`, `--triangle-test moller-trumbore`);
/// shading, bounds and exact insertion are the wrapped triangle's.
///
/// ```
/// use gridrt_tracer::{MtTriangle, Triangle};
/// use gridrt_grid::{Primitive, Ray, Real, Vec3};
/// let tri = MtTriangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y));
/// let ray = Ray::new(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z);
/// let h = tri.closest_hit(&(), &ray, &(), 0.0, Real::INFINITY).unwrap();
/// assert_eq!((h.t, h.u, h.v), (1.0, 0.25, 0.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MtTriangle(pub Triangle);

impl MtTriangle {
    /// Möller–Trumbore: `(t, u, v)` of a hit with `t > 0` in
    /// `[t_min, t_max]`.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<PrimHit> {
        let [p0, p1, p2] = self.0.vertices();
        let e1 = p1 - p0;
        let e2 = p2 - p0;
        let pvec = ray.dir.cross(e2);
        let det = e1.dot(pvec);
        // Parallel within the paper's epsilon, or a NaN (a zero or NaN
        // direction): no hit.
        if !(det.abs() >= MT_EPSILON) {
            return None;
        }
        let inv_det = 1.0 / det;
        let tvec = ray.origin - p0;
        let u = tvec.dot(pvec) * inv_det;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let qvec = tvec.cross(e1);
        let v = ray.dir.dot(qvec) * inv_det;
        if !(v >= 0.0 && u + v <= 1.0) {
            return None;
        }
        let t = e2.dot(qvec) * inv_det;
        if !(t > 0.0 && t >= t_min && t <= t_max) {
            return None;
        }
        Some(PrimHit::new(t, u, v))
    }
}

impl Primitive for MtTriangle {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// Nothing is computed once per ray.
    type RayData = ();
    type Four = ();

    #[inline]
    fn ray_data(_: &Ray) {}

    #[inline]
    fn bounds(&self, _: &()) -> Aabb {
        self.0.bounds(&())
    }

    #[inline]
    fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t_min: Real, t_max: Real) -> Option<PrimHit> {
        self.intersect(ray, t_min, t_max)
    }

    #[inline]
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        self.0.overlaps_box(&(), cell)
    }
}

impl Surface for MtTriangle {
    #[inline]
    fn surface(&self, _: &(), ray: &Ray, h: &PrimHit) -> SurfacePoint {
        self.0.surface(&(), ray, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Shear;
    use gridrt_bbox::Vec3;

    #[test]
    fn agrees_with_the_watertight_test_away_from_edges() {
        let tri = Triangle::new(
            Vec3::new(0.0, 0.0, -2.0),
            Vec3::new(4.0, 0.0, -2.0),
            Vec3::new(0.0, 4.0, -2.0),
        );
        let r = Ray::new(Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
        let a = tri.intersect(&Shear::new(&r), 0.0, Real::INFINITY).unwrap();
        let b = MtTriangle(tri).intersect(&r, 0.0, Real::INFINITY).unwrap();
        assert_eq!((a.t, a.u, a.v), (b.t, b.u, b.v));
        assert!(MtTriangle(tri).intersect(&r, 0.0, 1.5).is_none());
        let miss = Ray::new(Vec3::new(5.0, 2.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(MtTriangle(tri).intersect(&miss, 0.0, 10.0).is_none());
    }

    #[test]
    fn the_fixed_epsilon_drops_small_triangles_the_watertight_test_hits() {
        // A triangle of side 2⁻¹² seen along a unit direction: det is
        // 2⁻²⁴ < 10⁻⁶, so Möller–Trumbore calls the ray parallel.
        let s = (2.0 as Real).powi(-12);
        let tri = Triangle::new(Vec3::ZERO, Vec3::X * s, Vec3::Y * s);
        let r = Ray::new(Vec3::new(0.25 * s, 0.25 * s, 1.0), -Vec3::Z);
        assert!(tri
            .intersect(&Shear::new(&r), 0.0, Real::INFINITY)
            .is_some());
        assert!(MtTriangle(tri).intersect(&r, 0.0, Real::INFINITY).is_none());
    }

    #[test]
    fn nan_and_zero_directions_miss() {
        let tri = MtTriangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y));
        let r = Ray::new(Vec3::new(0.1, 0.1, 1.0), Vec3::ZERO);
        assert!(tri.intersect(&r, 0.0, 10.0).is_none());
        let r = Ray::new(Vec3::new(0.1, 0.1, 1.0), Vec3::new(Real::NAN, 0.0, -1.0));
        assert!(tri.intersect(&r, 0.0, 10.0).is_none());
    }
}
