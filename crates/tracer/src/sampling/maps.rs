//! Maps from the unit square to the disk, the hemisphere and the sphere,
//! with their densities (Suffern ch. 6 and 7; pbrt-v4 A.5).
//!
//! Hemisphere maps are in a local frame whose z axis is the normal (or the
//! lobe's axis); [`Frame`] takes them to world space.

use gridrt_bbox::{Real, Vec3};

const PI: Real = std::f64::consts::PI as Real;

/// Shirley and Chiu's concentric map from `[0, 1)²` to the unit disk: area
/// preserving (uniform density `1/π`) and with little distortion, so
/// stratification survives it.
#[inline]
#[must_use]
pub fn concentric_disk(u: (Real, Real)) -> (Real, Real) {
    let a = 2.0 * u.0 - 1.0;
    let b = 2.0 * u.1 - 1.0;
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, (PI / 4.0) * (b / a))
    } else {
        (b, PI / 2.0 - (PI / 4.0) * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

/// A cosine-weighted direction about +z (Malley's method: a point of the
/// concentric disk lifted to the hemisphere). Density `cos θ / π`.
#[inline]
#[must_use]
pub fn cosine_hemisphere(u: (Real, Real)) -> Vec3 {
    let (x, y) = concentric_disk(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    Vec3::new(x, y, z)
}

/// Density of [`cosine_hemisphere`] for a direction with `cos θ = cos`.
#[inline]
#[must_use]
pub fn cosine_hemisphere_pdf(cos: Real) -> Real {
    cos.max(0.0) / PI
}

/// A direction about +z with density proportional to `cosⁿθ` (the Phong
/// lobe, Suffern §25.2): `cos θ = u₁^(1/(n+1))`. Density
/// `(n + 1)/(2π)·cosⁿθ`.
#[inline]
#[must_use]
pub fn cosine_power_lobe(u: (Real, Real), n: Real) -> Vec3 {
    let cos = u.0.powf(1.0 / (n + 1.0));
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// Density of [`cosine_power_lobe`] for `cos θ = cos` about the lobe axis.
#[inline]
#[must_use]
pub fn cosine_power_lobe_pdf(cos: Real, n: Real) -> Real {
    if cos <= 0.0 {
        0.0
    } else {
        (n + 1.0) / (2.0 * PI) * cos.powf(n)
    }
}

/// A uniformly distributed direction on the unit sphere (density `1/(4π)`).
#[inline]
#[must_use]
pub fn uniform_sphere(u: (Real, Real)) -> Vec3 {
    let z = 1.0 - 2.0 * u.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A uniformly distributed point of a triangle, as barycentrics `(b1, b2)`
/// of its second and third vertices (Heitz's low-distortion map, 2019).
#[inline]
#[must_use]
pub fn uniform_triangle(u: (Real, Real)) -> (Real, Real) {
    let (b0, b1);
    if u.0 < u.1 {
        b0 = u.0 / 2.0;
        b1 = u.1 - b0;
    } else {
        b1 = u.1 / 2.0;
        b0 = u.0 - b1;
    }
    (b1, 1.0 - b0 - b1)
}

/// An orthonormal frame whose z axis is a given unit vector (Duff et al.,
/// "Building an Orthonormal Basis, Revisited", JCGT 2017).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub x: Vec3,
    /// Second tangent.
    pub y: Vec3,
    /// The axis.
    pub z: Vec3,
}

impl Frame {
    /// The frame about the unit vector `n`.
    #[inline]
    #[must_use]
    pub fn new(n: Vec3) -> Self {
        let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Self {
            x: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            y: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            z: n,
        }
    }

    /// A local direction in world space.
    #[inline]
    #[must_use]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }

    /// A world direction in the local frame (the inverse of
    /// [`Frame::to_world`]).
    #[inline]
    #[must_use]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{sample_2d, SamplerKind};
    use proptest::prelude::*;

    fn points(n: u32) -> impl Iterator<Item = (Real, Real)> {
        (0..n).map(move |s| sample_2d(SamplerKind::Sobol, 3, s, n, 1))
    }

    #[test]
    fn the_disk_map_is_uniform() {
        // Mean of r² over the unit disk is 1/2; mean of x is 0.
        let n = 4096;
        let (mut r2, mut x) = (0.0f64, 0.0f64);
        for u in points(n) {
            let (a, b) = concentric_disk(u);
            r2 += crate::float::to_f64(a * a + b * b);
            x += crate::float::to_f64(a);
        }
        assert!((r2 / f64::from(n) - 0.5).abs() < 0.005);
        assert!((x / f64::from(n)).abs() < 0.005);
    }

    #[test]
    fn cosine_samples_have_the_right_moments() {
        // E[cos θ] = 2/3 under the density cos θ/π.
        let n = 4096;
        let mean: f64 = points(n)
            .map(|u| crate::float::to_f64(cosine_hemisphere(u).z))
            .sum::<f64>()
            / f64::from(n);
        assert!((mean - 2.0 / 3.0).abs() < 0.005, "{mean}");
        // The cosine-power lobe: E[cos θ] = (n + 1)/(n + 2).
        for e in [1.0 as Real, 10.0, 100.0] {
            let mean: f64 = points(n)
                .map(|u| crate::float::to_f64(cosine_power_lobe(u, e).z))
                .sum::<f64>()
                / f64::from(n);
            let want = crate::float::to_f64((e + 1.0) / (e + 2.0));
            assert!((mean - want).abs() < 0.005, "exp {e}: {mean} vs {want}");
        }
    }

    #[test]
    fn sphere_samples_have_zero_mean_and_unit_length() {
        let n = 4096;
        let mut m = Vec3::ZERO;
        for u in points(n) {
            let d = uniform_sphere(u);
            assert!((d.length() - 1.0).abs() < 1e-5);
            m += d;
        }
        assert!((m / n as Real).length() < 0.01);
    }

    #[test]
    fn lobe_pdfs_integrate_to_one() {
        // ∫ p dω over the hemisphere by the midpoint rule in cos θ.
        for e in [0.0 as Real, 1.0, 20.0] {
            let steps = 20_000;
            let mut sum = 0.0f64;
            for i in 0..steps {
                let c = (i as Real + 0.5) / steps as Real;
                sum +=
                    crate::float::to_f64(cosine_power_lobe_pdf(c, e)) * 2.0 * std::f64::consts::PI
                        / f64::from(steps);
            }
            assert!((sum - 1.0).abs() < 1e-3, "exp {e}: {sum}");
        }
    }

    proptest! {
        #[test]
        fn disk_points_lie_on_the_disk(a in 0.0f64..1.0, b in 0.0f64..1.0) {
            let (x, y) = concentric_disk((a as Real, b as Real));
            prop_assert!(x * x + y * y <= 1.0 + 1e-5);
        }

        #[test]
        fn hemisphere_directions_are_unit_and_up(a in 0.0f64..1.0, b in 0.0f64..1.0, e in 0.0f64..1000.0) {
            let u = (a as Real, b as Real);
            for d in [cosine_hemisphere(u), cosine_power_lobe(u, e as Real)] {
                prop_assert!((d.length() - 1.0).abs() < 1e-4);
                prop_assert!(d.z >= 0.0);
            }
        }

        #[test]
        fn triangle_points_are_inside(a in 0.0f64..1.0, b in 0.0f64..1.0) {
            let (b1, b2) = uniform_triangle((a as Real, b as Real));
            prop_assert!(b1 >= 0.0 && b2 >= -1e-6 && b1 + b2 <= 1.0 + 1e-6);
        }

        #[test]
        fn frames_are_orthonormal(x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0) {
            let n = Vec3::new(x as Real, y as Real, z as Real);
            prop_assume!(n.length() > 0.1);
            let f = Frame::new(n.normalize());
            prop_assert!(f.x.dot(f.y).abs() < 1e-4 && f.x.dot(f.z).abs() < 1e-4 && f.y.dot(f.z).abs() < 1e-4);
            prop_assert!((f.x.length() - 1.0).abs() < 1e-4 && (f.y.length() - 1.0).abs() < 1e-4);
        }
    }
}
