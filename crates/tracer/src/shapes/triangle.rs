use super::{overlap, unit_or, Surface, SurfacePoint};
use gridrt_bbox::{gamma, Aabb, Ray, Real, Vec3};
use gridrt_grid::{PrimHit, Primitive};

/// A triangle given by its three vertices (counter-clockwise = front).
///
/// The ray test is **watertight** (Woop, Benthin & Wald, "Watertight
/// Ray/Triangle Intersection", JCGT 2013): the vertices are moved into a
/// frame where the ray is the +z axis (translate, permute so that the
/// largest direction component is z, shear), and the three 2D edge
/// functions decide the hit by their signs. A ray through an edge or vertex
/// shared by two triangles hits at least one of them, because both see the
/// same edge function, bit for bit. When an edge function is exactly 0 in
/// `f32`, it is recomputed in `f64`, where the products are exact, so its
/// sign is right. Degenerate triangles (zero area) never hit and give no NaN.
///
/// A hit reports barycentrics `u`, `v`: the weights of `p1` and `p2` (the
/// hit point is `(1 − u − v)·p0 + u·p1 + v·p2`). Hits within the rounding
/// error of the ray origin (t ≤ δt, pbrt-v4's conservative bound) are
/// rejected, so a ray leaving the triangle does not hit it again.
///
/// ```
/// use gridrt_tracer::Triangle;
/// use gridrt_grid::{Primitive, Ray, Real, Vec3};
/// let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
/// let ray = Ray::new(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z);
/// let h = tri.closest_hit(&ray, 0.0, Real::INFINITY).unwrap();
/// assert_eq!((h.t, h.u, h.v), (1.0, 0.25, 0.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First vertex.
    pub p0: Vec3,
    /// Second vertex (barycentric `u`).
    pub p1: Vec3,
    /// Third vertex (barycentric `v`).
    pub p2: Vec3,
}

impl Triangle {
    /// A triangle from its vertices.
    #[inline]
    #[must_use]
    pub const fn new(p0: Vec3, p1: Vec3, p2: Vec3) -> Self {
        Self { p0, p1, p2 }
    }

    /// `(p1 − p0) × (p2 − p0)`: twice the area, along the front normal.
    #[inline]
    #[must_use]
    pub fn area_normal(&self) -> Vec3 {
        (self.p1 - self.p0).cross(self.p2 - self.p0)
    }

    /// Whether the triangle has zero area (its vertices are collinear), in
    /// which case it is never hit.
    #[inline]
    #[must_use]
    pub fn is_degenerate(&self) -> bool {
        self.area_normal() == Vec3::ZERO
    }

    /// The watertight test: `(t, u, v)` of a hit with `t` in
    /// `[t_min, t_max]` and `t > δt`.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<PrimHit> {
        let d = ray.dir;
        let ad = d.abs();
        // Permutation: kz is the axis of the largest |d|; swapping kx, ky for
        // a negative d[kz] keeps the winding (and so the signs) consistent.
        let kz = if ad.x > ad.y {
            if ad.x > ad.z {
                0
            } else {
                2
            }
        } else if ad.y > ad.z {
            1
        } else {
            2
        };
        let mut kx = if kz == 2 { 0 } else { kz + 1 };
        let mut ky = if kx == 2 { 0 } else { kx + 1 };
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        // Shear constants. d[kz] == 0 only for a zero direction: then sz is
        // infinite, the edge functions are NaN and every test below fails.
        let sz = 1.0 / d[kz];
        let sx = d[kx] * sz;
        let sy = d[ky] * sz;

        // Vertices relative to the origin, permuted and sheared.
        let a = self.p0 - ray.origin;
        let b = self.p1 - ray.origin;
        let c = self.p2 - ray.origin;
        let ax = a[kx] - sx * a[kz];
        let ay = a[ky] - sy * a[kz];
        let bx = b[kx] - sx * b[kz];
        let by = b[ky] - sy * b[kz];
        let cx = c[kx] - sx * c[kz];
        let cy = c[ky] - sy * c[kz];

