use super::{Surface, SurfacePoint};
use gridrt_bbox::{gamma, Aabb, Ray, Real, Vec3};
use gridrt_grid::{PrimHit, Primitive};

/// A solid axis-aligned box: its six faces are the surface, so a ray from
/// outside hits where it enters and a ray from inside where it leaves.
///
/// [`Primitive::closest_hit`] reports the face in `u` (`0..6`: −x, +x, −y,
/// +y, −z, +z) so that shading does not have to guess it from the point.
///
/// ```
/// use gridrt_tracer::Cuboid;
/// use gridrt_grid::{Primitive, Ray, Real, Vec3};
/// let c = Cuboid::new(Vec3::splat(-1.0), Vec3::ONE);
/// let h = c.closest_hit(&(), &Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), &(), 0.0, Real::INFINITY).unwrap();
/// assert_eq!((h.t, h.u), (4.0, 5.0)); // enters through the +z face
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Cuboid {
    /// A box from its corners (`min ≤ max` on every axis).
    #[inline]
    #[must_use]
    pub const fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The nearest face crossing with `t` in `[t_min, t_max]`, as `(t, face)`.
    ///
    /// A zero direction component means the ray is parallel to that pair of
    /// faces: it is tested against the slab directly (no `0·∞`), so an origin
    /// exactly on a face plane resolves the same way every time.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<(Real, u8)> {
        let mut t_enter = Real::NEG_INFINITY;
        let mut t_exit = Real::INFINITY;
        let mut face_enter = 0u8;
        let mut face_exit = 0u8;
        for a in 0..3 {
            let o = ray.origin[a];
            let d = ray.dir[a];
            if d == 0.0 {
                if o < self.min[a] || o > self.max[a] {
                    return None;
                }
                continue;
            }
            let inv = ray.inv_dir[a];
            let t_lo = (self.min[a] - o) * inv;
            let t_hi = (self.max[a] - o) * inv;
            // Entering through the min face when d > 0, the max face when d < 0.
            let (near, far, f_near, f_far) = if d > 0.0 {
                (t_lo, t_hi, 2 * a as u8, 2 * a as u8 + 1)
            } else {
                (t_hi, t_lo, 2 * a as u8 + 1, 2 * a as u8)
            };
            if near > t_enter {
                t_enter = near;
                face_enter = f_near;
            }
            if far < t_exit {
                t_exit = far;
                face_exit = f_far;
            }
        }
        if !(t_enter <= t_exit) {
            return None;
        }
        if t_enter >= t_min && t_enter <= t_max {
            Some((t_enter, face_enter))
        } else if t_exit >= t_min && t_exit <= t_max {
            Some((t_exit, face_exit))
        } else {
            None
        }
    }
}

impl Primitive for Cuboid {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// Nothing is computed once per ray.
    type RayData = ();
    type Four = ();

    #[inline]
    fn ray_data(_: &Ray) {}

    #[inline]
    fn bounds(&self, _: &()) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    #[inline]
    fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t_min: Real, t_max: Real) -> Option<PrimHit> {
        self.intersect(ray, t_min, t_max)
            .map(|(t, face)| PrimHit::new(t, Real::from(face), 0.0))
    }

    /// Box–box overlap: exact (no arithmetic).
    #[inline]
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        self.bounds(&()).overlaps(cell)
    }
}

impl Surface for Cuboid {
    /// The point's coordinate on the face's axis is set to the face value
    /// exactly; the other two come from `o + t·d`. The error that matters
    /// for an offset is along the face normal, so the bound is small.
    #[inline]
    fn surface(&self, _: &(), ray: &Ray, h: &PrimHit) -> SurfacePoint {
        let (t, u) = (h.t, h.u);
        let face = (u as usize).min(5);
        let axis = face / 2;
        let positive = face % 2 == 1;
        let mut p = ray.at(t).clamp(self.min, self.max);
        p[axis] = if positive {
            self.max[axis]
        } else {
            self.min[axis]
        };
        let mut n = Vec3::ZERO;
        n[axis] = if positive { 1.0 } else { -1.0 };
        SurfacePoint {
            p,
            p_err: p.abs() * gamma(2),
            n,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enters_then_exits() {
        let c = Cuboid::new(Vec3::ZERO, Vec3::ONE);
        let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        assert_eq!(c.intersect(&r, 0.0, 10.0), Some((1.0, 4)));
        assert_eq!(c.intersect(&r, 1.5, 10.0), Some((2.0, 5)));
        assert_eq!(c.intersect(&r, 2.5, 10.0), None);
        let inside = Ray::new(Vec3::splat(0.5), -Vec3::X);
        assert_eq!(c.intersect(&inside, 0.0, 10.0), Some((0.5, 0)));
    }

    #[test]
    fn parallel_rays_on_a_face_plane() {
        let c = Cuboid::new(Vec3::ZERO, Vec3::ONE);
        // In the plane y = 1 (a face), moving along x: hits (touching counts).
        let r = Ray::new(Vec3::new(-1.0, 1.0, 0.5), Vec3::X);
        assert_eq!(c.intersect(&r, 0.0, 10.0).map(|h| h.0), Some(1.0));
        let above = Ray::new(Vec3::new(-1.0, 1.0 + 1e-6, 0.5), Vec3::X);
        assert_eq!(c.intersect(&above, 0.0, 10.0), None);
        assert_eq!(
            c.intersect(&Ray::new(Vec3::splat(0.5), Vec3::ZERO), 0.0, 1.0),
            None
        );
    }

    #[test]
    fn surface_snaps_to_the_face() {
        let c = Cuboid::new(Vec3::new(-1.0, -2.0, -3.0), Vec3::new(0.3, 0.7, 0.1));
        let r = Ray::new(Vec3::new(5.0, 0.1, -1.0), Vec3::new(-1.0, 0.013, 0.02));
        let h = c.closest_hit(&(), &r, &(), 0.0, 100.0).unwrap();
        let sp = c.surface(&(), &r, &h);
        assert_eq!(sp.p.x, 0.3);
        assert_eq!(sp.n, Vec3::X);
    }
}
