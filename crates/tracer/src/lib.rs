//! The gridrt renderer: shapes, camera, materials, lights, the effect plan
//! and the parallel render loop, over the regular grid of `gridrt-grid`.
//!
//! **Invariants.** The tracer knows scenes as data ([`Scene`]) and never
//! touches files or formats (that is `gridrt-io`'s job). It builds its
//! accelerator only through `gridrt-grid`'s [`Accelerator`] trait and renders
//! generic code over it (static dispatch, no `dyn` in the hot path). An image
//! depends only on the scene and the accelerator's answers, never on the
//! thread count or tiling: samples are hashed from the pixel and sample
//! index. Effects the scene does not call for cost nothing (the
//! [`EffectPlan`]), and every ray is counted by kind ([`RayCounts`]).
//!
//! ```
//! use gridrt_tracer::{
//!     render, Camera, Geometry, Light, Material, Object, Projection, RenderOptions, Rgb, Scene,
//!     Settings,
//! };
//! use gridrt_grid::Vec3;
//!
//! let scene = Scene {
//!     camera: Camera {
//!         eye: Vec3::new(0.0, 0.0, 5.0),
//!         look_at: Vec3::ZERO,
//!         up: Vec3::Y,
//!         projection: Projection::Perspective { vfov_deg: 40.0 },
//!         lens: None,
//!     },
//!     settings: Settings { width: 32, height: 24, ..Settings::default() },
//!     materials: vec![Material::Matte { color: Rgb::new(0.8, 0.3, 0.2), ka: 0.1, kd: 0.9 }],
//!     lights: vec![
//!         Light::Ambient { color: Rgb::ONE, intensity: 1.0, occlusion: None },
//!         Light::Directional {
//!             direction: Vec3::new(1.0, 1.0, 1.0),
//!             color: Rgb::ONE,
//!             intensity: 3.0,
//!             shadows: true,
//!         },
//!     ],
//!     objects: vec![Object {
//!         geometry: Geometry::Sphere { center: Vec3::ZERO, radius: 1.0 },
//!         material: 0,
//!     }],
//!     textures: Default::default(),
//! };
//! let (image, stats) = render(&scene, &RenderOptions::default()).unwrap();
//! assert_eq!(image.pixels.len(), 32 * 24);
//! assert!(stats.pixels_hit > 0);
//! // One convex sphere cannot shadow itself: the plan casts no shadow rays.
//! assert_eq!(stats.rays.shadow, 0);
//! println!("{stats}");
//! ```
//!
//! Huge sphere scenes (Suffern's benchmark with a million spheres) are one
//! [`Object`] whose geometry is a [`Geometry::Spheres`] set: the spheres
//! and their colours in two arrays, one material for all;
//! [`suffern::scene`] builds one. A scene of spheres
//! (and planes) only is rendered over a grid of compact [`Sphere`]s, any
//! other scene over a grid of [`Shape`]s; planes stay outside the grid.
//!
//! # Features
//! - `rayon` (default): render tiles (and build the grid) in parallel on a
//!   local thread pool; without it everything runs on the calling thread.
//! - `f64` (off): [`Real`](gridrt_bbox::Real) is `f64` throughout (colours
//!   stay `f32`).
//! - `serde` (off): `Serialize` for [`RenderStats`], [`RayCounts`] and
//!   [`EffectPlan`].
#![warn(missing_docs)]
// `!(a <= b)` is how this crate rejects NaN on purpose (a NaN fails every
// comparison, so the negated form takes the safe branch); see the comments
// at each use.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod accel_of;
mod aov;
mod bsdf;
mod camera;
mod emitters;
mod error;
mod float;
mod framebuffer;
pub mod hard_meshes;
mod ignored;
mod instancing;
mod integrator;
mod lights;
mod mesh_shading;
mod occlusion;
pub mod offset_scenes;
pub mod optics;
mod path;
mod plan;
mod pool;
mod prepare;
mod render;
mod robustness;
pub mod sampling;
pub mod scene;
#[cfg(feature = "serde")]
mod serde_support;
mod shapes;
mod srgb;
mod stats;
pub mod suffern;
pub mod texture;
mod tiles;
mod transform;
mod validate;
mod whitted;

pub use accel_of::{TriangleStorage, INDEXED_FROM};
pub use aov::{Aov, AovImage};
pub use error::{Cancelled, SceneError};
pub use framebuffer::{Framebuffer, LiveImage, PixelRect, Srgb8Image};
pub use gridrt_grid::Accelerator;
pub use ignored::{ignored_effects, Ignored, Where};
pub use instancing::InstancingStats;
pub use plan::{EffectPlan, IntegratorKind, RayCounts};
pub use prepare::MAX_PIXELS;
pub use render::{render, AccelKind, RenderOptions, RenderStats, Renderer};
pub use robustness::{RayOffset, TriangleTest};
pub use sampling::{Filter, SamplerKind};
pub use scene::{
    Camera, ConductorFresnel, EnvImage, Geometry, IntegratorChoice, Light, Material, MaterialId,
    Mesh, Object, Occlusion, Projection, Rgb, Scene, Settings, SphereColors, SphereSet, ThinLens,
};
pub use shapes::{
    Cuboid, MeshTriangle, MeshVertices, MtTriangle, Plane, Shape, Shear, Sphere, SphereFour,
    SphereRay, Triangle, TriangleFour, MT_EPSILON,
};
pub use srgb::{linear_to_srgb, srgb8, srgb8_into};
pub use texture::{MaterialMaps, Texture, TextureRef, Textures};
pub use transform::Affine;

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
