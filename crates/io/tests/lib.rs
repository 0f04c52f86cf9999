//! Integration tests of gridrt-io, one binary (parry3d style): the bad-input
//! corpus, the fixture scenes, model loading, the `gridrt` binary end to
//! end, and optional checks against `../shared/scenes` (skipped when absent).

// Test helpers outside #[test] functions unwrap too: a failure is a test failure.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod ambient_occlusion;
mod bad_inputs;
mod cli;
mod docs;
mod effect_warnings;
mod environment;
mod farm;
mod fixture_scenes;
mod full_precision;
mod instancing;
mod models;
mod normals;
mod passes;
mod ply;
mod robustness_switches;
mod shared;
mod stats;
mod textures;
mod untrusted;
mod untrusted_messages;
mod untrusted_outputs;

use std::path::PathBuf;

/// `fixtures/` at the workspace root.
pub fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// The sandbox of `path` with `fixtures/` and `../shared/scenes` allowed
/// too (fixture scenes name meshes in `../meshes`).
pub fn sandbox(path: &std::path::Path) -> gridrt_io::Sandbox {
    let mut s = gridrt_io::Sandbox::for_input(path);
    s.allow(&fixtures()).unwrap();
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    if shared.is_dir() {
        s.allow(&shared).unwrap();
    }
    s
}

/// [`gridrt_io::load_scene`] with [`sandbox`].
pub fn load_scene(path: &std::path::Path) -> gridrt_io::Result<gridrt_io::LoadedScene> {
    gridrt_io::load_scene_in(path, &sandbox(path))
}

/// [`gridrt_io::parse_scene`] with [`sandbox`].
pub fn parse_scene(
    text: &str,
    path: &std::path::Path,
) -> gridrt_io::Result<gridrt_io::LoadedScene> {
    gridrt_io::parse_scene_in(text, path, &sandbox(path))
}

/// Runs the `gridrt` binary with `args` in `cwd`.
pub fn gridrt(args: &[&str], cwd: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_gridrt"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the gridrt binary runs")
}

/// A file under `fixtures/`.
pub fn fixture(rel: &str) -> PathBuf {
    fixtures().join(rel)
}
