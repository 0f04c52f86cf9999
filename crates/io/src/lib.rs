//! Everything that touches the outside world: RON scene files, OBJ, PLY and glTF
//! meshes, PNG and EXR images, ray-query CSV files, and the `gridrt`
//! command-line renderer built on them.
//!
//! **Invariant: this is the only gridrt crate that reads or writes files or
//! knows a file format.** It turns files into the tracer's in-memory
//! [`Scene`](gridrt_tracer::Scene) and framebuffers into files; the tracer
//! and the grid below it never see a path. Bad input of any kind is an
//! [`Error`] that names the file and the place in it (RON line:column, OBJ
//! line, glTF node and primitive, CSV line) and says what to fix; it never
//! panics. Every output is written atomically (a temporary file renamed into
//! place), so a failed run never leaves a half-written file or clobbers a
//! good one.
//!
//! ```
//! use gridrt_io::parse_scene;
//! use std::path::Path;
//!
//! let text = r#"Scene(
//!     camera: Camera(eye: (0, 1, 6), look_at: (0, 0.5, 0), projection: Perspective(vfov: 40)),
//!     settings: Settings(width: 40, height: 30),
//!     materials: {
//!         "floor": Matte(color: (0.8, 0.8, 0.8)),
//!         "mirror": Reflective(),
//!     },
//!     lights: [Ambient(intensity: 0.2), Point(position: (3, 6, 4), intensity: 3)],
//!     objects: [
//!         Plane(point: (0, 0, 0), normal: (0, 1, 0), material: "floor"),
//!         Sphere(center: (0, 1, 0), radius: 1, material: "mirror"),
//!     ],
//! )"#;
//! let loaded = parse_scene(text, Path::new("inline.ron")).unwrap();
//! assert_eq!(loaded.scene.objects.len(), 2);
//!
//! // Unknown fields are errors that point at the line and column.
//! let err = parse_scene("(objects: [], colour: 1)", Path::new("bad.ron")).unwrap_err();
//! assert!(err.to_string().starts_with("bad.ron:1:"));
//! ```
//!
//! The scene format is documented field by field in `docs/scene-format.md`,
//! the command line in `docs/cli.md`.
//!
//! # Features
//! - `cli` (default): the `gridrt` binary and the [`cli`] module, with
//!   their dependencies (clap, indicatif, ctrlc). Off, the crate is the
//!   loaders and writers alone.
//! - `rayon` (default): render and build grids in parallel (passed on to
//!   gridrt-tracer and gridrt-grid).
//! - `f64` (off): `Real` is `f64` throughout the stack. Not additive.
#![warn(missing_docs)]

mod aov_out;
#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "cli")]
mod cli_access;
#[cfg(feature = "cli")]
mod cli_counts;
#[cfg(feature = "cli")]
mod cli_effects;
#[cfg(feature = "cli")]
mod cli_outputs;
#[cfg(feature = "cli")]
mod cli_rays;
#[cfg(feature = "cli")]
mod cli_robustness;
#[cfg(feature = "cli")]
mod cli_stats;
#[cfg(feature = "cli")]
mod cli_view;
mod diff;
mod error;
pub mod huge_page_alloc;
mod image_out;
mod model;
mod model_scene;
mod model_view;
mod parts;
mod random;
mod rays;
mod ron_text;
mod sandbox;
mod scene;
mod scene_lights;
mod scene_numbers;
mod scene_transform;
mod schema;
mod schema_settings;
mod schema_textures;
mod schema_values;

pub use aov_out::{
    aov_png_path, parse_aovs, stage_aov_pngs, stage_exr_with_aovs, write_aov_pngs,
    write_exr_with_aovs,
};
pub use diff::{
    diff_files, diff_values, kind_name, read_image, write_diff_image, ImageDiff, ImageValues,
    RgbImage,
};
pub use error::{escape_control, Error, Result};
pub use gridrt_tracer::linear_to_srgb;
pub use huge_page_alloc::HugePageAlloc;
pub use image_out::{
    check_image_path, check_output_dir, stage, stage_image, stage_png8, write_atomic, write_image,
    ImageFormat, Staged,
};
pub use model::{
    default_material, load_model, load_model_in, Model, ModelCamera, ModelFormat, ModelMesh,
    NamedMaterial,
};
pub use model_scene::{apply_overrides, frame, scene_from_model};
pub use parts::{fingerprint, merge_parts, stage_part, write_part, PartSpec, STRIP};
pub use rays::{
    format_hits, parse_rays, trace_rays, trace_rays_into, trace_rays_on, RayQuery, CHUNK,
};
pub use sandbox::{Limits, Sandbox};
pub use scene::{
    default_scene, load_scene, load_scene_in, parse_scene, parse_scene_in, LoadedScene,
    DEFAULT_SCENE, DEFAULT_SCENE_NAME,
};

/// Writes a rendered framebuffer as PNG or EXR (by extension), atomically.
///
/// # Errors
/// As [`write_image`].
pub fn write_framebuffer(path: &std::path::Path, fb: &gridrt_tracer::Framebuffer) -> Result<()> {
    write_image(path, fb.width, fb.height, &fb.pixels)
}

/// The top-level README's Rust examples, compiled and run as doc tests so
/// they stay true.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
