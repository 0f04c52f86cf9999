//! Texture images of model files: read through the [`Sandbox`] (only
//! allowed folders, within the size limit) or taken from bytes embedded in
//! the model, decoded with the `image` crate (PNG, JPEG, Radiance HDR,
//! OpenEXR) into the tracer's [`ImageTexture`]s, each file decoded once
//! per colour space and sampler.

use crate::error::{Error, Result};
use crate::sandbox::Sandbox;
use gridrt_tracer::texture::{ImageTexture, Sampler, MAX_TEXTURE_SIDE};
use gridrt_tracer::{MaterialMaps, Texture, TextureRef, Textures};
use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where an image comes from, as the cache key knows it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Source {
    File(PathBuf),
    Embedded(String),
}

/// Collects the textures of one model file.
#[derive(Debug)]
pub(crate) struct TextureLoader<'a> {
    /// The model file as the user named it (for messages).
    path: &'a Path,
    /// Its canonical path (references are resolved from its folder).
    real: &'a Path,
    sandbox: &'a Sandbox,
    cache: HashMap<(Source, bool, Sampler), u32>,
    /// The textures loaded so far.
    pub list: Vec<Texture>,
}

impl<'a> TextureLoader<'a> {
    pub(crate) fn new(path: &'a Path, real: &'a Path, sandbox: &'a Sandbox) -> Self {
        Self {
            path,
            real,
            sandbox,
            cache: HashMap::new(),
            list: Vec::new(),
        }
    }

    /// The texture of image file `reference` (relative to the model's
    /// folder), colour (`srgb`) or data; `place` names the material.
    pub(crate) fn file(
        &mut self,
        reference: &Path,
        srgb: bool,
        sampler: Sampler,
        place: &str,
    ) -> Result<u32> {
        let real = self
            .sandbox
            .resolve(self.real, reference, true)
            .map_err(|e| e.renamed(self.real, self.path))?;
        let key = (Source::File(real.clone()), srgb, sampler);
        if let Some(&i) = self.cache.get(&key) {
            return Ok(i);
        }
        let bytes = self.sandbox.read(&real)?;
        let shown = self
            .path
            .parent()
            .map_or_else(|| reference.to_path_buf(), |d| d.join(reference));
        let t = decode(&bytes, srgb, sampler).map_err(|msg| Error::Texture {
            path: shown,
            place: place.to_string(),
            msg,
        })?;
        Ok(self.push(key, t))
    }

    /// The texture of image bytes embedded in the model (a GLB buffer view
    /// or a data URI), named `name` in messages.
    pub(crate) fn embedded(
        &mut self,
        name: &str,
        bytes: &[u8],
        srgb: bool,
        sampler: Sampler,
        place: &str,
    ) -> Result<u32> {
        let key = (Source::Embedded(name.to_string()), srgb, sampler);
        if let Some(&i) = self.cache.get(&key) {
            return Ok(i);
        }
        if bytes.len() as u64 > self.sandbox.limits.max_file_bytes {
            return Err(Error::Texture {
                path: self.path.to_path_buf(),
                place: format!("{place}, {name}"),
                msg: format!(
                    "the image is {} bytes, over the limit of {} bytes: raise it with --max-file-size BYTES",
                    bytes.len(),
                    self.sandbox.limits.max_file_bytes
                ),
            });
        }
        let t = decode(bytes, srgb, sampler).map_err(|msg| Error::Texture {
            path: self.path.to_path_buf(),
            place: format!("{place}, {name}"),
            msg,
        })?;
        Ok(self.push(key, t))
    }

    fn push(&mut self, key: (Source, bool, Sampler), t: ImageTexture) -> u32 {
        self.list.push(Texture::Image(Arc::new(t)));
        let i = (self.list.len() - 1) as u32;
        self.cache.insert(key, i);
        i
    }
}

