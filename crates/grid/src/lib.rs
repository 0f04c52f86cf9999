//! A regular (uniform) grid that accelerates ray queries, and the exhaustive
//! baseline it is measured against.
//!
//! The grid knows primitives only through the [`Primitive`] trait (bounds,
//! closest hit, any hit): **no shapes, no materials, no files**. Both
//! accelerators implement [`Accelerator`], so one generic harness tests and
//! benchmarks them.
#![warn(missing_docs)]

mod accel;
mod config;
mod exhaustive;

pub use accel::{Accelerator, Hit, PrimHit, Primitive};
pub use config::{CellStorage, GridConfig, GridStats};
pub use exhaustive::Exhaustive;
pub use gridrt_bbox::{Aabb, Ray, Real, Vec3};
