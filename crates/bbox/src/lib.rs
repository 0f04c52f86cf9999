//! Rays, axis-aligned bounding boxes and a robust ray–box slab test.
//!
//! This is the bottom layer of gridrt. It knows vectors, rays and boxes and
//! nothing else: **no grids, no shapes, no files**. Every crate above it uses
//! its scalar alias [`Real`] and vector alias [`Vec3`], so the whole stack
//! switches precision with one feature.
//!
//! ```
//! use gridrt_bbox::{Aabb, Ray, Real, Vec3};
//!
//! let unit = Aabb::new(Vec3::ZERO, Vec3::ONE);
//! let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
//! let (t_enter, t_exit) = unit.hit(&ray, 0.0, Real::INFINITY).unwrap();
//! assert_eq!(t_enter, 1.0);
//! assert!(t_exit >= 2.0);
//! ```
//!
//! # Features
//! - `f64` (off): [`Real`] is `f64` and [`Vec3`] is `glam::DVec3`. Not additive;
//!   the crates above pass it on.
//! - `serde` (off): `Serialize`/`Deserialize` for [`Ray`] and [`Aabb`].
#![warn(missing_docs)]

mod aabb;
pub mod math;
mod ray;

pub use aabb::{Aabb, SlabRay, SlabTest};
pub use math::{gamma, Real, Vec3};
pub use ray::Ray;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reexports_work_together() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let r = Ray::new(Vec3::splat(-1.0), Vec3::ONE);
        let (t0, t1) = b.hit(&r, 0.0, Real::INFINITY).unwrap();
        assert_eq!(t0, 1.0);
        assert!(t1 >= 2.0 && t1 <= 2.0 * (1.0 + 2.0 * gamma(3)) + Real::EPSILON);
    }
}

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
