//! Camera rays: an orthonormal basis from eye, look-at and up, and the three
//! projections of [`crate::Projection`].

use crate::error::SceneError;
use crate::float::to_f64;
use crate::sampling::maps::concentric_disk;
use crate::scene::{Camera, Projection};
use gridrt_bbox::{Ray, Real, Vec3};

/// A camera ready to make rays for an image of a given size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CameraModel {
    eye: Vec3,
    /// Right.
    u: Vec3,
    /// Up.
    v: Vec3,
    /// Backwards: from `look_at` to the eye.
    w: Vec3,
    /// Half the width and height in pixels.
    half_w: Real,
    half_h: Real,
    /// Size of a pixel on the view plane (world units).
    pixel_size: Real,
    /// Eye to view plane; `None` for parallel (orthographic) rays.
    distance: Option<Real>,
    /// The thin lens `(radius, focus distance)`; `None`: a pinhole.
    lens: Option<(Real, Real)>,
}

fn finite(v: Vec3, what: &'static str) -> Result<Vec3, SceneError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(SceneError::CameraNotFinite { what })
    }
}

impl CameraModel {
    /// Checks the camera and builds its basis: `w = normalize(eye − look_at)`,
    /// `u = normalize(up × w)`, `v = w × u` (Suffern's `compute_uvw`).
    pub(crate) fn new(cam: &Camera, width: u32, height: u32) -> Result<Self, SceneError> {
        let eye = finite(cam.eye, "eye")?;
        let look_at = finite(cam.look_at, "look_at")?;
        let up = finite(cam.up, "up")?;
        let w = (eye - look_at)
            .try_normalize()
            .ok_or(SceneError::CameraEyeAtLookAt)?;
        let u = up
            .cross(w)
            .try_normalize()
            .ok_or(SceneError::CameraUpParallel)?;
        let v = w.cross(u);
        let half_w = width as Real * 0.5;
        let half_h = height as Real * 0.5;
        let (pixel_size, distance) = match cam.projection {
            Projection::Perspective { vfov_deg } => {
                if !(vfov_deg > 0.0 && vfov_deg < 180.0) {
                    return Err(SceneError::CameraProjection {
                        what: "the vertical field of view",
                        value: to_f64(vfov_deg),
                        range: "in (0, 180) degrees",
                    });
                }
                // A view plane at distance 1 whose height spans the field of view.
                let tan = (vfov_deg.to_radians() * 0.5).tan();
                (2.0 * tan / height as Real, Some(1.0))
            }
            Projection::ViewPlane {
                distance,
                pixel_size,
            } => {
                if !(distance > 0.0 && distance.is_finite()) {
                    return Err(SceneError::CameraProjection {
                        what: "the view-plane distance",
                        value: to_f64(distance),
                        range: "finite and > 0",
                    });
                }
                if !(pixel_size > 0.0 && pixel_size.is_finite()) {
                    return Err(SceneError::CameraProjection {
                        what: "the pixel size",
                        value: to_f64(pixel_size),
                        range: "finite and > 0",
                    });
                }
                (pixel_size, Some(distance))
            }
            Projection::Orthographic { height: h } => {
                if !(h > 0.0 && h.is_finite()) {
                    return Err(SceneError::CameraProjection {
                        what: "the orthographic height",
                        value: to_f64(h),
                        range: "finite and > 0",
                    });
                }
                (h / height as Real, None)
            }
        };
        if !(pixel_size > 0.0 && pixel_size.is_finite()) {
            return Err(SceneError::CameraProjection {
                what: "the pixel size that follows from the projection",
                value: to_f64(pixel_size),
                range: "finite and > 0 (check the image size and field of view)",
            });
        }
        let lens = match cam.lens {
            Some(l) if l.radius != 0.0 => {
                if !(l.radius > 0.0 && l.radius.is_finite()) {
                    return Err(SceneError::CameraProjection {
                        what: "the lens radius",
                        value: to_f64(l.radius),
                        range: "finite and ≥ 0 (0 is a pinhole)",
                    });
                }
                if !(l.focus_distance > 0.0 && l.focus_distance.is_finite()) {
                    return Err(SceneError::CameraProjection {
                        what: "the focus distance of a lens with a non-zero radius",
                        value: to_f64(l.focus_distance),
                        range: "finite and > 0 (the distance to the plane in focus)",
                    });
                }
                Some((l.radius, l.focus_distance))
            }
            _ => None,
        };
        Ok(Self {
            eye,
            u,
            v,
            w,
            half_w,
            half_h,
            pixel_size,
            distance,
            lens,
        })
    }

