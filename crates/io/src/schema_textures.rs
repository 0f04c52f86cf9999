//! Procedural textures in RON scenes: `texture: Checker(...)` or
//! `texture: Fbm(...)` on a `Matte`, `Phong` or `Reflective` material
//! multiplies its colour (see `docs/scene-format.md`).

use crate::schema::{Color, NonNeg, Positive};
use gridrt_tracer::texture::{Checker, Fbm};
use gridrt_tracer::{MaterialMaps, Rgb, Texture, TextureRef, Textures};
use serde::Deserialize;

/// A solid (3D) procedural texture.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Texture")]
pub(crate) enum TextureDesc {
    /// `Checker(size: 1, even: (1, 1, 1), odd: (0.2, 0.2, 0.2))`: cubes of
    /// side `size` in world space, alternating.
    Checker {
        #[serde(default = "one")]
        size: Positive,
        #[serde(default = "white")]
        even: Color,
        #[serde(default = "dark")]
        odd: Color,
    },
    /// `Fbm(scale: 1, octaves: 6, lacunarity: 2, gain: 0.5, low: (0, 0, 0),
    /// high: (1, 1, 1), seed: 0)`: fractional Brownian motion of value
    /// noise, `scale` lattice cells per world unit in the first octave.
    Fbm {
        #[serde(default = "one")]
        scale: Positive,
        #[serde(default = "six")]
        octaves: u32,
        #[serde(default = "two")]
        lacunarity: Positive,
        #[serde(default = "half")]
        gain: NonNeg,
        #[serde(default = "black")]
        low: Color,
        #[serde(default = "white")]
        high: Color,
        #[serde(default)]
        seed: u32,
    },
}

fn one() -> Positive {
    Positive(1.0)
}
fn two() -> Positive {
    Positive(2.0)
}
fn half() -> NonNeg {
    NonNeg(0.5)
}
fn six() -> u32 {
    6
}
fn white() -> Color {
    Color([1.0; 3])
}
fn black() -> Color {
    Color([0.0; 3])
}
fn dark() -> Color {
    Color([0.2; 3])
}

fn rgb(c: Color) -> Rgb {
    Rgb::new(c.0[0] as f32, c.0[1] as f32, c.0[2] as f32)
}

impl TextureDesc {
    /// The texture (its parameters are checked again by the tracer).
    pub(crate) fn texture(&self) -> Texture {
        match *self {
            TextureDesc::Checker { size, even, odd } => Texture::Checker(Checker {
                size: size.0 as f32,
                even: rgb(even),
                odd: rgb(odd),
            }),
            TextureDesc::Fbm {
                scale,
                octaves,
                lacunarity,
                gain,
                low,
                high,
                seed,
            } => Texture::Fbm(Fbm {
                scale: scale.0 as f32,
                octaves,
                lacunarity: lacunarity.0 as f32,
                gain: gain.0 as f32,
                low: rgb(low),
                high: rgb(high),
                seed,
            }),
        }
    }
}

/// Adds `desc` to `textures` as material `id`'s base-colour map.
pub(crate) fn bind(textures: &mut Textures, id: u32, desc: &TextureDesc) {
    textures.list.push(desc.texture());
    let maps = MaterialMaps {
        base_color: Some(TextureRef::new((textures.list.len() - 1) as u32)),
        ..MaterialMaps::default()
    };
    crate::model::texture_load::bind(textures, id, &maps, 0);
}
