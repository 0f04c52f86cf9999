//! The scalar type and the floating-point error bounds used across gridrt.

/// The scalar type of the whole stack: `f32` by default, `f64` with the `f64` feature.
#[cfg(not(feature = "f64"))]
pub type Real = f32;
/// The scalar type of the whole stack: `f32` by default, `f64` with the `f64` feature.
#[cfg(feature = "f64")]
pub type Real = f64;

/// The 3-vector of [`Real`]: `glam::Vec3` by default, `glam::DVec3` with `f64`.
#[cfg(not(feature = "f64"))]
pub type Vec3 = glam::Vec3;
/// The 3-vector of [`Real`]: `glam::Vec3` by default, `glam::DVec3` with `f64`.
#[cfg(feature = "f64")]
pub type Vec3 = glam::DVec3;

/// A [`Real`] as `f64`: exact in both builds (a no-op with `f64`), for
/// reports and error measurements written once for either build.
#[inline]
#[must_use]
#[allow(clippy::unnecessary_cast)] // a no-op with the `f64` feature
pub fn to_f64(x: Real) -> f64 {
    x as f64
}

/// A 3-vector held in one SIMD register whose fourth lane is defined:
/// `glam::Vec3A` by default, `glam::DVec3` with `f64`. Its lane-wise
/// arithmetic and `dot` round exactly as [`Vec3`]'s. Kernels load operands
/// into it when the compiler would otherwise widen [`Vec3`] arithmetic to four
/// lanes and read the bytes after a value (an enum's unused bytes, say): a
/// subnormal pattern there costs a microcode assist per operation although
/// its lane is discarded.
#[cfg(not(feature = "f64"))]
pub type Vec3Lanes = glam::Vec3A;
/// A 3-vector held in one SIMD register whose fourth lane is defined:
/// `glam::Vec3A` by default, `glam::DVec3` with `f64`.
#[cfg(feature = "f64")]
pub type Vec3Lanes = glam::DVec3;

/// Four lanes of [`Real`] (SIMD on x86-64): `glam::Vec4`, or `glam::DVec4`
/// with `f64`. For testing four primitives at once.
#[cfg(not(feature = "f64"))]
pub type Lanes = glam::Vec4;
/// Four lanes of [`Real`] (SIMD on x86-64): `glam::Vec4`, or `glam::DVec4`
/// with `f64`. For testing four primitives at once.
#[cfg(feature = "f64")]
pub type Lanes = glam::DVec4;

/// Four [`Lanes`] as the columns of a matrix, whose `transpose` turns four
/// records of four values (one a column) into four lanes of each value.
///
/// ```
/// use gridrt_bbox::math::{LaneMat, Lanes};
/// let m = LaneMat::from_cols_array_2d(&[[1.0, 2.0, 3.0, 4.0]; 4]).transpose();
/// assert_eq!(m.y_axis, Lanes::splat(2.0));
/// ```
#[cfg(not(feature = "f64"))]
pub type LaneMat = glam::Mat4;
/// Four [`Lanes`] as the columns of a matrix, whose `transpose` turns four
/// records of four values (one a column) into four lanes of each value.
#[cfg(feature = "f64")]
pub type LaneMat = glam::DMat4;

/// The unit roundoff of [`Real`] (half the machine epsilon): the largest
/// relative error of one correctly rounded operation.
pub const UNIT_ROUNDOFF: Real = Real::EPSILON * 0.5;

/// Higham's γ(n) = n·u / (1 − n·u): a bound on the relative error of `n`
/// consecutive rounded operations (pbrt-v4 `gamma`, Higham 2002 §3.1).
///
/// ```
/// use gridrt_bbox::gamma;
/// assert!(gamma(3) > 3.0 * gridrt_bbox::math::UNIT_ROUNDOFF);
/// assert!(gamma(3) < 4.0 * gridrt_bbox::math::UNIT_ROUNDOFF);
/// ```
#[inline]
#[must_use]
pub fn gamma(n: u32) -> Real {
    let nu = n as Real * UNIT_ROUNDOFF;
    nu / (1.0 - nu)
}

/// Lane-wise choices by one comparison, with that comparison's answer for
/// NaN and signed zeros: `a.max_gt(b)` is `if a > b { a } else { b }` in
/// each lane and `a.min_lt(b)` is `if a < b { a } else { b }` (both `b`
/// when the lanes are unordered). Unlike `max` and `min`, whose NaN and
/// `±0` answers differ between targets, these are the same everywhere: on
/// x86 they are SSE's `maxps` and `minps`, one instruction where a compare
/// and a select take three or four; elsewhere the select itself.
pub trait LaneChoice: Sized {
    /// `if a > b { a } else { b }` in each lane.
    #[must_use]
    fn max_gt(self, b: Self) -> Self;
    /// `if a < b { a } else { b }` in each lane.
    #[must_use]
    fn min_lt(self, b: Self) -> Self;
}

