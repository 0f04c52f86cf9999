//! Property tests for gridrt-morton, as one test binary: every
//! implementation (magic masks, BMI2, the naive loop) against the others,
//! round trips over the full coordinate ranges, and the ordering laws.

mod props;
