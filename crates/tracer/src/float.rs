//! Floating-point helpers: stepping by one ULP and offsetting ray origins by
//! a bound on the rounding error of a hit point (pbrt-v4 `OffsetRayOrigin`).

use gridrt_bbox::{Real, Vec3};

/// The unsigned integer with the bit layout of [`Real`].
#[cfg(not(feature = "f64"))]
type Bits = u32;
#[cfg(feature = "f64")]
type Bits = u64;

/// A [`Real`] as `f32` (colour arithmetic is always `f32`).
#[inline]
#[must_use]
#[allow(clippy::unnecessary_cast)] // a no-op unless the `f64` feature is on
pub(crate) fn to_f32(x: Real) -> f32 {
    x as f32
}

pub(crate) use gridrt_bbox::math::to_f64;

/// The next representable value above `x` (`+∞` stays, NaN stays NaN).
///
/// Written out because `f32::next_up` is newer than the workspace's MSRV.
#[inline]
#[must_use]
pub(crate) fn next_up(x: Real) -> Real {
    if x.is_nan() || x == Real::INFINITY {
        return x;
    }
    if x == 0.0 {
        // Both zeros step to the smallest positive subnormal.
        return Real::from_bits(1);
    }
    let b: Bits = x.to_bits();
    Real::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

/// The next representable value below `x` (`−∞` stays, NaN stays NaN).
#[inline]
#[must_use]
pub(crate) fn next_down(x: Real) -> Real {
    -next_up(-x)
}

/// Moves a surface point off the surface so that a ray leaving it along `w`
/// cannot hit the same surface again through rounding (pbrt-v4
/// `OffsetRayOrigin`, Pharr, Jakob & Humphreys 2023, §6.8.6).
///
/// `p_err` bounds, per axis, the absolute rounding error of `p`; `n` is the
/// geometric normal (either orientation). The point moves along `±n` by the
/// projection of the error box on `n`, to the side `w` points to, and then one
/// more ULP per axis away from `p`, so that the rounding of the addition
/// cannot pull it back. No fixed epsilon: the offset scales with the error.
/// Unlike pbrt, the ULP step is taken along every axis where `n` is non-zero
/// even when the error bound is zero, so a point computed exactly still
/// leaves its surface; and a coordinate it moves never ends subnormal: a
/// point at 0 (an exact hit on a coordinate plane) steps to the smallest
/// normal number instead of the smallest subnormal, further out on the
/// same side. Subnormal operands cost the CPU a microcode assist in every
/// later test of the ray (about 100 cycles each on x86): shadow rays from
/// such points were several times slower than others.
#[inline]
#[must_use]
pub(crate) fn offset_ray_origin(p: Vec3, p_err: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_err);
    let side = if w.dot(n) < 0.0 { -1.0 } else { 1.0 };
    let dir = n * side;
    let mut po = p + dir * d;
    for a in 0..3 {
        // Past a subnormal (or zero) the step continues to the smallest
        // normal number of the same direction.
        if dir[a] > 0.0 {
            po[a] = next_up(po[a]);
            if po[a].abs() < Real::MIN_POSITIVE {
                po[a] = Real::MIN_POSITIVE;
            }
        } else if dir[a] < 0.0 {
            po[a] = next_down(po[a]);
            if po[a].abs() < Real::MIN_POSITIVE {
                po[a] = -Real::MIN_POSITIVE;
            }
        }
    }
    po
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_bbox::gamma;

    #[test]
    fn next_up_and_down_step_one_ulp() {
        assert_eq!(next_up(1.0), 1.0 + Real::EPSILON);
        assert_eq!(next_down(1.0), 1.0 - Real::EPSILON / 2.0);
        assert!(next_up(0.0) > 0.0 && next_up(-0.0) > 0.0);
        assert!(next_down(0.0) < 0.0);
        assert_eq!(next_up(-1.0), -(1.0 - Real::EPSILON / 2.0));
        assert_eq!(next_up(Real::INFINITY), Real::INFINITY);
        assert_eq!(next_up(Real::NEG_INFINITY), Real::MIN);
        assert!(next_up(Real::NAN).is_nan());
    }

    #[test]
    fn offset_moves_to_the_side_of_w_and_beyond_the_error() {
        let p = Vec3::new(1000.0, 0.0, 0.0);
        let err = Vec3::splat(gamma(5)) * p.abs();
        let n = Vec3::X;
        let out = offset_ray_origin(p, err, n, Vec3::new(1.0, 1.0, 0.0));
        assert!(out.x > p.x + err.x);
        assert_eq!((out.y, out.z), (0.0, 0.0));
        let inside = offset_ray_origin(p, err, n, -Vec3::X);
        assert!(inside.x < p.x - err.x);
        // A zero error bound still moves the point by one ULP along the normal.
        let exact = offset_ray_origin(p, Vec3::ZERO, n, Vec3::X);
        assert_eq!(exact, Vec3::new(next_up(p.x), 0.0, 0.0));
        let at_zero = offset_ray_origin(Vec3::ZERO, Vec3::ZERO, -Vec3::Y, Vec3::Y);
        assert!(at_zero.y > 0.0 && at_zero.x == 0.0);
        // Never a subnormal coordinate: from 0 (and from subnormals) the
        // step goes to the smallest normal number on the chosen side.
        assert_eq!(at_zero.y, Real::MIN_POSITIVE);
        let below = offset_ray_origin(Vec3::ZERO, Vec3::ZERO, Vec3::Y, -Vec3::Y);
        assert_eq!(below.y, -Real::MIN_POSITIVE);
        let tiny = Vec3::new(0.0, -Real::from_bits(3), 0.0);
        assert_eq!(
            offset_ray_origin(tiny, Vec3::ZERO, Vec3::Y, Vec3::Y).y,
            Real::MIN_POSITIVE
        );
        let normal = Vec3::new(0.0, 2.0 * Real::MIN_POSITIVE, 0.0);
        assert_eq!(
            offset_ray_origin(normal, Vec3::ZERO, Vec3::Y, -Vec3::Y).y,
            next_down(normal.y)
        );
    }
}