    /// A pixel's width in world units at distance `d` along a camera ray
    /// is `footprint[0] + footprint[1]·d` (the spread of a pinhole's rays,
    /// or the constant width of parallel ones): texture lookups filter over it.
    pub(crate) fn footprint(&self) -> [f32; 2] {
        let s = crate::float::to_f32(self.pixel_size);
        match self.distance {
            Some(d) => [0.0, s / crate::float::to_f32(d)],
            None => [s, 0.0],
        }
    }

    /// The ray through the point `(c + jx, r + jy)` of the pixel grid, where
    /// `c` is the column and `r` the row counted **from the bottom** (Suffern's
    /// convention) and `jx, jy ∈ [0, 1)` the position inside the pixel
    /// (½, ½ is the centre).
    ///
    /// For the view plane the direction is, in this order of operations,
    /// `x = s·(c − w/2 + jx)`, `y = s·(r − h/2 + jy)`,
    /// `normalize(x·u + y·v − d·w)`: with an axis-aligned basis this is bit
    /// for bit `normalize(x, y, −d)`, as Suffern and the Embree peer compute
    /// it. Directions are unit length.
    #[inline]
    pub(crate) fn ray(&self, c: u32, r: u32, jx: Real, jy: Real) -> Ray {
        let x = self.pixel_size * (c as Real - self.half_w + jx);
        let y = self.pixel_size * (r as Real - self.half_h + jy);
        match self.distance {
            Some(d) => Ray::new(self.eye, (self.u * x + self.v * y - self.w * d).normalize()),
            None => Ray::new(self.eye + self.u * x + self.v * y, -self.w),
        }
    }
}

impl CameraModel {
    /// Whether rays start on a lens (depth of field) rather than at a point.
    #[inline]
    pub(crate) fn has_lens(&self) -> bool {
        self.lens.is_some()
    }

