//! Cross-module tests of the renderer: analytic radiance, mirrors and glass,
//! the effect plan, determinism across accelerators and threads, watertight
//! meshes, precision, the Suffern benchmark counts, errors, cancellation.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod ambient_occlusion;
mod area_lights;
mod common;

mod determinism;
mod dielectric;
mod environment;
mod errors;
mod glossy;
mod instancing;
mod lambert;
mod leaks;
mod mirror;
mod offsets;
mod packed_fours;
mod path;
mod plan;
mod precision;
mod progress;
mod random_closed;
mod ray_kinds;
mod rows;
mod shading_normals;
mod suffern;
mod textures;
mod ties;
mod watertight;
