//! Writing render passes (AOVs): as extra channels of the EXR image, or as
//! PNG pictures beside a PNG image.

use crate::error::Result;
use crate::image_out::Staged;
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, ImageAttributes, IntegerBounds, Layer,
    LayerAttributes, WritableImage,
};
use gridrt_tracer::{Aov, AovImage, Framebuffer, Rgb};
use std::path::{Path, PathBuf};

/// Parses `--aov albedo,normal,...` (names as [`Aov::name`]; `all` for
/// every pass).
///
/// # Errors
/// A message naming an unknown pass and listing the known ones.
pub fn parse_aovs(s: &str) -> std::result::Result<Vec<Aov>, String> {
    if s.trim() == "all" {
        return Ok(Aov::ALL.to_vec());
    }
    let mut v = Vec::new();
    for name in s.split(',').map(str::trim) {
        let aov = Aov::from_name(name).ok_or_else(|| {
            let known: Vec<&str> = Aov::ALL.iter().map(|a| a.name()).collect();
            format!(
                "unknown pass `{}`: use {} or all",
                name.escape_debug(),
                known.join(", ")
            )
        })?;
        if !v.contains(&aov) {
            v.push(aov);
        }
    }
    Ok(v)
}

/// EXR channel names of a pass: `albedo.R`, `normal.X`, `depth.Z`, …
fn channel_names(aov: Aov) -> Vec<String> {
    let suffixes: &[&str] = match aov {
        Aov::Albedo => &["R", "G", "B"],
        Aov::Normal | Aov::Position => &["X", "Y", "Z"],
        Aov::Depth => &["Z"],
        _ => &["V"],
    };
    suffixes
        .iter()
        .map(|s| format!("{}.{s}", aov.name()))
        .collect()
}

/// Writes the image and its passes as one EXR file: the image as `R`, `G`,
/// `B` (linear, as rendered) and each pass as channels named after it
/// (`albedo.R`, `normal.X`, `depth.Z`, `tests.V`, …), atomically.
///
/// # Errors
/// As [`crate::write_atomic`].
pub fn write_exr_with_aovs(path: &Path, image: &Framebuffer, aovs: &[AovImage]) -> Result<()> {
    stage_exr_with_aovs(path, image, aovs)?.commit()
}

/// [`write_exr_with_aovs`] up to the rename (see [`crate::stage`]).
///
/// # Errors
/// As [`crate::write_atomic`].
pub fn stage_exr_with_aovs(path: &Path, image: &Framebuffer, aovs: &[AovImage]) -> Result<Staged> {
    let plane = |f: fn(&Rgb) -> f32| FlatSamples::F32(image.pixels.iter().map(f).collect());
    let mut channels = vec![
        AnyChannel::new("R", plane(|p| p.x)),
        AnyChannel::new("G", plane(|p| p.y)),
        AnyChannel::new("B", plane(|p| p.z)),
    ];
    for a in aovs {
        let n = a.aov.channels();
        for (c, name) in channel_names(a.aov).into_iter().enumerate() {
            let v = a.values.iter().skip(c).step_by(n).copied().collect();
            channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(v)));
        }
    }
    let size = (image.width as usize, image.height as usize);
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let out = Image::from_layers(
        ImageAttributes::new(IntegerBounds::from_dimensions(size)),
        vec![layer],
    );
    crate::stage(path, |file| {
        let mut w = std::io::BufWriter::new(file);
        out.write()
            .non_parallel()
            .to_buffered(&mut w)
            .map_err(std::io::Error::other)?;
        std::io::Write::flush(&mut w)
    })
}

/// The file a pass is written to beside a PNG image: `out.png` →
/// `out.albedo.png`.
#[must_use]
pub fn aov_png_path(image: &Path, aov: Aov) -> PathBuf {
    let stem = image
        .file_stem()
        .map_or_else(|| "out".into(), |s| s.to_string_lossy().into_owned());
    image.with_file_name(format!("{stem}.{}.png", aov.name()))
}