    /// [`CameraModel::ray`] through a thin lens: `lens_u` in `[0, 1)²` is
    /// mapped to the aperture by the concentric disk map, and the ray
    /// passes through the point where the pinhole ray meets the plane of
    /// focus. Without a lens it is the pinhole ray. Directions are unit
    /// length.
    #[inline]
    pub(crate) fn lens_ray(&self, c: u32, r: u32, jx: Real, jy: Real, lens_u: (Real, Real)) -> Ray {
        let pinhole = self.ray(c, r, jx, jy);
        let Some((radius, focus)) = self.lens else {
            return pinhole;
        };
        // The pinhole ray meets the plane of focus (focus in front of the
        // eye, perpendicular to the view direction −w) at t_f.
        let cos = -pinhole.dir.dot(self.w);
        let p_focus = pinhole.origin + pinhole.dir * (focus / cos);
        let (lx, ly) = concentric_disk(lens_u);
        let origin = pinhole.origin + (self.u * lx + self.v * ly) * radius;
        Ray::new(origin, (p_focus - origin).normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn suffern() -> CameraModel {
        let cam = Camera {
            eye: Vec3::new(0.0, 0.0, 20.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::ViewPlane {
                distance: 3600.0,
                pixel_size: 1.0,
            },
            lens: None,
        };
        CameraModel::new(&cam, 400, 400).unwrap()
    }

    #[test]
    fn view_plane_matches_suffern_bit_for_bit() {
        let cam = suffern();
        for (c, r) in [
            (0u32, 0u32),
            (399, 0),
            (0, 399),
            (123, 287),
            (200, 200),
            (399, 399),
        ] {
            let ray = cam.ray(c, r, 0.5, 0.5);
            // What Suffern / the Embree peer compute, in the same precision.
            let dx = (c as f64 - 200.0 + 0.5) as Real;
            let dy = (r as f64 - 200.0 + 0.5) as Real;
            let dz: Real = -3600.0;
            let inv = 1.0 / (dx * dx + dy * dy + dz * dz).sqrt();
            assert_eq!(ray.dir, Vec3::new(dx * inv, dy * inv, dz * inv));
            assert_eq!(ray.origin, Vec3::new(0.0, 0.0, 20.0));
        }
        // r = 0 is the bottom row: its rays point down.
        assert!(cam.ray(0, 0, 0.5, 0.5).dir.y < 0.0);
    }

    #[test]
    fn perspective_spans_the_field_of_view() {
        let cam = Camera {
            eye: Vec3::ZERO,
            look_at: -Vec3::Z,
            up: Vec3::Y,
            projection: Projection::Perspective { vfov_deg: 90.0 },
            lens: None,
        };
        let m = CameraModel::new(&cam, 100, 50).unwrap();
        // The top edge of the image is 45° up.
        let top = m.ray(50, 50, 0.0, 0.0).dir;
        assert!((top.y - top.z.abs()).abs() < 1e-5 && top.x.abs() < 1e-6);
        let centre = m.ray(50, 25, 0.0, 0.0).dir;
        assert!((centre - -Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn orthographic_rays_are_parallel() {
        let cam = Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Orthographic { height: 2.0 },
            lens: None,
        };
        let m = CameraModel::new(&cam, 4, 4).unwrap();
        let a = m.ray(0, 0, 0.5, 0.5);
        let b = m.ray(3, 3, 0.5, 0.5);
        assert_eq!(a.dir, b.dir);
        assert_eq!(a.origin, Vec3::new(-0.75, -0.75, 5.0));
        assert_eq!(b.origin, Vec3::new(0.75, 0.75, 5.0));
    }

    #[test]
    fn thin_lens_rays_meet_on_the_plane_of_focus() {
        let mut cam = Camera {
            eye: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Perspective { vfov_deg: 40.0 },
            lens: Some(crate::ThinLens {
                radius: 0.25,
                focus_distance: 4.0,
            }),
        };
        let m = CameraModel::new(&cam, 16, 12).unwrap();
        assert!(m.has_lens());
        let pin = m.ray(3, 9, 0.25, 0.75);
        // The pinhole ray's point on the plane 4 units in front of the eye.
        let view = (cam.look_at - cam.eye).normalize();
        let focus = pin.origin + pin.dir * (4.0 / pin.dir.dot(view));
        let mut spread: Real = 0.0;
        for u in [(0.1, 0.2), (0.9, 0.5), (0.5, 0.99), (0.3, 0.7)] {
            let r = m.lens_ray(3, 9, 0.25, 0.75, u);
            assert!((r.dir.length() - 1.0).abs() < 1e-5);
            // Starts on the aperture, in the lens plane.
            let off = r.origin - cam.eye;
            assert!(off.length() <= 0.25 + 1e-5 && off.dot(view).abs() < 1e-5);
            spread = spread.max(off.length());
            // Passes through the focus point.
            let t = (focus - r.origin).dot(r.dir);
            assert!((r.origin + r.dir * t - focus).length() < 1e-4);
        }
        assert!(spread > 0.1);
        // Radius 0 is the pinhole, whatever the focus distance.
        cam.lens = Some(crate::ThinLens {
            radius: 0.0,
            focus_distance: 0.0,
        });
        let m = CameraModel::new(&cam, 16, 12).unwrap();
        assert!(!m.has_lens());
        assert_eq!(m.lens_ray(3, 9, 0.25, 0.75, (0.1, 0.2)), pin);
        // An aperture without a focus distance is an error.
        cam.lens = Some(crate::ThinLens {
            radius: 0.1,
            focus_distance: 0.0,
        });
        assert!(matches!(
            CameraModel::new(&cam, 16, 12),
            Err(SceneError::CameraProjection { what, .. }) if what.contains("focus distance")
        ));
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        let mut cam = Camera {
            eye: Vec3::ONE,
            look_at: Vec3::ONE,
            up: Vec3::Y,
            projection: Projection::Perspective { vfov_deg: 60.0 },
            lens: None,
        };
        assert_eq!(
            CameraModel::new(&cam, 4, 4),
            Err(SceneError::CameraEyeAtLookAt)
        );
        cam.look_at = Vec3::new(1.0, 5.0, 1.0);
        assert_eq!(
            CameraModel::new(&cam, 4, 4),
            Err(SceneError::CameraUpParallel)
        );
        cam.up = Vec3::X;
        cam.projection = Projection::Perspective { vfov_deg: 180.0 };
        assert!(matches!(
            CameraModel::new(&cam, 4, 4),
            Err(SceneError::CameraProjection { .. })
        ));
        cam.projection = Projection::Perspective { vfov_deg: 60.0 };
        cam.eye.x = Real::NAN;
        assert!(matches!(
            CameraModel::new(&cam, 4, 4),
            Err(SceneError::CameraNotFinite { .. })
        ));
    }
}
