//! MTL texture maps: `map_Kd` (base colour), `map_Ke` (emission), `map_d`
//! (opacity: cut-outs), `norm` (tangent-space normal map) and
//! `map_Bump` / `bump` (height map), with the options `-s` and `-o`
//! (scale and offset of the coordinates), `-bm` (bump multiplier) and
//! `-clamp on`; other options are skipped.

use super::texture_load::TextureLoader;
use crate::error::Result;
use gridrt_tracer::texture::{AlphaMode, Sampler, UvTransform, Wrap};
use gridrt_tracer::{MaterialMaps, Rgb, TextureRef};
use std::path::Path;

/// One texture statement: the file and its options.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MapSpec {
    pub file: String,
    pub transform: UvTransform,
    pub bump: f32,
    pub clamp: bool,
}

/// Parses `[-opt args…]… file` (a file name may hold spaces).
pub(crate) fn parse_map(text: &str) -> Option<MapSpec> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let mut spec = MapSpec {
        file: String::new(),
        transform: UvTransform::IDENTITY,
        bump: 1.0,
        clamp: false,
    };
    let mut i = 0;
    let num = |w: Option<&&str>| {
        w.and_then(|w| w.parse::<f32>().ok())
            .filter(|x| x.is_finite())
    };
    while i < words.len() && words[i].starts_with('-') && words[i].len() > 1 {
        let args = match words[i] {
            "-s" | "-o" | "-t" => 3,
            "-mm" => 2,
            "-blendu" | "-blendv" | "-boost" | "-texres" | "-clamp" | "-imfchan" | "-type"
            | "-cc" | "-bm" => 1,
            _ => 0,
        };
        match words[i] {
            "-s" => {
                let (u, v) = (num(words.get(i + 1)), num(words.get(i + 2)));
                spec.transform.scale = glam::Vec2::new(u.unwrap_or(1.0), v.unwrap_or(1.0));
            }
            "-o" => {
                let (u, v) = (num(words.get(i + 1)), num(words.get(i + 2)));
                spec.transform.offset = glam::Vec2::new(u.unwrap_or(0.0), v.unwrap_or(0.0));
            }
            "-bm" => spec.bump = num(words.get(i + 1)).unwrap_or(1.0),
            "-clamp" => spec.clamp = words.get(i + 1) == Some(&"on"),
            _ => {}
        }
        // `-s` and `-o` take one to three numbers: skip only the numbers.
        let mut k = 1;
        while k <= args
            && words
                .get(i + k)
                .is_some_and(|w| w.parse::<f32>().is_ok() || args == 1)
        {
            k += 1;
        }
        i += k;
    }
    spec.file = words.get(i..)?.join(" ");
    (!spec.file.is_empty()).then_some(spec)
}

/// The maps of MTL material `m`, loading its textures; `ke` is its
/// emission colour (`Ke`, or 1 when only `map_Ke` is given).
#[allow(clippy::unnecessary_cast)] // tobj's numbers are f64 with the `f64` feature
pub(crate) fn maps(m: &tobj::Material, loader: &mut TextureLoader) -> Result<MaterialMaps> {
    let place = format!("material \"{}\"", m.name);
    let mut get =
        |text: Option<&String>, srgb: bool, what: &str| -> Result<Option<(TextureRef, MapSpec)>> {
            let Some(spec) = text.and_then(|t| parse_map(t)) else {
                return Ok(None);
            };
            let wrap = if spec.clamp {
                Wrap::Clamp
            } else {
                Wrap::Repeat
            };
            let sampler = Sampler {
                wrap_u: wrap,
                wrap_v: wrap,
                ..Sampler::DEFAULT
            };
            let id = loader.file(
                Path::new(&spec.file),
                srgb,
                sampler,
                &format!("{place} {what}"),
            )?;
            Ok(Some((
                TextureRef {
                    texture: id,
                    transform: spec.transform,
                    set: 0,
                },
                spec,
            )))
        };
    let base_color = get(m.diffuse_texture.as_ref(), true, "map_Kd")?;
    let emissive = get(m.unknown_param.get("map_Ke"), true, "map_Ke")?;
    let opacity = get(m.dissolve_texture.as_ref(), false, "map_d")?;
    let normal = get(m.unknown_param.get("norm"), false, "norm")?;
    let bump = get(m.normal_texture.as_ref(), false, "map_Bump")?;
    let ke = m
        .emissive
        .map(|c| Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32))
        .filter(|c| c.is_finite() && c.cmpge(Rgb::ZERO).all() && *c != Rgb::ZERO)
        .unwrap_or(Rgb::ONE);
    let d = m
        .dissolve
        .map(|x| x as f32)
        .filter(|x| x.is_finite())
        .map_or(1.0, |x| x.clamp(0.0, 1.0));
    Ok(MaterialMaps {
        base_color: base_color.map(|(r, _)| r),
        emissive_factor: if emissive.is_some() { ke } else { Rgb::ZERO },
        emissive: emissive.map(|(r, _)| r),
        alpha: if opacity.is_some() { d } else { 1.0 },
        alpha_mode: if opacity.is_some() {
            AlphaMode::Mask { cutoff: 0.5 }
        } else {
            AlphaMode::Opaque
        },
        opacity: opacity.map(|(r, _)| r),
        normal: normal.map(|(r, _)| r),
        // Heights in texture units: a full-range step over 1/256 of the
        // texture (one texel of a 256-texel map) times `-bm`.
        bump_scale: bump.as_ref().map_or(1.0, |(_, s)| s.bump / 256.0),
        bump: bump.map(|(r, _)| r),
        ..MaterialMaps::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_parsed_and_the_file_kept() {
        let s = parse_map("-bm 0.5 -s 2 3 -o 0.1 0.2 0 -clamp on my bump.png").unwrap();
        assert_eq!(s.file, "my bump.png");
        assert_eq!(s.bump, 0.5);
        assert!(s.clamp);
        assert_eq!(s.transform.scale, glam::Vec2::new(2.0, 3.0));
        assert_eq!(s.transform.offset, glam::Vec2::new(0.1, 0.2));
        assert_eq!(parse_map("tex.jpg").unwrap().file, "tex.jpg");
        assert_eq!(parse_map("-s 2 tex.jpg").unwrap().file, "tex.jpg");
        assert!(parse_map("-bm 1").is_none());
    }
}