/// A colour for a count in `[0, max]`: dark blue through green and yellow
/// to white, in linear RGB.
fn heat(v: f32, max: f32) -> Rgb {
    let x = if max > 0.0 {
        (v / max).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let stops = [
        Rgb::new(0.0, 0.0, 0.02),
        Rgb::new(0.0, 0.05, 0.5),
        Rgb::new(0.0, 0.6, 0.2),
        Rgb::new(1.0, 0.8, 0.0),
        Rgb::new(1.0, 1.0, 1.0),
    ];
    let f = x * (stops.len() - 1) as f32;
    let i = (f as usize).min(stops.len() - 2);
    stops[i].lerp(stops[i + 1], f - i as f32)
}

/// A colour per id, fixed for the id (−1, nothing: black).
fn id_colour(id: f32) -> Rgb {
    if id < 0.0 {
        return Rgb::ZERO;
    }
    let mut h = (id as u32).wrapping_mul(0x9e37_79b9) ^ 0x5bd1_e995;
    h ^= h >> 15;
    let c = |s: u32| 0.1 + 0.9 * ((h >> s) & 0xff) as f32 / 255.0;
    Rgb::new(c(0), c(8), c(16))
}

/// A pass as a picture: albedo as colour, normals as `0.5 + 0.5 n`, depth
/// from near (white) to far (dark), position scaled to the range seen, ids as a colour per id, cells
/// and tests as a heat map up to their largest value.
fn picture(a: &AovImage) -> Vec<Rgb> {
    let finite_max = |it: &mut dyn Iterator<Item = f32>| {
        it.filter(|v| v.is_finite())
            .fold(0.0f32, |m, v| m.max(v.abs()))
    };
    match a.aov {
        Aov::Albedo => a
            .values
            .chunks_exact(3)
            .map(|c| Rgb::new(c[0], c[1], c[2]))
            .collect(),
        // Displayed values: the PNG writer encodes with the sRGB curve, so
        // these are decoded first to show 0.5 + 0.5 n as such.
        Aov::Normal => a
            .values
            .chunks_exact(3)
            .map(|c| {
                let d = |x: f32| srgb_decode(0.5 + 0.5 * x);
                Rgb::new(d(c[0]), d(c[1]), d(c[2]))
            })
            .collect(),
        Aov::Position => {
            let m = finite_max(&mut a.values.iter().copied()).max(f32::MIN_POSITIVE);
            a.values
                .chunks_exact(3)
                .map(|c| {
                    let d = |x: f32| srgb_decode(0.5 + 0.5 * x / m);
                    Rgb::new(d(c[0]), d(c[1]), d(c[2]))
                })
                .collect()
        }
        Aov::Depth => {
            // Near (white) to far (dark) between the nearest depth and the
            // 98th percentile, so a floor running to the horizon does not
            // flatten the rest.
            let mut seen: Vec<f32> = a.values.iter().copied().filter(|z| z.is_finite()).collect();
            seen.sort_by(f32::total_cmp);
            let near = seen.first().copied().unwrap_or(0.0);
            let far = seen.get(seen.len() * 98 / 100).copied().unwrap_or(near);
            // On a log scale: equal ratios of distance, equal steps of grey.
            let span = (far.max(near) / near.max(f32::MIN_POSITIVE))
                .ln()
                .max(f32::MIN_POSITIVE);
            a.values
                .iter()
                .map(|&z| {
                    if z.is_finite() {
                        let v = ((z / near.max(f32::MIN_POSITIVE)).ln() / span).clamp(0.0, 1.0);
                        Rgb::splat(srgb_decode(1.0 - 0.85 * v))
                    } else {
                        Rgb::ZERO
                    }
                })
                .collect()
        }
        Aov::PrimId | Aov::MaterialId => a.values.iter().map(|&i| id_colour(i)).collect(),
        Aov::CellsVisited | Aov::Tests => {
            let m = finite_max(&mut a.values.iter().copied());
            a.values.iter().map(|&v| heat(v, m)).collect()
        }
    }
}

fn srgb_decode(s: f32) -> f32 {
    let s = s.clamp(0.0, 1.0);
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// Writes each pass beside a PNG image as a picture ([`aov_png_path`]),
/// atomically, and returns the paths written.
///
/// # Errors
/// As [`crate::write_image`].
pub fn write_aov_pngs(image: &Path, aovs: &[AovImage]) -> Result<Vec<PathBuf>> {
    let staged = stage_aov_pngs(image, aovs)?;
    let mut written = Vec::new();
    for (a, s) in aovs.iter().zip(staged) {
        s.commit()?;
        written.push(aov_png_path(image, a.aov));
    }
    Ok(written)
}

/// [`write_aov_pngs`] up to the renames (see [`crate::stage`]).
///
/// # Errors
/// As [`crate::write_image`].
pub fn stage_aov_pngs(image: &Path, aovs: &[AovImage]) -> Result<Vec<Staged>> {
    aovs.iter()
        .map(|a| crate::stage_image(&aov_png_path(image, a.aov), a.width, a.height, &picture(a)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pass_lists_parse() {
        assert_eq!(parse_aovs("all").unwrap().len(), 8);
        assert_eq!(
            parse_aovs("normal, tests,normal").unwrap(),
            vec![Aov::Normal, Aov::Tests]
        );
        let e = parse_aovs("albedo,colour").unwrap_err();
        assert!(e.contains("`colour`") && e.contains("cells-visited"), "{e}");
    }

    #[test]
    fn names_and_pictures() {
        assert_eq!(
            aov_png_path(Path::new("dir/out.png"), Aov::CellsVisited),
            PathBuf::from("dir/out.cells-visited.png")
        );
        assert_eq!(
            channel_names(Aov::Normal),
            ["normal.X", "normal.Y", "normal.Z"]
        );
        assert_eq!(heat(0.0, 10.0), Rgb::new(0.0, 0.0, 0.02));
        assert_eq!(heat(10.0, 10.0), Rgb::ONE);
        assert_eq!(id_colour(-1.0), Rgb::ZERO);
        assert_eq!(id_colour(7.0), id_colour(7.0));
        assert_ne!(id_colour(7.0), id_colour(8.0));
    }

    #[test]
    fn exr_holds_the_passes_as_channels() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.exr");
        let img = Framebuffer::new(2, 1);
        let depth = AovImage {
            aov: Aov::Depth,
            width: 2,
            height: 1,
            values: vec![1.5, f32::INFINITY],
        };
        write_exr_with_aovs(&p, &img, &[depth]).unwrap();
        let read = exr::prelude::read_all_flat_layers_from_file(&p).unwrap();
        let ch = &read.layer_data[0].channel_data.list;
        let z = ch.iter().find(|c| c.name.eq("depth.Z")).unwrap();
        match &z.sample_data {
            FlatSamples::F32(v) => assert_eq!(v, &vec![1.5, f32::INFINITY]),
            other => panic!("{other:?}"),
        }
    }
}
