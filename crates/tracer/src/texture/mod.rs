//! Textures and the per-material maps that use them: image textures (with
//! mip pyramids, wrap modes and filtering, [`ImageTexture`]) and the solid
//! procedural textures of Suffern's chapters ([`Checker`], [`Fbm`]), bound
//! to a material's base colour, emission, metallic-roughness, normal or
//! bump map and alpha by [`MaterialMaps`].
//!
//! The tracer knows textures as texels in memory; reading and decoding
//! image files is `gridrt-io`'s job. Colour textures hold sRGB-decoded
//! (linear) values, data textures (normal, metallic-roughness, bump,
//! opacity) linear ones; every lookup answers linear RGBA.

mod image;
mod procedural;
pub(crate) mod shade;

pub use image::{
    linear_to_srgb, srgb_to_linear, ImageTexture, Sampler, TexFilter, Wrap, MAX_TEXTURE_SIDE,
};
pub use procedural::{Checker, Fbm};

use crate::scene::Rgb;
use gridrt_bbox::Vec3;

/// Why a texture cannot be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TextureError {
    /// The image has a side of zero or over [`MAX_TEXTURE_SIDE`] texels, or
    /// its texel data does not match its size. Resize or re-export it.
    #[error("a {width}×{height} texture: {reason}")]
    Size {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// What is wrong.
        reason: &'static str,
    },
}

/// A texture: something that gives linear RGBA at a surface point.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// An image, looked up at the hit's texture coordinates.
    Image(std::sync::Arc<ImageTexture>),
    /// A 3D checker in world space.
    Checker(Checker),
    /// fBm noise in world space.
    Fbm(Fbm),
}

/// Where a texture is looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexQuery {
    /// Texture coordinates (after the reference's transform).
    pub uv: glam::Vec2,
    /// The hit's second texture-coordinate set, read by references to set
    /// 1 (equal to `uv` where the mesh has one set).
    pub uv1: glam::Vec2,
    /// The hit point, world space (solid textures).
    pub p: Vec3,
    /// Width of the pixel's footprint in texture-coordinate units (0: a point).
    pub width: f32,
}

impl Texture {
    /// Linear RGBA at `q` (alpha 1 for procedural textures).
    #[must_use]
    pub fn eval(&self, q: &TexQuery) -> [f32; 4] {
        match self {
            Texture::Image(t) => t.lookup(q.uv, q.width),
            Texture::Checker(c) => c.eval(q.p).extend(1.0).to_array(),
            Texture::Fbm(f) => f.eval(q.p).extend(1.0).to_array(),
        }
    }

    fn check(&self) -> Result<(), &'static str> {
        let color_ok = |c: Rgb| c.is_finite() && c.cmpge(Rgb::ZERO).all();
        match self {
            Texture::Image(_) => Ok(()),
            Texture::Checker(c) => {
                if !(c.size > 0.0 && c.size.is_finite()) {
                    return Err("a checker's size must be finite and > 0");
                }
                if !color_ok(c.even) || !color_ok(c.odd) {
                    return Err("a checker's colours must be finite and ≥ 0");
                }
                Ok(())
            }
            Texture::Fbm(f) => {
                if !(f.scale > 0.0 && f.scale.is_finite()) {
                    return Err("fBm's scale must be finite and > 0");
                }
                if !(1..=16).contains(&f.octaves) {
                    return Err("fBm's octaves must be 1 to 16");
                }
                if !(f.lacunarity.is_finite()
                    && f.lacunarity > 0.0
                    && f.gain.is_finite()
                    && f.gain >= 0.0)
                {
                    return Err("fBm's lacunarity must be finite and > 0, its gain finite and ≥ 0");
                }
                if !color_ok(f.low) || !color_ok(f.high) {
                    return Err("fBm's colours must be finite and ≥ 0");
                }
                Ok(())
            }
        }
    }
}

/// An affine map of texture coordinates, glTF's `KHR_texture_transform`:
/// `uv' = offset + R(rotation) · (scale ⊙ uv)`, with
/// `R(r) = [[cos r, −sin r], [sin r, cos r]]` in the extension's
/// column-major GLSL (`mat3(cos, sin, 0, −sin, cos, 0, …)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Added last.
    pub offset: glam::Vec2,
    /// Radians.
    pub rotation: f32,
    /// Applied first, per axis.
    pub scale: glam::Vec2,
}

impl Default for UvTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl UvTransform {
    /// No change.
    pub const IDENTITY: Self = Self {
        offset: glam::Vec2::ZERO,
        rotation: 0.0,
        scale: glam::Vec2::ONE,
    };

    /// The transformed coordinates.
    #[inline]
    #[must_use]
    pub fn apply(&self, uv: glam::Vec2) -> glam::Vec2 {
        if *self == Self::IDENTITY {
            return uv;
        }
        let s = uv * self.scale;
        let (sin, cos) = self.rotation.sin_cos();
        glam::Vec2::new(cos * s.x - sin * s.y, sin * s.x + cos * s.y) + self.offset
    }

