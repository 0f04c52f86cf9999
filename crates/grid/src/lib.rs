//! A regular (uniform) grid that accelerates ray queries, and the exhaustive
//! baseline it is measured against.
//!
//! The grid knows primitives only through the [`Primitive`] trait (bounds,
//! closest hit, any hit): **no shapes, no materials, no files**. Both
//! accelerators implement [`Accelerator`], so one generic harness tests and
//! benchmarks them.
#![warn(missing_docs)]

mod accel;
mod build;
mod config;
mod counters;
mod dda;
mod exhaustive;
mod geom;
mod grid;
mod morton;
mod par;
mod radix;
mod table;

pub use accel::{Accelerator, Hit, PrimHit, Primitive};
pub use config::{CellStorage, GridConfig, GridStats};
pub use counters::{Counters, NoCounters, QueryCounters};
pub use dda::{CellIter, CellVisit};
pub use exhaustive::Exhaustive;
pub use grid::{Grid, GridScratch};
pub use gridrt_bbox::{Aabb, Ray, Real, Vec3};
