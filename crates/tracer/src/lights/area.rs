//! Rectangle (parallelogram) and disk area lights as surfaces: ray
//! intersection on their plane and a bounds test in it. Sampling them for
//! light goes through [`crate::emitters::Emitters`], like emissive meshes.

use crate::emitters::EmitterShape;
use crate::sampling::maps::Frame;
use crate::shapes::{Plane, SurfacePoint};
use gridrt_bbox::{Ray, Real, Vec3};

/// The outline of an area light within its plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum AreaShape {
    /// `corner + a·u + b·v` for `a, b` in `[0, 1]`.
    Rect { corner: Vec3, u: Vec3, v: Vec3 },
    /// Points within `radius` of `center`.
    Disk { center: Vec3, radius: Real },
}

/// An area light as the renderer holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AreaLight {
    pub(crate) shape: AreaShape,
    /// The light's plane; its normal is the emitting (front) side.
    pub(crate) plane: Plane,
    /// `u × v` over its squared length, to solve for `a` and `b` (rectangles).
    w: Vec3,
    /// Index of its (emissive) material in the scene data.
    pub(crate) material: u32,
    /// Index among the sampled emitters (`u32::MAX`: not sampled).
    pub(crate) emitter: u32,
}

impl AreaLight {
    /// A parallelogram; `None` when its edges are parallel or zero.
    pub(crate) fn rect(corner: Vec3, u: Vec3, v: Vec3, material: u32) -> Option<Self> {
        let w = u.cross(v);
        let ww = w.length_squared();
        if !(ww > 0.0) || !ww.is_finite() {
            return None;
        }
        Some(Self {
            shape: AreaShape::Rect { corner, u, v },
            plane: Plane::new(corner, w),
            w: w / ww,
            material,
            emitter: u32::MAX,
        })
    }

    /// A disk; `None` when the normal is zero or the radius not positive.
    pub(crate) fn disk(center: Vec3, normal: Vec3, radius: Real, material: u32) -> Option<Self> {
        let n = normal.try_normalize()?;
        if !(radius > 0.0) || !radius.is_finite() {
            return None;
        }
        Some(Self {
            shape: AreaShape::Disk { center, radius },
            plane: Plane::new(center, n),
            w: Vec3::ZERO,
            material,
            emitter: u32::MAX,
        })
    }

    /// The same surface as a light to sample.
    pub(crate) fn emitter_shape(&self) -> EmitterShape {
        let n = self.plane.normal;
        match self.shape {
            AreaShape::Rect { corner, u, v } => EmitterShape::Rect { corner, u, v, n },
            AreaShape::Disk { center, radius } => {
                let f = Frame::new(n);
                EmitterShape::Disk {
                    center,
                    radius,
                    x: f.x,
                    y: f.y,
                    n,
                }
            }
        }
    }

    /// The ray parameter of the crossing in `[0, t_max]`, from either side.
    #[inline]
    pub(crate) fn intersect(&self, ray: &Ray, t_max: Real) -> Option<Real> {
        let t = self.plane.intersect(ray, 0.0, t_max)?;
        let p = ray.at(t);
        let inside = match self.shape {
            AreaShape::Rect { corner, u, v } => {
                let d = p - corner;
                let a = d.cross(v).dot(self.w);
                let b = u.cross(d).dot(self.w);
                (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)
            }
            AreaShape::Disk { center, radius } => (p - center).length_squared() <= radius * radius,
        };
        inside.then_some(t)
    }

    /// The surface point of a crossing found by [`AreaLight::intersect`].
    #[inline]
    pub(crate) fn surface(&self, ray: &Ray, t: Real) -> SurfacePoint {
        self.plane.surface(ray, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rectangle_is_hit_inside_and_missed_outside_from_both_sides() {
        let l = AreaLight::rect(Vec3::new(0.0, 1.0, 0.0), Vec3::X, Vec3::Z, 0).unwrap();
        // Front is X × Z = −Y.
        assert!(l.plane.normal.y < -0.99);
        let down = |x, z| Ray::new(Vec3::new(x, 3.0, z), Vec3::NEG_Y);
        let up = |x, z| Ray::new(Vec3::new(x, -3.0, z), Vec3::Y);
        assert_eq!(l.intersect(&down(0.5, 0.5), 10.0), Some(2.0));
        assert_eq!(l.intersect(&up(0.25, 0.75), 10.0), Some(4.0));
        assert_eq!(l.intersect(&down(1.5, 0.5), 10.0), None);
        assert_eq!(l.intersect(&down(0.5, -0.1), 10.0), None);
        assert_eq!(l.intersect(&down(0.5, 0.5), 1.5), None);
    }

    #[test]
    fn a_slanted_parallelogram_is_bounded_by_its_edges() {
        let l = AreaLight::rect(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0),
            0,
        )
        .unwrap();
        let down = |x, z| Ray::new(Vec3::new(x, 1.0, z), Vec3::NEG_Y);
        assert!(l.intersect(&down(2.5, 0.9), 5.0).is_some());
        assert!(l.intersect(&down(0.2, 0.9), 5.0).is_none());
    }

    #[test]
    fn a_disk_is_round() {
        let l = AreaLight::disk(Vec3::ZERO, Vec3::Y, 1.0, 0).unwrap();
        let down = |x, z| Ray::new(Vec3::new(x, 1.0, z), Vec3::NEG_Y);
        assert!(l.intersect(&down(0.7, 0.7), 5.0).is_some());
        assert!(l.intersect(&down(0.72, 0.72), 5.0).is_none());
        assert!(AreaLight::disk(Vec3::ZERO, Vec3::ZERO, 1.0, 0).is_none());
        assert!(AreaLight::disk(Vec3::ZERO, Vec3::Y, 0.0, 0).is_none());
        assert!(AreaLight::rect(Vec3::ZERO, Vec3::X, Vec3::X * 2.0, 0).is_none());
    }
}
