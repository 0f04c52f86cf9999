//! Shared helpers: a seeded generator and the checks every hit must pass.

use gridrt_bbox::{gamma, Aabb, Ray, Real, Vec3};

pub const INF: Real = Real::INFINITY;

/// The unit cube `[0, 1]³`.
pub fn unit() -> Aabb {
    Aabb::new(Vec3::ZERO, Vec3::ONE)
}

pub fn v(x: Real, y: Real, z: Real) -> Vec3 {
    Vec3::new(x, y, z)
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny seeded generator, so the
/// loop tests need no RNG crate and always see the same inputs.
#[derive(Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`, drawn in f64 and rounded to `Real`.
    pub fn range(&mut self, lo: f64, hi: f64) -> Real {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        (lo + (hi - lo) * u) as Real
    }
}

/// The interval contract of `Aabb::hit`: on a hit, nothing is NaN and
/// `t_min <= t_enter <= t_exit <= t_max`. Returns the hit unchanged.
#[track_caller]
pub fn checked_hit(b: &Aabb, r: &Ray, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
    let h = b.hit(r, t_min, t_max);
    if let Some((t0, t1)) = h {
        assert!(
            !t0.is_nan() && !t1.is_nan(),
            "NaN interval {h:?} for {b:?} {r:?}"
        );
        assert!(
            t_min <= t0 && t0 <= t1 && t1 <= t_max,
            "interval {h:?} not ordered within [{t_min}, {t_max}] for {b:?} {r:?}"
        );
    }
    h
}

/// The exit bound the conservative slab test may report for a true exit `t`:
/// at most 2·γ(3) above it, plus a few ulps for the widening's own rounding.
pub fn widened(t: Real) -> Real {
    t + t.abs() * (2.0 * gamma(3)) + t.abs() * 4.0 * Real::EPSILON
}
