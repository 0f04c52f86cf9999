//! Area lights: the emitting primitives of a scene (triangles of emissive
//! meshes, emissive spheres) and the rectangle and disk lights, chosen in
//! proportion to their power and sampled by area for next-event estimation
//! (and for the soft shadows of the Whitted tracer).
//!
//! Emission is one-sided, on the front face, as in pbrt and Mitsuba: a
//! triangle's front is the side its counter-clockwise winding faces (the
//! direction of `(p1 − p0) × (p2 − p0)`), a sphere's is its outside.

use crate::sampling::maps::{concentric_disk, uniform_sphere, uniform_triangle};
use crate::scene::Rgb;
use gridrt_bbox::{Real, Vec3};

const PI: Real = std::f64::consts::PI as Real;

/// The shape of an emitter, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum EmitterShape {
    Triangle {
        p0: Vec3,
        e1: Vec3,
        e2: Vec3,
        /// Unit normal of the front (emitting) face.
        n: Vec3,
    },
    Sphere {
        center: Vec3,
        radius: Real,
    },
    /// A parallelogram `corner + a·u + b·v`, `a, b` in `[0, 1]`.
    Rect {
        corner: Vec3,
        u: Vec3,
        v: Vec3,
        /// Unit normal of the front face.
        n: Vec3,
    },
    /// A disk in the plane spanned by the unit tangents `x`, `y`.
    Disk {
        center: Vec3,
        radius: Real,
        x: Vec3,
        y: Vec3,
        /// Unit normal of the front face.
        n: Vec3,
    },
}

impl EmitterShape {
    /// Surface area.
    pub(crate) fn area(&self) -> Real {
        match *self {
            EmitterShape::Triangle { e1, e2, .. } => 0.5 * e1.cross(e2).length(),
            EmitterShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            EmitterShape::Rect { u, v, .. } => u.cross(v).length(),
            EmitterShape::Disk { radius, .. } => PI * radius * radius,
        }
    }
}

/// One emitting primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Emitter {
    pub shape: EmitterShape,
    /// Emitted radiance on the front face.
    pub radiance: Rgb,
    /// `1 / area`.
    pub inv_area: Real,
    /// Probability of choosing this emitter.
    pub pmf: Real,
}

/// A point sampled on an emitter, seen from a shading point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightSample {
    /// The point on the light.
    pub point: Vec3,
    /// Unit direction from the shading point towards it.
    pub wi: Vec3,
    /// Radiance arriving from it (before occlusion).
    pub radiance: Rgb,
    /// Density of the sample per unit solid angle (emitter choice included).
    pub pdf: Real,
}

/// The area lights of a scene.
#[derive(Clone, Debug, Default)]
pub(crate) struct Emitters {
    pub list: Vec<Emitter>,
    /// Cumulative `pmf`, for choosing by a uniform number.
    cdf: Vec<Real>,
    /// Accelerator primitive → index in `list` (`u32::MAX`: not an emitter);
    /// empty when there is no emitter.
    pub of_prim: Vec<u32>,
}

impl Emitters {
    /// Adds the emitting primitive `prim` (index in the accelerator).
    pub(crate) fn push(&mut self, prim: usize, shape: EmitterShape, radiance: Rgb) {
        let Some(i) = self.push_shape(shape, radiance) else {
            return;
        };
        if self.of_prim.len() <= prim {
            self.of_prim.resize(prim + 1, u32::MAX);
        }
        self.of_prim[prim] = i;
    }

    /// Adds an emitter that is not an accelerator primitive (a rectangle or
    /// disk light) and returns its index in `list`; `None` when it has no
    /// area or no radiance.
    pub(crate) fn push_shape(&mut self, shape: EmitterShape, radiance: Rgb) -> Option<u32> {
        let area = shape.area();
        if !(area > 0.0) || !area.is_finite() || radiance == Rgb::ZERO {
            return None;
        }
        let i = self.list.len() as u32;
        self.list.push(Emitter {
            shape,
            radiance,
            inv_area: 1.0 / area,
            pmf: 0.0,
        });
        Some(i)
    }

    /// Emitter `i` of `list`.
    #[inline]
    pub(crate) fn get(&self, i: u32) -> Option<&Emitter> {
        self.list.get(i as usize)
    }