    /// How much the map stretches lengths (the larger singular value: the
    /// larger absolute scale), for the lookup's footprint.
    #[inline]
    fn stretch(&self) -> f32 {
        self.scale.abs().max_element()
    }
}

/// A material's use of one texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Textures::list`].
    pub texture: u32,
    /// Transform of the mesh's texture coordinates before the lookup.
    pub transform: UvTransform,
    /// Which texture-coordinate set the lookup reads: 0 or 1 (glTF's
    /// `texCoord`; a mesh without a second set reads its first).
    pub set: u8,
}

impl TextureRef {
    /// A reference to texture `texture` with untransformed coordinates.
    #[must_use]
    pub fn new(texture: u32) -> Self {
        Self {
            texture,
            transform: UvTransform::IDENTITY,
            set: 0,
        }
    }
}

/// How a material's alpha (base-colour alpha × alpha factor × opacity map)
/// is used.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored (glTF's default).
    #[default]
    Opaque,
    /// Cut-outs: the surface is absent where alpha < `cutoff`, for every
    /// ray, shadow rays included (glTF `MASK`, default cutoff 0.5).
    Mask {
        /// Alpha threshold.
        cutoff: f32,
    },
    /// A simple transmission: a ray passes through with probability
    /// 1 − alpha (stochastic transparency, decided by a hash of the ray and
    /// the hit so that images do not depend on threads), which averages
    /// over a pixel's samples to alpha blending (glTF `BLEND`).
    Blend,
}

/// The textures bound to one material. Each map multiplies (or replaces,
/// for normals) what the material gives on its own.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialMaps {
    /// Multiplies the diffuse albedo (RGB) and the alpha (A) of a Matte,
    /// Phong or Reflective material (glTF `baseColorTexture`, MTL `map_Kd`).
    pub base_color: Option<TextureRef>,
    /// Emitted radiance = `emissive_factor ⊙ texture` (glTF
    /// `emissiveTexture`, MTL `map_Ke`); without a texture,
    /// `emissive_factor` alone.
    pub emissive: Option<TextureRef>,
    /// Scale of the emission (glTF `emissiveFactor` × strength).
    pub emissive_factor: Rgb,
    /// glTF's metallic-roughness map: blue = metallic, green = roughness,
    /// multiplying `metallic` and `roughness`.
    pub metallic_roughness: Option<TextureRef>,
    /// Metallic factor in [0, 1].
    pub metallic: f32,
    /// Roughness factor in [0, 1].
    pub roughness: f32,
    /// A tangent-space normal map (glTF `normalTexture`, MTL `norm`):
    /// RGB in [0, 1] encodes a unit vector, +Z along the surface normal,
    /// +X along increasing u, +Y along decreasing v (glTF, OpenGL style).
    pub normal: Option<TextureRef>,
    /// Scale of the normal map's X and Y (glTF `normalTexture.scale`).
    pub normal_scale: f32,
    /// A height (bump) map: its first channel times `bump_scale` is a
    /// height in texture-coordinate units (1 = the texture's width) that
    /// tilts the shading normal (MTL `map_Bump`, `bump`).
    pub bump: Option<TextureRef>,
    /// Height of a bump-map value of 1, texture-coordinate units.
    pub bump_scale: f32,
    /// An opacity map: its first channel multiplies alpha (MTL `map_d`).
    pub opacity: Option<TextureRef>,
    /// The alpha factor (glTF `baseColorFactor.a`, MTL `d`).
    pub alpha: f32,
    /// How alpha is used.
    pub alpha_mode: AlphaMode,
}

impl Default for MaterialMaps {
    fn default() -> Self {
        Self {
            base_color: None,
            emissive: None,
            emissive_factor: Rgb::ZERO,
            metallic_roughness: None,
            metallic: 0.0,
            roughness: 1.0,
            normal: None,
            normal_scale: 1.0,
            bump: None,
            bump_scale: 1.0,
            opacity: None,
            alpha: 1.0,
            alpha_mode: AlphaMode::Opaque,
        }
    }
}

impl MaterialMaps {
    /// Whether any texture or alpha test is bound (a material without
    /// costs nothing at a hit).
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.refs().next().is_some()
            || self.emissive_factor != Rgb::ZERO
            || self.alpha_mode != AlphaMode::Opaque
    }

    fn refs(&self) -> impl Iterator<Item = &TextureRef> {
        [
            &self.base_color,
            &self.emissive,
            &self.metallic_roughness,
            &self.normal,
            &self.bump,
            &self.opacity,
        ]
        .into_iter()
        .flatten()
    }

    /// Metallic and roughness at `q` (factors times the map's blue and
    /// green channels), the parameters of a metallic-roughness BSDF.
    #[must_use]
    pub fn metallic_roughness(&self, textures: &[Texture], q: &TexQuery) -> (f32, f32) {
        match self
            .metallic_roughness
            .and_then(|r| lookup(textures, &r, q))
        {
            Some(t) => (self.metallic * t[2], self.roughness * t[1]),
            None => (self.metallic, self.roughness),
        }
    }
}

