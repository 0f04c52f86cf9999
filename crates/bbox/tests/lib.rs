//! Hard numerical cases and property tests for gridrt-bbox, as one test binary.
//!
//! Everything is written against `Real`/`Vec3`, so the same tests run with
//! the default f32 build and with `--features f64`.

mod props;
mod slab;
mod support;