    /// Finishes the table once every emitter is in: the choice
    /// probabilities in proportion to power (area × mean radiance), and the
    /// map from primitives padded to `prims` entries.
    pub(crate) fn finish(&mut self, prims: usize) {
        if self.list.is_empty() {
            self.of_prim.clear();
            return;
        }
        self.of_prim.resize(prims, u32::MAX);
        let power = |e: &Emitter| {
            let l = e.radiance;
            Real::from((l.x + l.y + l.z) / 3.0) / e.inv_area
        };
        let total: Real = self.list.iter().map(power).sum();
        let mut acc = 0.0;
        self.cdf.clear();
        for e in &mut self.list {
            e.pmf = power(e) / total;
            acc += e.pmf;
            self.cdf.push(acc);
        }
    }

    /// Whether the scene has any area light.
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The emitter of accelerator primitive `prim`, if it emits.
    #[inline]
    pub(crate) fn of(&self, prim: u32) -> Option<&Emitter> {
        let i = *self.of_prim.get(prim as usize)?;
        self.list.get(i as usize)
    }

    /// Chooses an emitter by `u1` and a point on it by `u2`, as seen from
    /// `p`. `None` when the point faces away (one-sided emission) or
    /// coincides with `p`.
    #[inline]
    pub(crate) fn sample(&self, p: Vec3, u1: Real, u2: (Real, Real)) -> Option<LightSample> {
        let i = self
            .cdf
            .partition_point(|&c| c <= u1)
            .min(self.list.len() - 1);
        let e = &self.list[i];
        let (q, n) = match e.shape {
            EmitterShape::Triangle { p0, e1, e2, n } => {
                let (b1, b2) = uniform_triangle(u2);
                (p0 + e1 * b1 + e2 * b2, n)
            }
            EmitterShape::Sphere { center, radius } => {
                let n = uniform_sphere(u2);
                (center + n * radius, n)
            }
            EmitterShape::Rect { corner, u, v, n } => (corner + u * u2.0 + v * u2.1, n),
            EmitterShape::Disk {
                center,
                radius,
                x,
                y,
                n,
            } => {
                let (a, b) = concentric_disk(u2);
                (center + (x * a + y * b) * radius, n)
            }
        };
        let d = q - p;
        let dist2 = d.length_squared();
        if !(dist2 > 0.0) {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let cos_l = -n.dot(wi);
        if !(cos_l > 0.0) {
            return None;
        }
        Some(LightSample {
            point: q,
            wi,
            radiance: e.radiance,
            pdf: e.pmf * dist2 / (e.inv_area.recip() * cos_l),
        })
    }

    /// Density per unit solid angle with which [`Emitters::sample`] picks
    /// the point at distance `dist` along the unit direction `wi` on `e`,
    /// whose normal there is `n`.
    #[inline]
    pub(crate) fn pdf(e: &Emitter, wi: Vec3, dist: Real, n: Vec3) -> Real {
        let cos_l = n.dot(wi).abs();
        if cos_l > 0.0 {
            e.pmf * dist * dist * e.inv_area / cos_l
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> Emitters {
        // A unit square at y = 1 facing down (−y), radiance 2.
        let mut e = Emitters::default();
        let a = Vec3::new(0.0, 1.0, 0.0);
        let b = Vec3::new(1.0, 1.0, 0.0);
        let c = Vec3::new(1.0, 1.0, 1.0);
        let d = Vec3::new(0.0, 1.0, 1.0);
        for (i, (p0, p1, p2)) in [(a, b, c), (a, c, d)].into_iter().enumerate() {
            let (e1, e2) = (p1 - p0, p2 - p0);
            let n = e1.cross(e2).normalize();
            e.push(i, EmitterShape::Triangle { p0, e1, e2, n }, Rgb::splat(2.0));
        }
        e.finish(2);
        e
    }

    #[test]
    fn the_irradiance_of_a_square_light_is_estimated_right() {
        let e = quad();
        // Both triangles of the square face −y (counter-clockwise seen from below).
        assert!(e
            .list
            .iter()
            .all(|l| matches!(l.shape, EmitterShape::Triangle { n, .. } if n.y < -0.99)));
        // E at the origin, normal +y: ∫ L cos θ dω, by light sampling; the
        // closed form for a unit square at height 1 with a corner above the
        // point is the form-factor integral, here checked against a fine
        // midpoint sum over the square.
        let p = Vec3::ZERO;
        let n = 400;
        let mut est = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u1 = (i as Real + 0.5) / n as Real;
                let u2 = (
                    (j as Real + 0.5) / n as Real,
                    ((i * 7 + j * 3) % n) as Real / n as Real,
                );
                if let Some(s) = e.sample(p, u1, u2) {
                    est += crate::float::to_f64(Real::from(s.radiance.x) * s.wi.y / s.pdf);
                }
            }
        }
        est /= f64::from(n * n);
        let m = 400;
        let mut want = 0.0f64;
        for i in 0..m {
            for j in 0..m {
                let x = (f64::from(i) + 0.5) / f64::from(m);
                let z = (f64::from(j) + 0.5) / f64::from(m);
                let r2 = x * x + 1.0 + z * z;
                // L cos θ cos θ_l / r² dA with cos θ = cos θ_l = 1/r.
                want += 2.0 / (r2 * r2) / f64::from(m * m);
            }
        }
        assert!((est - want).abs() < 0.01 * want, "{est} vs {want}");
    }

    /// Irradiance at the origin (normal +y) from `e`, by light sampling on
    /// an `n × n` stratified grid of sample pairs.
    fn irradiance(e: &Emitters, n: u32) -> f64 {
        let mut est = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u2 = ((i as Real + 0.5) / n as Real, (j as Real + 0.5) / n as Real);
                if let Some(s) = e.sample(Vec3::ZERO, 0.5, u2) {
                    est += crate::float::to_f64(Real::from(s.radiance.x) * s.wi.y / s.pdf);
                }
            }
        }
        est / f64::from(n * n)
    }

    #[test]
    fn a_disk_light_gives_the_closed_form_irradiance() {
        // A disk of radius r at height h facing down: E = π·L·r²/(r² + h²).
        let (r, h, l) = (0.5, 1.0, 3.0);
        let mut e = Emitters::default();
        let f = crate::sampling::maps::Frame::new(Vec3::NEG_Y);
        let shape = EmitterShape::Disk {
            center: Vec3::new(0.0, h, 0.0),
            radius: r,
            x: f.x,
            y: f.y,
            n: Vec3::NEG_Y,
        };
        assert_eq!(e.push_shape(shape, Rgb::splat(l)), Some(0));
        e.finish(0);
        let want = std::f64::consts::PI * f64::from(l) * 0.25 / (0.25 + 1.0);
        let est = irradiance(&e, 300);
        assert!((est - want).abs() < 2e-3 * want, "{est} vs {want}");
    }

    #[test]
    fn a_rect_light_matches_its_two_triangles() {
        let mut e = Emitters::default();
        let shape = EmitterShape::Rect {
            corner: Vec3::new(0.0, 1.0, 0.0),
            u: Vec3::X,
            v: Vec3::Z,
            n: Vec3::NEG_Y,
        };
        e.push_shape(shape, Rgb::splat(2.0));
        e.finish(0);
        let (a, b) = (irradiance(&e, 300), irradiance(&quad(), 300));
        assert!((a - b).abs() < 5e-3 * b, "{a} vs {b}");
        // Nothing from behind, nothing of no area.
        assert!(e
            .sample(Vec3::new(0.5, 2.0, 0.5), 0.5, (0.5, 0.5))
            .is_none());
        let flat = EmitterShape::Rect {
            corner: Vec3::ZERO,
            u: Vec3::X,
            v: Vec3::X,
            n: Vec3::Y,
        };
        assert_eq!(e.push_shape(flat, Rgb::ONE), None);
    }

    #[test]
    fn emission_is_one_sided() {
        let e = quad();
        // Above the square, its back faces us: nothing.
        assert!(e
            .sample(Vec3::new(0.5, 2.0, 0.5), 0.3, (0.2, 0.4))
            .is_none());
        assert!(e
            .sample(Vec3::new(0.5, 0.0, 0.5), 0.3, (0.2, 0.4))
            .is_some());
    }

    #[test]
    fn pdfs_of_sampling_and_lookup_agree() {
        let e = quad();
        let p = Vec3::new(0.3, 0.2, 0.6);
        let s = e.sample(p, 0.7, (0.3, 0.8)).unwrap();
        let i = usize::from(0.7 > e.cdf[0]);
        let n = match e.list[i].shape {
            EmitterShape::Triangle { n, .. } => n,
            _ => unreachable!(),
        };
        let pdf = Emitters::pdf(&e.list[i], s.wi, (s.point - p).length(), n);
        assert!((pdf - s.pdf).abs() < 1e-4 * s.pdf);
    }
}
