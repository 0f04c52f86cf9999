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
