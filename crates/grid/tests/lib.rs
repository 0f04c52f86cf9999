//! Integration tests of gridrt-grid: hard numerical cases, build edge cases,
//! and property tests that the grid answers exactly like the exhaustive
//! baseline. One test binary (parry3d's layout).

// Casts between `Real` and f32/f64 are no-ops in one precision only.
#![allow(clippy::unnecessary_cast)]

mod support;

mod build;
mod equivalence;
mod groups;
mod hard_cases;
mod hierarchy;
mod nested;
mod offset;
mod traversal;
