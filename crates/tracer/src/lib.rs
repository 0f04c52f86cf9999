//! The renderer. Knows shapes, materials, lights and cameras; builds the grid
//! through `gridrt-grid`. **Never touches files or formats** (that is `gridrt-io`).
#![warn(missing_docs)]

pub mod scene;

pub use scene::{
    Camera, Geometry, Light, Material, MaterialId, Mesh, Object, Projection, Rgb, Scene, Settings,
};
