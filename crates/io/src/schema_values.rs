//! Checked scalars and vectors of the RON scene schema: each type checks its
//! value while it is read (through `try_from`), so a bad value's error
//! carries the position of the value.

use crate::schema::{MAX_DEPTH, MAX_RANDOM_SPHERES, MAX_SIDE, MAX_SPP};
use gridrt_tracer::MAX_PIXELS;
use serde::Deserialize;

/// A finite number.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct Finite(pub f64);

impl TryFrom<f64> for Finite {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() {
            Ok(Self(x))
        } else {
            Err(format!("expected a finite number, found {x}"))
        }
    }
}

/// A finite number > 0.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct Positive(pub f64);

impl TryFrom<f64> for Positive {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() && x > 0.0 {
            Ok(Self(x))
        } else {
            Err(format!("expected a number > 0, found {x}"))
        }
    }
}

/// A finite number ≥ 0 (default 0).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct NonNeg(pub f64);

impl TryFrom<f64> for NonNeg {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() && x >= 0.0 {
            Ok(Self(x))
        } else {
            Err(format!("expected a number >= 0, found {x}"))
        }
    }
}

/// A point or vector `(x, y, z)` with finite components.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "[f64; 3]")]
pub(crate) struct V3(pub [f64; 3]);

impl TryFrom<[f64; 3]> for V3 {
    type Error = String;
    fn try_from(v: [f64; 3]) -> Result<Self, String> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Self(v))
        } else {
            Err(format!(
                "expected finite coordinates (x, y, z), found ({}, {}, {})",
                v[0], v[1], v[2]
            ))
        }
    }
}

impl V3 {
    pub(crate) fn is_zero(&self) -> bool {
        self.0 == [0.0; 3]
    }
}

/// A non-zero direction `(x, y, z)`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "[f64; 3]")]
pub(crate) struct Dir(pub [f64; 3]);

impl TryFrom<[f64; 3]> for Dir {
    type Error = String;
    fn try_from(v: [f64; 3]) -> Result<Self, String> {
        let v3 = V3::try_from(v)?;
        if v3.is_zero() {
            Err("expected a non-zero direction, found (0, 0, 0)".to_string())
        } else {
            Ok(Self(v))
        }
    }
}

/// A linear-RGB colour `(r, g, b)`, components finite and ≥ 0 (they may
/// exceed 1: light colours and emission often do).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "[f64; 3]")]
pub(crate) struct Color(pub [f64; 3]);

impl TryFrom<[f64; 3]> for Color {
    type Error = String;
    fn try_from(c: [f64; 3]) -> Result<Self, String> {
        if c.iter().all(|x| x.is_finite() && *x >= 0.0) {
            Ok(Self(c))
        } else {
            Err(format!(
                "expected a colour (r, g, b) with finite components >= 0, found ({}, {}, {})",
                c[0], c[1], c[2]
            ))
        }
    }
}

/// A number in `[0, 1]` (roughness, metalness).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct Unit(pub f64);

impl TryFrom<f64> for Unit {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if (0.0..=1.0).contains(&x) {
            Ok(Self(x))
        } else {
            Err(format!("expected a number in [0, 1], found {x}"))
        }
    }
}

/// A reflectance `(r, g, b)`, components in `[0, 1]`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "[f64; 3]")]
pub(crate) struct UnitColor(pub [f64; 3]);

impl TryFrom<[f64; 3]> for UnitColor {
    type Error = String;
    fn try_from(c: [f64; 3]) -> Result<Self, String> {
        if c.iter().all(|x| (0.0..=1.0).contains(x)) {
            Ok(Self(c))
        } else {
            Err(format!(
                "expected a reflectance (r, g, b) with components in [0, 1], found ({}, {}, {})",
                c[0], c[1], c[2]
            ))
        }
    }
}

pub(crate) const fn gray(x: f64) -> Color {
    Color([x, x, x])
}

/// An image side, 1..=16384 pixels.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "u32")]
pub(crate) struct Side(pub u32);