/// Looks up a reference (its transform applied); `None` when the index is
/// out of range (validation rules that out before a render).
#[inline]
pub(crate) fn lookup(textures: &[Texture], r: &TextureRef, q: &TexQuery) -> Option<[f32; 4]> {
    let t = textures.get(r.texture as usize)?;
    let q = TexQuery {
        uv: r.transform.apply(if r.set == 1 { q.uv1 } else { q.uv }),
        width: q.width * r.transform.stretch(),
        ..*q
    };
    Some(t.eval(&q))
}

/// The textures of a scene and what each material binds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Textures {
    /// The textures, referred to by index.
    pub list: Vec<Texture>,
    /// The maps of material `i` at index `i`; materials past the end have
    /// none (so an untextured scene leaves it empty).
    pub maps: Vec<MaterialMaps>,
}

impl Textures {
    /// Checks references, factors and procedural parameters.
    ///
    /// # Errors
    /// A message naming the material or texture.
    pub(crate) fn check(&self, materials: usize) -> Result<(), String> {
        if self.maps.len() > materials {
            return Err(format!(
                "{} material maps for {materials} materials",
                self.maps.len()
            ));
        }
        for (i, t) in self.list.iter().enumerate() {
            t.check().map_err(|e| format!("texture {i}: {e}"))?;
        }
        for (i, m) in self.maps.iter().enumerate() {
            if let Some(r) = m.refs().find(|r| r.texture as usize >= self.list.len()) {
                return Err(format!(
                    "material {i} refers to texture {} of {}",
                    r.texture,
                    self.list.len()
                ));
            }
            if let Some(r) = m.refs().find(|r| {
                let t = &r.transform;
                !(t.offset.is_finite() && t.rotation.is_finite() && t.scale.is_finite())
            }) {
                return Err(format!(
                    "material {i}: the transform of texture {} is not finite",
                    r.texture
                ));
            }
            let unit = |x: f32| (0.0..=1.0).contains(&x);
            if !(unit(m.metallic) && unit(m.roughness) && unit(m.alpha)) {
                return Err(format!(
                    "material {i}: metallic, roughness and alpha must be in [0, 1]"
                ));
            }
            if !(m.emissive_factor.is_finite() && m.emissive_factor.cmpge(Rgb::ZERO).all()) {
                return Err(format!(
                    "material {i}: the emissive factor must be finite and ≥ 0"
                ));
            }
            if !(m.normal_scale.is_finite() && m.bump_scale.is_finite()) {
                return Err(format!(
                    "material {i}: the normal and bump scales must be finite"
                ));
            }
            if let AlphaMode::Mask { cutoff } = m.alpha_mode {
                if !cutoff.is_finite() {
                    return Err(format!("material {i}: the alpha cutoff must be finite"));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn identity_transform_changes_nothing_and_others_compose() {
        let uv = Vec2::new(0.3, 0.7);
        assert_eq!(UvTransform::IDENTITY.apply(uv), uv);
        let t = UvTransform {
            offset: Vec2::new(0.5, 0.0),
            rotation: std::f32::consts::FRAC_PI_2,
            scale: Vec2::new(2.0, 1.0),
        };
        // Scale (0.6, 0.7), rotate a quarter turn to (−0.7, 0.6), offset.
        let got = t.apply(uv);
        assert!((got - Vec2::new(-0.2, 0.6)).length() < 1e-6, "{got}");
    }

    #[test]
    fn metallic_roughness_reads_blue_and_green() {
        let img =
            ImageTexture::from_rgba8(1, 1, &[0, 128, 255, 255], false, Sampler::DEFAULT).unwrap();
        let maps = MaterialMaps {
            metallic_roughness: Some(TextureRef::new(0)),
            metallic: 1.0,
            roughness: 0.5,
            ..MaterialMaps::default()
        };
        let q = TexQuery {
            uv: Vec2::ZERO,
            uv1: Vec2::ZERO,
            p: Vec3::ZERO,
            width: 0.0,
        };
        let (m, r) = maps.metallic_roughness(&[Texture::Image(img.into())], &q);
        assert_eq!(m, 1.0);
        assert!((r - 0.5 * 128.0 / 255.0).abs() < 1e-6);
        assert!(maps.is_active());
        assert!(!MaterialMaps::default().is_active());
    }

    #[test]
    fn checks_name_what_is_wrong() {
        let t = Textures {
            list: vec![],
            maps: vec![MaterialMaps {
                base_color: Some(TextureRef::new(3)),
                ..MaterialMaps::default()
            }],
        };
        assert!(t.check(1).unwrap_err().contains("texture 3 of 0"));
        assert!(t.check(0).is_err());
        let t = Textures {
            list: vec![Texture::Fbm(Fbm {
                scale: 1.0,
                octaves: 0,
                lacunarity: 2.0,
                gain: 0.5,
                low: Rgb::ZERO,
                high: Rgb::ONE,
                seed: 0,
            })],
            maps: vec![],
        };
        assert!(t.check(0).unwrap_err().contains("octaves"));
    }
}
