//! Lights beyond points and directions: the cone of spot lights, the
//! rectangle and disk area lights, which are surfaces of their own outside
//! the grid (tested one by one after the grid query, as planes are), and
//! the environment light.

mod area;
mod environment;

pub(crate) use area::AreaLight;
pub(crate) use environment::Environment;

use gridrt_bbox::Real;

/// The share of a spot light's intensity that leaves at angle θ from its
/// axis, given `cos θ`: 1 inside the inner cone, 0 outside the outer cone,
/// and pbrt-v4's smoothstep in the cosine between.
#[inline]
#[must_use]
pub(crate) fn spot_falloff(cos: Real, cos_outer: Real, cos_inner: Real) -> f32 {
    if cos >= cos_inner {
        return 1.0;
    }
    if !(cos > cos_outer) {
        return 0.0;
    }
    let x = ((cos - cos_outer) / (cos_inner - cos_outer)).clamp(0.0, 1.0);
    crate::float::to_f32(x * x * (3.0 - 2.0 * x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spot_falloff_is_full_inside_and_zero_outside() {
        let (outer, inner) = (
            (40.0 as Real).to_radians().cos(),
            (30.0 as Real).to_radians().cos(),
        );
        assert_eq!(spot_falloff(1.0, outer, inner), 1.0);
        assert_eq!(spot_falloff(inner, outer, inner), 1.0);
        assert_eq!(spot_falloff(outer, outer, inner), 0.0);
        assert_eq!(spot_falloff(-1.0, outer, inner), 0.0);
        let mid = spot_falloff((35.0 as Real).to_radians().cos(), outer, inner);
        assert!(mid > 0.3 && mid < 0.7, "{mid}");
        // Monotonic in the angle.
        let mut last = 1.0;
        for d in 0..=90 {
            let f = spot_falloff((d as Real).to_radians().cos(), outer, inner);
            assert!(f <= last);
            last = f;
        }
    }

    #[test]
    fn a_hard_edged_spot_has_no_falloff_band() {
        let c = (20.0 as Real).to_radians().cos();
        assert_eq!(spot_falloff(c + 1e-3, c, c), 1.0);
        assert_eq!(spot_falloff(c - 1e-3, c, c), 0.0);
    }
}