impl TryFrom<u32> for Side {
    type Error = String;
    fn try_from(x: u32) -> Result<Self, String> {
        check_side(x).map(Self)
    }
}

/// Checks an image side (shared with the command line).
pub(crate) fn check_side(x: u32) -> Result<u32, String> {
    if (1..=MAX_SIDE).contains(&x) {
        Ok(x)
    } else {
        Err(format!(
            "image size {x} is out of range: use 1 to {MAX_SIDE} pixels per side"
        ))
    }
}

/// Checks the pixel count (shared with the command line).
pub(crate) fn check_pixels(w: u32, h: u32) -> Result<(), String> {
    let n = u64::from(w) * u64::from(h);
    if n > MAX_PIXELS {
        Err(format!(
            "image of {w} x {h} = {n} pixels is too large: at most {MAX_PIXELS} (2^26) pixels"
        ))
    } else {
        Ok(())
    }
}

/// Samples per pixel, 1..=65536.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "u32")]
pub(crate) struct Spp(pub u32);

impl TryFrom<u32> for Spp {
    type Error = String;
    fn try_from(x: u32) -> Result<Self, String> {
        check_spp(x).map(Self)
    }
}

/// Checks samples per pixel (shared with the command line).
pub(crate) fn check_spp(x: u32) -> Result<u32, String> {
    if (1..=MAX_SPP).contains(&x) {
        Ok(x)
    } else {
        Err(format!(
            "spp (samples per pixel) {x} is out of range: use 1 to {MAX_SPP}"
        ))
    }
}

/// Reflection/refraction depth, 0..=64.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "u32")]
pub(crate) struct Depth(pub u32);

impl TryFrom<u32> for Depth {
    type Error = String;
    fn try_from(x: u32) -> Result<Self, String> {
        if x <= MAX_DEPTH {
            Ok(Self(x))
        } else {
            Err(format!("max_depth {x} is too large: use 0 to {MAX_DEPTH}"))
        }
    }
}

/// A vertical field of view in degrees, strictly between 0 and 180.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct Fov(pub f64);

impl TryFrom<f64> for Fov {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() && x > 0.0 && x < 180.0 {
            Ok(Self(x))
        } else {
            Err(format!(
                "field of view {x} is out of range: use degrees strictly between 0 and 180"
            ))
        }
    }
}

/// A cone half-angle in degrees, in `[0, 180]`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct Angle(pub f64);

impl TryFrom<f64> for Angle {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() && (0.0..=180.0).contains(&x) {
            Ok(Self(x))
        } else {
            Err(format!(
                "angle {x} is out of range: use degrees from 0 to 180"
            ))
        }
    }
}

/// An index of refraction, finite and > 0.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct Ior(pub f64);

impl TryFrom<f64> for Ior {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() && x > 0.0 {
            Ok(Self(x))
        } else {
            Err(format!(
                "index of refraction {x} is invalid: use a number > 0 (glass 1.5, water 1.33)"
            ))
        }
    }
}

/// Occlusion rays per shaded point, 1..=[`Occlusion::MAX_SAMPLES`].
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "u32")]
pub(crate) struct AoSamples(pub u32);

impl TryFrom<u32> for AoSamples {
    type Error = String;
    fn try_from(x: u32) -> Result<Self, String> {
        let max = gridrt_tracer::Occlusion::MAX_SAMPLES;
        if (1..=max).contains(&x) {
            Ok(Self(x))
        } else {
            Err(format!(
                "occlusion samples {x} is out of range: use 1 to {max} rays per shaded point"
            ))
        }
    }
}

/// A sphere count for `RandomSpheres`, at most 10 million.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "u32")]
pub(crate) struct Count(pub u32);

impl TryFrom<u32> for Count {
    type Error = String;
    fn try_from(x: u32) -> Result<Self, String> {
        if x <= MAX_RANDOM_SPHERES {
            Ok(Self(x))
        } else {
            Err(format!(
                "count {x} is too large: at most {MAX_RANDOM_SPHERES} spheres"
            ))
        }
    }
}