/// Decodes an image: 8- and 16-bit images become 8-bit texels (sRGB-encoded
/// when `srgb`), floating-point ones (HDR, EXR) linear `f32` texels.
///
/// # Errors
/// A message saying what the bytes are not, or which limit they exceed.
pub(crate) fn decode(bytes: &[u8], srgb: bool, sampler: Sampler) -> Result<ImageTexture, String> {
    let mut reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    if reader.format().is_none() {
        return Err(
            "not a PNG, JPEG, HDR or EXR image (unknown signature): convert the texture to PNG"
                .to_string(),
        );
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(1 << 31);
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| format!("cannot decode the image: {e}"))?;
    let (w, h) = (img.width(), img.height());
    let tex = if matches!(
        img.color(),
        image::ColorType::Rgb32F | image::ColorType::Rgba32F
    ) {
        let texels = img.to_rgba32f().pixels().map(|p| p.0).collect();
        ImageTexture::from_rgba32f(w, h, texels, sampler)
    } else {
        ImageTexture::from_rgba8(w, h, img.to_rgba8().as_raw(), srgb, sampler)
    };
    tex.map_err(|e| e.to_string())
}

/// Appends `list` to `textures` and returns the offset of its first entry.
pub(crate) fn append(textures: &mut Textures, list: &[Texture]) -> u32 {
    let offset = textures.list.len() as u32;
    textures.list.extend(list.iter().cloned());
    offset
}

/// Binds `maps` (whose references count from `offset`) to material `id`.
pub(crate) fn bind(textures: &mut Textures, id: u32, maps: &MaterialMaps, offset: u32) {
    if !maps.is_active() {
        return;
    }
    let shift = |r: Option<TextureRef>| {
        r.map(|r| TextureRef {
            texture: r.texture + offset,
            ..r
        })
    };
    let m = MaterialMaps {
        base_color: shift(maps.base_color),
        emissive: shift(maps.emissive),
        metallic_roughness: shift(maps.metallic_roughness),
        normal: shift(maps.normal),
        bump: shift(maps.bump),
        opacity: shift(maps.opacity),
        ..maps.clone()
    };
    let id = id as usize;
    if textures.maps.len() <= id {
        textures.maps.resize(id + 1, MaterialMaps::default());
    }
    textures.maps[id] = m;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32, rgba: &[u8]) -> Vec<u8> {
        let img = image::RgbaImage::from_raw(w, h, rgba.to_vec()).unwrap();
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    #[test]
    fn a_png_decodes_to_srgb_decoded_texels() {
        let bytes = png(1, 1, &[255, 128, 0, 255]);
        let t = decode(&bytes, true, Sampler::DEFAULT).unwrap();
        let c = t.lookup(glam::Vec2::splat(0.5), 0.0);
        assert_eq!(c[0], 1.0);
        assert!((c[1] - 0.2158605).abs() < 1e-5, "{c:?}");
        let t = decode(&bytes, false, Sampler::DEFAULT).unwrap();
        assert!((t.lookup(glam::Vec2::splat(0.5), 0.0)[1] - 128.0 / 255.0).abs() < 1e-6);
    }

    #[test]
    fn garbage_and_truncated_images_are_errors() {
        let e = decode(b"not an image at all", true, Sampler::DEFAULT).unwrap_err();
        assert!(e.contains("not a PNG"), "{e}");
        let bytes = png(4, 4, &[7; 64]);
        let e = decode(&bytes[..bytes.len() / 2], true, Sampler::DEFAULT).unwrap_err();
        assert!(e.contains("cannot decode"), "{e}");
    }

    #[test]
    fn binding_shifts_references() {
        let mut t = Textures::default();
        let maps = MaterialMaps {
            base_color: Some(TextureRef::new(1)),
            ..MaterialMaps::default()
        };
        bind(&mut t, 2, &maps, 5);
        assert_eq!(t.maps.len(), 3);
        assert_eq!(t.maps[2].base_color.map(|r| r.texture), Some(6));
        assert!(!t.maps[0].is_active());
    }
}
