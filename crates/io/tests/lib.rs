//! Integration tests of gridrt-io, one binary (parry3d style): the bad-input
//! corpus, the fixture scenes, model loading, the `gridrt` binary end to
//! end, and optional checks against `../shared/scenes` (skipped when absent).

// Test helpers outside #[test] functions unwrap too: a failure is a test failure.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod bad_inputs;
mod cli;
mod docs;
mod fixture_scenes;
mod full_precision;
mod models;
mod shared;

use std::path::PathBuf;

/// `fixtures/` at the workspace root.
pub fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// A file under `fixtures/`.
pub fn fixture(rel: &str) -> PathBuf {
    fixtures().join(rel)
}