        // Scaled barycentrics: the 2D edge functions.
        #[allow(unused_mut)]
        let mut e0 = cx * by - cy * bx;
        #[allow(unused_mut)]
        let mut e1 = ax * cy - ay * cx;
        #[allow(unused_mut)]
        let mut e2 = bx * ay - by * ax;
        #[cfg(not(feature = "f64"))]
        if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
            // On an edge in f32: redo the differences of exact f64 products so
            // that the sign, which decides the hit, is exact.
            let (ax, ay, bx, by, cx, cy) = (
                ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
            );
            e0 = (cx * by - cy * bx) as f32;
            e1 = (ax * cy - ay * cx) as f32;
            e2 = (bx * ay - by * ax) as f32;
        }
        // Inside means all three of one sign (zeros allowed: edges count).
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 || det.is_nan() {
            // Seen edge-on, or a zero direction.
            return None;
        }
        let az = sz * a[kz];
        let bz = sz * b[kz];
        let cz = sz * c[kz];
        let inv_det = 1.0 / det;
        let t = (e0 * az + e1 * bz + e2 * cz) * inv_det;
        if !(t >= t_min && t <= t_max) {
            return None;
        }
        // pbrt-v4's bound on the error of t (§6.8.4): a hit closer than it
        // cannot be told apart from the origin.
        let max_zt = az.abs().max(bz.abs()).max(cz.abs());
        let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
        let max_yt = ay.abs().max(by.abs()).max(cy.abs());
        let delta_z = gamma(3) * max_zt;
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = e0.abs().max(e1.abs()).max(e2.abs());
        let delta_t =
            3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        if t <= delta_t {
            return None;
        }
        // A zero-area triangle can pass the sign test through rounding of
        // the (nearly cancelling) edge functions; it never hits.
        if self.is_degenerate() {
            return None;
        }
        Some(PrimHit {
            t,
            u: e1 * inv_det,
            v: e2 * inv_det,
        })
    }
}

impl Primitive for Triangle {
    #[inline]
    fn bounds(&self) -> Aabb {
        Aabb::new(
            self.p0.min(self.p1).min(self.p2),
            self.p0.max(self.p1).max(self.p2),
        )
    }