/// Implements [`LaneChoice`] for a `glam` type held in an SSE register.
#[cfg(all(not(feature = "f64"), target_feature = "sse2"))]
macro_rules! sse_lane_choice {
    ($t:ty) => {
        impl LaneChoice for $t {
            #[inline(always)]
            fn max_gt(self, b: Self) -> Self {
                #[cfg(target_arch = "x86")]
                use std::arch::x86::_mm_max_ps;
                #[cfg(target_arch = "x86_64")]
                use std::arch::x86_64::_mm_max_ps;
                // SAFETY: SSE2 is enabled (the `cfg`); `maxps` gives its
                // first operand where it compares greater, else its second.
                Self::from(unsafe { _mm_max_ps(self.into(), b.into()) })
            }
            #[inline(always)]
            fn min_lt(self, b: Self) -> Self {
                #[cfg(target_arch = "x86")]
                use std::arch::x86::_mm_min_ps;
                #[cfg(target_arch = "x86_64")]
                use std::arch::x86_64::_mm_min_ps;
                // SAFETY: as for `max_gt`; `minps` gives its first operand
                // where it compares less, else its second.
                Self::from(unsafe { _mm_min_ps(self.into(), b.into()) })
            }
        }
    };
}

/// Implements [`LaneChoice`] by a comparison and a select.
#[cfg(any(feature = "f64", not(target_feature = "sse2")))]
macro_rules! select_lane_choice {
    ($t:ty) => {
        impl LaneChoice for $t {
            #[inline(always)]
            fn max_gt(self, b: Self) -> Self {
                <$t>::select(self.cmpgt(b), self, b)
            }
            #[inline(always)]
            fn min_lt(self, b: Self) -> Self {
                <$t>::select(self.cmplt(b), self, b)
            }
        }
    };
}

#[cfg(all(not(feature = "f64"), target_feature = "sse2"))]
sse_lane_choice!(Lanes);
#[cfg(all(not(feature = "f64"), target_feature = "sse2"))]
sse_lane_choice!(Vec3Lanes);
#[cfg(any(feature = "f64", not(target_feature = "sse2")))]
select_lane_choice!(Lanes);
#[cfg(any(feature = "f64", not(target_feature = "sse2")))]
select_lane_choice!(Vec3Lanes);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_roundoff_is_half_an_ulp_of_one() {
        // 1 + u is a tie and rounds to even (1); 1 + 2u is the next float.
        // `black_box` keeps the sums at run time, in real rounding.
        let one: Real = std::hint::black_box(1.0);
        assert_eq!(one + UNIT_ROUNDOFF, 1.0);
        assert_eq!(one + 2.0 * UNIT_ROUNDOFF, 1.0 + Real::EPSILON);
        assert_eq!(UNIT_ROUNDOFF, Real::EPSILON / 2.0);
    }

    #[test]
    fn gamma_is_zero_at_zero_and_increasing() {
        assert_eq!(gamma(0), 0.0);
        let mut prev = 0.0;
        for n in 1..64 {
            let g = gamma(n);
            assert!(
                g > prev,
                "gamma({n}) = {g} not above gamma({}) = {prev}",
                n - 1
            );
            // γ(n) = nu / (1 - nu) lies strictly above nu, and only just.
            let nu = n as Real * UNIT_ROUNDOFF;
            assert!(g > nu && g < 1.01 * nu);
            prev = g;
        }
    }

    #[test]
    fn lane_choices_are_the_comparisons_answers() {
        let nan = Real::NAN;
        let a = Lanes::new(1.0, nan, 0.0, -0.0);
        let b = Lanes::new(2.0, 3.0, -0.0, nan);
        let bits = |v: Lanes| v.to_array().map(Real::to_bits);
        for (x, y) in [(a, b), (b, a)] {
            let want_max = Lanes::select(x.cmpgt(y), x, y);
            let want_min = Lanes::select(x.cmplt(y), x, y);
            assert_eq!(bits(x.max_gt(y)), bits(want_max));
            assert_eq!(bits(x.min_lt(y)), bits(want_min));
            let three = |v: Lanes| Vec3Lanes::new(v.x, v.y, v.z);
            let (x3, y3) = (three(x), three(y));
            let (m3, n3) = (x3.max_gt(y3), x3.min_lt(y3));
            for k in 0..3 {
                assert_eq!(m3[k].to_bits(), want_max[k].to_bits());
                assert_eq!(n3[k].to_bits(), want_min[k].to_bits());
            }
        }
    }

    #[test]
    fn real_and_vec3_agree_on_precision() {
        let expected = if cfg!(feature = "f64") { 8 } else { 4 };
        assert_eq!(std::mem::size_of::<Real>(), expected);
        let v = Vec3::splat(1.0 as Real);
        let x: Real = v.x;
        assert_eq!(x, 1.0);
    }
}
