//! glTF materials' textures: `baseColorTexture`, `emissiveTexture`,
//! `metallicRoughnessTexture` and `normalTexture` with their samplers,
//! `texCoord` sets and `KHR_texture_transform`, the alpha mode, and the
//! `TEXCOORD_n` accessors that feed them. Images are embedded in a GLB
//! buffer view, in a base64 data URI, or an external file read through
//! the sandbox.

use super::base64;
use super::texture_load::TextureLoader;
use crate::error::{Error, Result};
use crate::sandbox::uri_path;
use gltf::accessor::{DataType, Dimensions};
use gltf::texture::{MagFilter, MinFilter, WrappingMode};
use gridrt_tracer::texture::{AlphaMode, Sampler, TexFilter, UvTransform, Wrap};
use gridrt_tracer::{MaterialMaps, Rgb, TextureRef};
use std::borrow::Cow;
use std::path::Path;

/// The texture-coordinate set a texture reference reads
/// (`KHR_texture_transform` may override the reference's own).
fn info_set(i: &gltf::texture::Info) -> u32 {
    i.texture_transform()
        .and_then(|t| t.tex_coord())
        .unwrap_or_else(|| i.tex_coord())
}

/// The texture-coordinate sets a material's textures read, each once.
fn uv_sets(m: &gltf::Material) -> Vec<u32> {
    let pbr = m.pbr_metallic_roughness();
    let mut sets: Vec<u32> = [
        pbr.base_color_texture(),
        m.emissive_texture(),
        pbr.metallic_roughness_texture(),
    ]
    .iter()
    .flatten()
    .map(info_set)
    .chain(m.normal_texture().map(|n| n.tex_coord()))
    .collect();
    sets.sort_unstable();
    sets.dedup();
    sets
}

/// The set a reference reads as rendered: sets 0 and 1 are read; a higher
/// one reads set 0 (with a warning from [`primitive_uvs`]).
fn rendered_set(set: u32) -> u8 {
    u8::from(set == 1)
}

fn sampler(t: &gltf::Texture) -> Sampler {
    let s = t.sampler();
    let wrap = |w: WrappingMode| match w {
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
        WrappingMode::Repeat => Wrap::Repeat,
    };
    Sampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        filter: if s.mag_filter() == Some(MagFilter::Nearest) {
            TexFilter::Nearest
        } else {
            TexFilter::Linear
        },
        mipmaps: !matches!(s.min_filter(), Some(MinFilter::Nearest | MinFilter::Linear)),
    }
}

/// Loads texture `t` (colour when `srgb`).
fn texture(
    loader: &mut TextureLoader,
    path: &Path,
    buffers: &[Cow<[u8]>],
    t: &gltf::Texture,
    srgb: bool,
    place: &str,
) -> Result<u32> {
    let image = t.source();
    let name = match image.name() {
        Some(n) => format!("image {} \"{n}\"", image.index()),
        None => format!("image {}", image.index()),
    };
    let bad = |msg: String| Error::Texture {
        path: path.to_path_buf(),
        place: format!("{place}, {name}"),
        msg,
    };
    match image.source() {
        gltf::image::Source::View { view, .. } => {
            let data = buffers
                .get(view.buffer().index())
                .ok_or_else(|| bad(format!("buffer view {} has no buffer", view.index())))?;
            let bytes = view
                .offset()
                .checked_add(view.length())
                .and_then(|end| data.get(view.offset()..end))
                .ok_or_else(|| {
                    bad(format!(
                        "buffer view {} runs past the end of its buffer",
                        view.index()
                    ))
                })?;
            loader.embedded(&name, bytes, srgb, sampler(t), place)
        }
        gltf::image::Source::Uri { uri, .. } => {
            if let Some(rest) = uri.strip_prefix("data:") {
                let payload = rest
                    .split_once(";base64,")
                    .map(|(_, d)| d)
                    .ok_or_else(|| bad("only base64 data: URIs are supported".into()))?;
                let bytes = base64::decode(payload).map_err(bad)?;
                loader.embedded(&name, &bytes, srgb, sampler(t), place)
            } else {
                let rel = uri_path(uri).map_err(bad)?;
                loader.file(&rel, srgb, sampler(t), &format!("{place}, {name}"))
            }
        }
    }
}

fn transform(i: &gltf::texture::Info) -> UvTransform {
    i.texture_transform()
        .map_or(UvTransform::IDENTITY, |t| UvTransform {
            offset: glam::Vec2::from_array(t.offset()),
            rotation: t.rotation(),
            scale: glam::Vec2::from_array(t.scale()),
        })
}

