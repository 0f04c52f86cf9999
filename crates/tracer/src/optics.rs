//! Reflection, refraction and the Fresnel equations for smooth dielectrics.

use gridrt_bbox::{Real, Vec3};

/// Mirror direction of `wo` (pointing away from the surface) about `n`:
/// `−wo + 2(n·wo)n`.
#[inline]
#[must_use]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + n * (2.0 * n.dot(wo))
}

/// Fresnel reflectance of a smooth dielectric boundary for unpolarised
/// light (the mean of the s and p terms).
///
/// `cos_i` is the cosine of the incident angle (≥ 0) and `eta` the ratio
/// `η_t / η_i` of the refractive index on the far side to the one on the
/// ray's side. Returns 1 under total internal reflection
/// (`sin²θ_t = (1 − cos²θ_i)/η² ≥ 1`). At normal incidence it is
/// `((η − 1)/(η + 1))²`.
///
/// ```
/// use gridrt_tracer::optics::fresnel_dielectric;
/// let f0 = fresnel_dielectric(1.0, 1.5);
/// assert!((f0 - 0.04).abs() < 1e-6);
/// // From inside glass at a grazing angle: total internal reflection.
/// assert_eq!(fresnel_dielectric(0.1, 1.0 / 1.5), 1.0);
/// ```
#[inline]
#[must_use]
pub fn fresnel_dielectric(cos_i: Real, eta: Real) -> Real {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

/// The refracted direction of `wo` (pointing away from the surface, on the
/// side `n` points to) into the far side, for `eta = η_t / η_i`; `None` under
/// total internal reflection. `wo` and `n` are unit vectors; the result is
/// a unit vector.
#[inline]
#[must_use]
pub fn refract(wo: Vec3, n: Vec3, eta: Real) -> Option<Vec3> {
    let cos_i = n.dot(wo).clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wo / eta + n * (cos_i / eta - cos_t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_the_closed_form() {
        for n in [1.2 as Real, 1.333, 1.5, 2.4] {
            let expected = ((n - 1.0) / (n + 1.0)).powi(2);
            assert!((fresnel_dielectric(1.0, n) - expected).abs() < 1e-6);
            // The same leaving the denser medium.
            assert!((fresnel_dielectric(1.0, 1.0 / n) - expected).abs() < 1e-6);
        }
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        let eta: Real = 1.0 / 1.5;
        let critical_cos = (1.0 - eta * eta).sqrt();
        assert_eq!(fresnel_dielectric(critical_cos * 0.99, eta), 1.0);
        assert!(fresnel_dielectric(critical_cos * 1.01, eta) < 1.0);
        assert_eq!(fresnel_dielectric(0.0, eta), 1.0);
        let wo = Vec3::new(0.99, 0.141, 0.0).normalize();
        assert!(refract(wo, Vec3::Y, eta).is_none());
        // Grazing from outside: reflectance tends to 1 but light still enters.
        assert!(fresnel_dielectric(1e-3, 1.5) > 0.99);
        assert!(refract(wo, Vec3::Y, 1.5).is_some());
    }

    #[test]
    fn refraction_obeys_snell() {
        let wo = Vec3::new(0.6, 0.8, 0.0);
        let t = refract(wo, Vec3::Y, 1.5).unwrap();
        assert!((t.length() - 1.0).abs() < 1e-6);
        // sin θ_i = 0.6 (on the other side, pointing away) → sin θ_t = 0.4.
        assert!((t.x + 0.4).abs() < 1e-6 && t.y < 0.0);
        let r = reflect(wo, Vec3::Y);
        assert!((r - Vec3::new(-0.6, 0.8, 0.0)).length() < 1e-6);
    }
}
