//! A regular (uniform) grid that accelerates ray queries, after Suffern's
//! *Ray Tracing from the Ground Up* (ch. 22), and the exhaustive baseline it
//! is measured against.
//!
//! **Invariants.** The grid knows primitives only through the [`Primitive`]
//! trait (bounds, the data a ray test computes once per query, closest hit,
//! any hit, optional exact box overlap): **no shapes, no materials, no
//! files**. It owns its primitives, stored once in
//! cell order, and a hit names the primitive by the caller's index
//! ([`Hit::prim`]) and by where the grid keeps it ([`Hit::slot`]). Both accelerators
//! implement [`Accelerator`] and return *exactly* the same answer for every
//! query — the hit with the smallest `t` in the closed range
//! `[t_min, t_max]`, ties going to the lower primitive index
//! ([`Hit::is_better_than`]) — so one generic harness tests and benchmarks
//! them. Queries never allocate and use static dispatch; per-thread working
//! memory (the mailbox) is the caller's [`GridScratch`].
//!
//! ```
//! use gridrt_grid::{Aabb, Accelerator, Exhaustive, Grid, GridConfig, PrimHit, Primitive, Ray, Real, Vec3};
//!
//! /// A sphere (just enough for the example).
//! #[derive(Clone)]
//! struct Ball(Vec3, Real);
//!
//! impl Primitive for Ball {
//!     type Shared = ();
//!     type RayData = (); // nothing to compute once per ray
//!     type Four = ();
//!     fn ray_data(_: &Ray) {}
//!     fn bounds(&self, _: &()) -> Aabb {
//!         Aabb::new(self.0 - Vec3::splat(self.1), self.0 + Vec3::splat(self.1))
//!     }
//!     fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t0: Real, t1: Real) -> Option<PrimHit> {
//!         let oc = ray.origin - self.0;
//!         let (a, b, c) = (ray.dir.dot(ray.dir), oc.dot(ray.dir), oc.dot(oc) - self.1 * self.1);
//!         let disc = b * b - a * c;
//!         if disc < 0.0 {
//!             return None;
//!         }
//!         let s = disc.sqrt();
//!         [(-b - s) / a, (-b + s) / a].into_iter().find(|t| (t0..=t1).contains(t)).map(|t| PrimHit::new(t, 0.0, 0.0))
//!     }
//! }
//!
//! let balls: Vec<Ball> = (0..100).map(|i| Ball(Vec3::new((i % 10) as Real, (i / 10) as Real, 0.0), 0.3)).collect();
//! let grid = Grid::build(balls.clone(), &GridConfig::default());
//! grid.check_invariants().unwrap();
//!
//! let ray = Ray::new(Vec3::new(3.0, 4.0, 10.0), Vec3::new(0.0, 0.0, -1.0));
//! let mut scratch = grid.scratch(); // one per thread, reused for every query
//! let hit = grid.closest_hit(&ray, 0.0, Real::INFINITY, &mut scratch).unwrap();
//! assert_eq!(hit.prim, 43);
//! assert!((hit.t - 9.7).abs() < 1e-4);
//! assert!(grid.any_hit(&ray, 0.0, 20.0, &mut scratch));
//!
//! // The exhaustive baseline gives the very same answer.
//! let all = Exhaustive::new(balls);
//! assert_eq!(all.closest_hit(&ray, 0.0, Real::INFINITY, &mut ()), Some(hit));
//!
//! // The 3D-DDA itself: the cells along the ray, each with its t interval.
//! let cells: Vec<_> = grid.cells_along(&ray, 0.0, Real::INFINITY).collect();
//! assert!(cells.windows(2).all(|w| w[0].t_exit == w[1].t_enter));
//! ```
//!
//! # How it works
//!
//! - **Resolution**: the lecture's `s = cbrt(wx·wy·wz / n)`,
//!   `n_a = floor(m·w_a / s) + 1`, with degenerate extents handled and the
//!   cell count capped ([`GridConfig`]).
//! - **Storage** ([`CellStorage`]): a dense CSR offset table (one `u32` per
//!   cell, the default: fastest), or, as the lecture asks, an open-addressing
//!   hash table holding only the occupied cells, keyed by the Morton code of
//!   `(i, j, k)`, over references stored in Morton order. Either way the
//!   references are one flat `u32` array.
//! - **Build**, linear time: dense by counting, prefix sum and filling
//!   (Lagae & Dutré 2008), hashed by radix-sorting `(Morton code,
//!   primitive)` pairs (Kalojanov & Slusallek 2009); parallel with `rayon`.
//! - **Traversal**: the 3D-DDA of Amanatides & Woo (1987), entered through
//!   the robust slab test, with plane crossings computed from the stored cell
//!   planes. Queries leave a cube of empty cells in one step by a
//!   chessboard distance map (sparse dense tables), or cross empty 8³
//!   blocks in one step, and skip empty cells by an occupancy bit. [`Grid::cells_along`] (an iterator)
//!   and [`Grid::visit_cells`] (a `ControlFlow` visitor) expose the walk.
//! - **Exactness**: primitive boxes are widened by a few hundred ulps of the
//!   scene's coordinates before insertion, so a primitive whose hit lies on
//!   (or within rounding of) a cell plane is in the cells on both sides;
//!   `closest_hit` stops after a cell only when the best hit lies before
//!   the cell's exit by more than a few ulps, because a tie at the exit plane
//!   may be won by a lower-index primitive of the next cell. Mailboxing
//!   (optional) never loses a hit: a primitive's hit found in an earlier cell
//!   stays the best candidate until a cell containing it is reached.
//! - **Counters**: [`Grid::closest_hit_counted`] and
//!   [`Exhaustive::closest_hit_counted`] report cells, tests and mailbox
//!   skips through [`Counters`] ([`NoCounters`] costs nothing).
//!
//! # Features
//!
//! - `rayon` (default): build in parallel ([`GridConfig::parallel_build`]).
//! - `f64` (off): [`Real`] is `f64` throughout (passed on to `gridrt-bbox`).
#![warn(missing_docs)]
// NaN must land on the "miss" or "stop" side of every range test, which is
// what `!(a <= b)` says; `partial_cmp` would only obscure it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod accel;
mod build;
mod cells;
mod cluster;
mod config;
pub mod cost;
mod counters;
mod dda;
mod dense_build;
mod empty_space;
mod exhaustive;
mod geom;
mod grid;
mod groups;
mod hash_table;
pub mod mem;
mod morton;
mod nested;
mod order;
mod par;
mod radix;

pub use accel::{
    any_hits_each, any_hits_prefiltered, closest_hits_each, closest_hits_prefiltered, Accelerator,
    Hit, PrimHit, Primitive, NO_SLOT,
};
pub use config::{
    CellStorage, GridConfig, GridStats, NestLevel, AUTO_DIRECT_MAX, DEFAULT_BUDGET_FACTOR,
    HIERARCHY_MIN_REFS, MIN_BUDGET,
};
pub use counters::{Counters, NoCounters, QueryCounters};
pub use dda::{CellIter, CellVisit};
pub use exhaustive::Exhaustive;
pub use grid::{Grid, GridScratch};
pub use gridrt_bbox::{Aabb, Ray, Real, SlabTest, Vec3};
pub use order::{spatial_order, spatial_order_iter};

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