/// The maps of material `m` (named `name`), loading its textures.
pub(crate) fn maps(
    m: &gltf::Material,
    name: &str,
    loader: &mut TextureLoader,
    path: &Path,
    buffers: &[Cow<[u8]>],
) -> Result<MaterialMaps> {
    let place = format!("material \"{name}\"");
    let pbr = m.pbr_metallic_roughness();
    let mut get =
        |i: Option<gltf::texture::Info>, srgb: bool, what: &str| -> Result<Option<TextureRef>> {
            let Some(i) = i else { return Ok(None) };
            let id = texture(
                loader,
                path,
                buffers,
                &i.texture(),
                srgb,
                &format!("{place} {what}"),
            )?;
            Ok(Some(TextureRef {
                texture: id,
                transform: transform(&i),
                set: rendered_set(info_set(&i)),
            }))
        };
    let base_color = get(pbr.base_color_texture(), true, "baseColorTexture")?;
    let emissive = get(m.emissive_texture(), true, "emissiveTexture")?;
    let metallic_roughness = get(
        pbr.metallic_roughness_texture(),
        false,
        "metallicRoughnessTexture",
    )?;
    let normal = match m.normal_texture() {
        Some(n) => Some(TextureRef {
            set: rendered_set(n.tex_coord()),
            ..TextureRef::new(texture(
                loader,
                path,
                buffers,
                &n.texture(),
                false,
                &format!("{place} normalTexture"),
            )?)
        }),
        None => None,
    };
    let unit = |x: f32| {
        if x.is_finite() {
            x.clamp(0.0, 1.0)
        } else {
            1.0
        }
    };
    let strength = m
        .emissive_strength()
        .filter(|s| s.is_finite() && *s >= 0.0)
        .unwrap_or(1.0);
    let factor =
        Rgb::from_array(
            m.emissive_factor()
                .map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 }),
        );
    let alpha_mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask {
            cutoff: m.alpha_cutoff().filter(|c| c.is_finite()).unwrap_or(0.5),
        },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    Ok(MaterialMaps {
        base_color,
        // A factor without a texture is the material's own emission (an
        // Emissive material); with one, the texture scales it.
        emissive_factor: if emissive.is_some() {
            factor * strength
        } else {
            Rgb::ZERO
        },
        emissive,
        metallic_roughness,
        metallic: unit(pbr.metallic_factor()),
        roughness: unit(pbr.roughness_factor()),
        normal,
        normal_scale: m.normal_texture().map_or(1.0, |n| {
            if n.scale().is_finite() {
                n.scale()
            } else {
                1.0
            }
        }),
        alpha: unit(pbr.base_color_factor()[3]),
        alpha_mode,
        ..MaterialMaps::default()
    })
}

/// Reads a `TEXCOORD_n` accessor: FLOAT, or normalized UNSIGNED_BYTE or
/// UNSIGNED_SHORT, VEC2.
pub(crate) fn read_uvs(
    acc: &gltf::Accessor,
    buffers: &[Cow<[u8]>],
) -> std::result::Result<Vec<glam::Vec2>, String> {
    let (size, decode): (usize, fn(&[u8]) -> f32) = match (acc.data_type(), acc.normalized()) {
        (DataType::F32, _) => (4, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        (DataType::U8, true) => (1, |b| f32::from(b[0]) / 255.0),
        (DataType::U16, true) => (2, |b| f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0),
        _ => {
            return Err(format!(
                "accessor {} is {:?}; texture coordinates must be FLOAT or normalized UNSIGNED_BYTE/SHORT",
                acc.index(),
                acc.data_type()
            ))
        }
    };
    if acc.dimensions() != Dimensions::Vec2 || acc.sparse().is_some() {
        return Err(format!(
            "accessor {} must be a dense VEC2 for texture coordinates",
            acc.index()
        ));
    }
    let view = acc
        .view()
        .ok_or_else(|| format!("accessor {} has no buffer view", acc.index()))?;
    let elem = 2 * size;
    let (bytes, stride) =
        super::gltf_accessors::element_slice(&view, acc.offset(), acc.count(), elem, buffers)?;
    Ok((0..acc.count())
        .map(|i| {
            let b = &bytes[i * stride..i * stride + elem];
            let v = glam::Vec2::new(decode(b), decode(&b[size..]));
            if v.is_finite() {
                v
            } else {
                glam::Vec2::ZERO
            }
        })
        .collect())
}

/// The texture coordinates of the set the primitive's material uses
/// (none for an untextured material; unreadable ones are a warning).
pub(crate) fn primitive_uvs(
    prim: &gltf::Primitive,
    n: usize,
    buffers: &[Cow<[u8]>],
    (path, place): (&Path, &str),
    warnings: &mut Vec<String>,
) -> [Vec<glam::Vec2>; 2] {
    let mut out = [Vec::new(), Vec::new()];
    let sets = uv_sets(&prim.material());
    for &set in &sets {
        if set > 1 {
            warnings.push(format!(
                "{}: {place}: a texture reads TEXCOORD_{set}; only sets 0 and 1 are read, so it reads TEXCOORD_0",
                path.display()
            ));
            continue;
        }
        match prim
            .get(&gltf::Semantic::TexCoords(set))
            .map(|a| read_uvs(&a, buffers))
        {
            Some(Ok(uv)) if uv.len() == n => out[set as usize] = uv,
            other => {
                let why = match other {
                    None => "is missing".to_string(),
                    Some(Err(e)) => e,
                    Some(Ok(_)) => "has the wrong count".to_string(),
                };
                let fallback = if set == 1 { "TEXCOORD_0" } else { "(0, 0)" };
                warnings.push(format!(
                    "{}: {place}: TEXCOORD_{set} {why}; its textures read {fallback}",
                    path.display()
                ));
            }
        }
    }
    // Only set 1 read: it is the mesh's one set.
    if !sets.contains(&0) {
        out.swap(0, 1);
    }
    out
}