    #[inline]
    fn closest_hit(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<PrimHit> {
        self.intersect(ray, t_min, t_max)
    }

    /// The separating-axis test of Akenine-Möller (2001), with a rounding
    /// margin so that a touching box is never rejected.
    #[inline]
    fn overlaps_box(&self, cell: &Aabb) -> bool {
        overlap::triangle_box(self.p0, self.p1, self.p2, cell)
    }
}

impl Surface for Triangle {
    /// The point from the barycentrics, with pbrt-v4's error bound
    /// γ(7)·Σ|bᵢ·pᵢ| (§6.8.4).
    #[inline]
    fn surface(&self, _ray: &Ray, _t: Real, u: Real, v: Real) -> SurfacePoint {
        let w = 1.0 - u - v;
        let (q0, q1, q2) = (self.p0 * w, self.p1 * u, self.p2 * v);
        let p = q0 + q1 + q2;
        let p_err = (q0.abs() + q1.abs() + q2.abs()) * gamma(7);
        SurfacePoint {
            p,
            p_err,
            n: unit_or(self.area_normal(), Vec3::Z),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [Real; 3], d: [Real; 3]) -> Ray {
        Ray::new(Vec3::from_array(o), Vec3::from_array(d))
    }

    #[test]
    fn barycentrics_are_weights_of_p1_and_p2() {
        let tri = Triangle::new(
            Vec3::new(0.0, 0.0, -2.0),
            Vec3::new(4.0, 0.0, -2.0),
            Vec3::new(0.0, 4.0, -2.0),
        );
        let h = tri
            .intersect(&ray([1.0, 2.0, 0.0], [0.0, 0.0, -1.0]), 0.0, Real::INFINITY)
            .unwrap();
        assert_eq!((h.t, h.u, h.v), (2.0, 0.25, 0.5));
        // Either winding, either side.
        let back = Triangle::new(tri.p0, tri.p2, tri.p1);
        let h = back
            .intersect(&ray([1.0, 2.0, -5.0], [0.0, 0.0, 1.0]), 0.0, Real::INFINITY)
            .unwrap();
        assert_eq!((h.t, h.u, h.v), (3.0, 0.5, 0.25));
    }

    #[test]
    fn range_is_closed_and_misses_are_misses() {
        let tri = Triangle::new(
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(0.0, 1.0, -1.0),
        );
        let r = ray([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]);
        assert!(tri.intersect(&r, 0.0, 1.0).is_some());
        assert!(tri.intersect(&r, 1.0, 1.0).is_some());
        assert!(tri.intersect(&r, 0.0, 0.999).is_none());
        assert!(tri
            .intersect(&ray([5.0, 0.0, 0.0], [0.0, 0.0, -1.0]), 0.0, 10.0)
            .is_none());
        // Behind the origin.
        assert!(tri
            .intersect(&ray([0.0, 0.0, -3.0], [0.0, 0.0, -1.0]), 0.0, 10.0)
            .is_none());
    }

    #[test]
    fn degenerate_triangles_and_bad_rays_miss_without_nan() {
        let line = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0));
        let point = Triangle::new(Vec3::ONE, Vec3::ONE, Vec3::ONE);
        assert!(line.is_degenerate() && point.is_degenerate());
        for d in [
            [0.0, 0.0, -1.0],
            [0.0, -1.0, 0.0],
            [0.3, -1.0, 0.1],
            [1.0, 0.0, 0.0],
        ] {
            for o in [
                [0.5, 0.0, 1.0],
                [0.5, 1.0, 0.0],
                [0.0, 0.0, 0.0],
                [1.0, 2.0, 1.0],
            ] {
                let r = ray(o, d);
                assert!(line
                    .intersect(&r, -Real::INFINITY, Real::INFINITY)
                    .is_none());
                assert!(point
                    .intersect(&r, -Real::INFINITY, Real::INFINITY)
                    .is_none());
            }
        }
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(tri
            .intersect(&ray([0.1, 0.1, 1.0], [0.0, 0.0, 0.0]), 0.0, 10.0)
            .is_none());
        // A ray in the triangle's plane sees it edge-on.
        assert!(tri
            .intersect(&ray([-1.0, 0.1, 0.0], [1.0, 0.0, 0.0]), 0.0, 10.0)
            .is_none());
    }

    #[test]
    fn shared_edge_is_hit_by_one_triangle_at_least() {
        // Two triangles sharing the diagonal of a square; rays straight
        // through points of the diagonal.
        let a = Triangle::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        );
        let b = Triangle::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        for i in 0..=1000 {
            let s = i as Real / 1000.0;
            let r = ray([s, s, 3.0], [0.0137, -0.021, -1.0]);
            let o = Vec3::new(s, s, 0.0) - r.dir * 3.0;
            let r = Ray::new(o, r.dir);
            assert!(
                a.intersect(&r, 0.0, 10.0).is_some() || b.intersect(&r, 0.0, 10.0).is_some(),
                "fell through the shared edge at s = {s}"
            );
        }
    }

    #[test]
    fn self_hit_is_rejected_at_the_origin() {
        let tri = Triangle::new(
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        // A ray starting on the triangle and leaving it at a slant.
        let r = ray([0.1, 0.1, 0.0], [0.3, 0.2, 1.0]);
        assert!(tri.intersect(&r, 0.0, 10.0).is_none());
    }

    #[test]
    fn surface_gives_front_normal_and_error() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let r = ray([0.2, 0.3, 5.0], [0.0, 0.0, -1.0]);
        let h = tri.intersect(&r, 0.0, 10.0).unwrap();
        let sp = tri.surface(&r, h.t, h.u, h.v);
        assert_eq!(sp.n, Vec3::Z);
        assert!((sp.p - Vec3::new(0.2, 0.3, 0.0)).length() < 1e-6);
    }
}
