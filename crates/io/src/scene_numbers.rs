//! Numbers and vectors of scene files as the tracer takes them, and
//! numbers as messages write them.

use glam::DVec3;
use gridrt_bbox::{Real, Vec3};

/// A point or vector of the file in the tracer's precision.
pub(crate) fn v3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as Real, v[1] as Real, v[2] as Real)
}

/// A number as written in a message: exponent form when it is huge or tiny.
pub(crate) fn num(x: f64) -> String {
    if x != 0.0 && !(1e-4..1e15).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The unit vector along `v` (finite, non-zero), computed without
/// overflow: `(1e300, 0, 0)` is `(1, 0, 0)`, not a zero vector.
pub(crate) fn unit(v: [f64; 3]) -> DVec3 {
    let d = DVec3::from_array(v);
    let m = d.abs().max_element();
    if m > 0.0 && m.is_finite() {
        (d / m).normalize()
    } else {
        d
    }
}

pub(crate) fn f32s(x: f64) -> f32 {
    x as f32
}
