//! Lights of a scene file: from the schema to the tracer's lights, and
//! the environment images they name (read through the sandbox).

use crate::error::{Error, Result};
use crate::model::{self, to_vec3};
use crate::sandbox::Sandbox;
use crate::scene::{f32s, unit, v3};
use crate::schema::LightDesc;
use gridrt_bbox::Real;
use gridrt_tracer::{EnvImage, Light, Occlusion, Rgb};
use std::path::{Path, PathBuf};

pub(crate) fn light(d: &LightDesc) -> Light {
    match d {
        LightDesc::Ambient {
            color,
            intensity,
            occlusion,
        } => Light::Ambient {
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            occlusion: occlusion.as_ref().map(|o| Occlusion {
                samples: o.samples.0,
                // A distance beyond the range of `Real` is no limit.
                distance: o.distance.map_or(Real::INFINITY, |d| d.0 as Real),
                min_amount: f32s(o.min_amount.0),
            }),
        },
        LightDesc::Point {
            position,
            color,
            intensity,
            inverse_square,
            shadows,
        } => Light::Point {
            position: v3(position.0),
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            inverse_square: *inverse_square,
            shadows: *shadows,
        },
        LightDesc::Directional {
            direction,
            color,
            intensity,
            shadows,
        } => Light::Directional {
            // Kept as written when it fits (the tracer normalises it).
            direction: Some(v3(direction.0))
                .filter(|d| d.is_finite())
                .unwrap_or_else(|| to_vec3(unit(direction.0))),
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            shadows: *shadows,
        },
        LightDesc::Spot {
            position,
            direction,
            color,
            intensity,
            outer,
            inner,
            inverse_square,
            shadows,
        } => Light::Spot {
            position: v3(position.0),
            direction: to_vec3(unit(direction.0)),
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            inner_deg: f32s(inner.map_or((outer.0 - 5.0).max(0.0), |a| a.0)),
            outer_deg: f32s(outer.0),
            inverse_square: *inverse_square,
            shadows: *shadows,
        },
        LightDesc::Rect {
            corner,
            edge_u,
            edge_v,
            color,
            intensity,
        } => Light::Rect {
            corner: v3(corner.0),
            edge_u: v3(edge_u.0),
            edge_v: v3(edge_v.0),
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
        },
        LightDesc::Disk {
            center,
            normal,
            radius,
            color,
            intensity,
        } => Light::Disk {
            center: v3(center.0),
            normal: to_vec3(unit(normal.0)),
            radius: radius.0 as Real,
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
        },
        // The image, if any, is loaded by `Builder::env_image`.
        LightDesc::Environment {
            color, intensity, ..
        } => Light::Environment {
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            image: None,
        },
    }
}

/// Loads the equirectangular image `file` of an environment light (at
/// `place` in the scene `path`, whose resolved path is `real`) through the
/// sandbox: a Radiance `.hdr` or an OpenEXR `.exr`, as linear RGB.
pub(crate) fn env_image(
    path: &Path,
    real: &Path,
    sandbox: &Sandbox,
    place: String,
    file: &str,
) -> Result<EnvImage> {
    let shown = path
        .parent()
        .map_or_else(|| PathBuf::from(file), |d| d.join(file));
    let bad = |msg: String| Error::scene(path, place.clone(), msg);
    let ext = Path::new(file)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match ext.as_deref() {
        Some("hdr") => image::ImageFormat::Hdr,
        Some("exr") => image::ImageFormat::OpenExr,
        _ => {
            return Err(bad(format!(
                "environment image \"{file}\": give a Radiance .hdr or an OpenEXR .exr file"
            )))
        }
    };
    let real = sandbox
        .resolve(real, Path::new(file), false)
        .map_err(|e| match e {
            Error::Denied {
                reference, model, ..
            } => Error::Denied {
                path: path.to_path_buf(),
                place: place.clone(),
                reference,
                model,
            },
            e => e,
        })?;
    let bytes = sandbox.read(&real)?;
    let img = image::load_from_memory_with_format(&bytes, format)
        .map_err(|e| bad(format!("environment image {}: {e}", shown.display())))?;
    if u64::from(img.width()) * u64::from(img.height()) > gridrt_tracer::MAX_PIXELS {
        return Err(bad(format!(
            "environment image {}: {}×{} pixels, over the limit of 2^26: scale it down",
            shown.display(),
            img.width(),
            img.height()
        )));
    }
    let rgb = img.to_rgb32f();
    let pixels: Vec<Rgb> = rgb.pixels().map(|p| Rgb::new(p[0], p[1], p[2])).collect();
    if let Some(k) = pixels
        .iter()
        .position(|p| !p.is_finite() || p.min_element() < 0.0)
    {
        return Err(bad(format!(
            "environment image {}: pixel ({}, {}) is negative or not finite",
            shown.display(),
            k % rgb.width() as usize,
            k / rgb.width() as usize
        )));
    }
    Ok(EnvImage {
        width: rgb.width(),
        height: rgb.height(),
        pixels,
    })
}
