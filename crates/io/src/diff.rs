//! Comparing two images: the numbers `gridrt diff` prints and
//! `cargo xtask regress` checks, and a difference image.

use crate::error::{Error, Result};
use std::path::Path;

/// What the values of an image read by [`read_image`] mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageValues {
    /// 8-bit sRGB code values (0–255) of a PNG file.
    Srgb8,
    /// Linear floating-point values of an EXR file.
    Linear,
}

/// An RGB image read for comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `3 · width · height` channel values, row 0 (the top) first.
    pub values: Vec<f32>,
    /// What the values mean.
    pub kind: ImageValues,
}

/// Reads a PNG (as 8-bit code values) or an EXR (as linear floats) for
/// comparison; other channels (alpha) are dropped.
///
/// # Errors
/// [`Error::Output`] for another extension, [`Error::Images`] for a file
/// that cannot be decoded.
pub fn read_image(path: &Path) -> Result<RgbImage> {
    let format = crate::ImageFormat::from_path(path)?;
    let img = image::open(path).map_err(|e| Error::Images {
        path: path.to_path_buf(),
        msg: format!("cannot read the image: {e}"),
    })?;
    let (width, height) = (img.width(), img.height());
    let (values, kind) = match format {
        crate::ImageFormat::Png => (
            img.to_rgb8()
                .into_raw()
                .into_iter()
                .map(f32::from)
                .collect(),
            ImageValues::Srgb8,
        ),
        crate::ImageFormat::Exr => (img.to_rgb32f().into_raw(), ImageValues::Linear),
    };
    Ok(RgbImage {
        width,
        height,
        values,
        kind,
    })
}

/// What a comparison found, in the images' own units (8-bit steps for
/// PNG, linear values for EXR).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageDiff {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels with any channel different.
    pub pixels_differing: usize,
    /// Pixels with a channel differing by more than the threshold.
    pub pixels_over: usize,
    /// Mean absolute difference over all channels.
    pub mean_abs: f64,
    /// Root-mean-square difference over all channels.
    pub rmse: f64,
    /// Largest difference of one channel.
    pub max: f64,
}

/// The difference of two channel values: 0 when both are NaN, infinite
/// when only one is (or when both are infinities of opposite sign).
fn channel_diff(a: f32, b: f32) -> f64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        0.0
    } else if a.is_nan() || b.is_nan() {
        f64::INFINITY
    } else {
        (f64::from(a) - f64::from(b)).abs()
    }
}

/// Compares two images given as packed RGB channel values of the same
/// length. A pixel is "over" when one of its channels differs by more than
/// `threshold`. Returns the numbers and each channel's absolute
/// difference.
///
/// ```
/// use gridrt_io::diff_values;
/// let (d, per_channel) = diff_values(&[0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &[0.0, 0.0, 0.0, 1.0, 4.0, 1.0], 2.0);
/// assert_eq!((d.pixels, d.pixels_differing, d.pixels_over), (2, 1, 1));
/// assert_eq!(d.max, 3.0);
/// assert_eq!(per_channel[4], 3.0);
/// ```
///
/// # Panics
/// If the lengths differ (callers compare sizes first).
#[must_use]
pub fn diff_values(a: &[f32], b: &[f32], threshold: f64) -> (ImageDiff, Vec<f64>) {
    assert_eq!(a.len(), b.len(), "images must be the same size");
    let per_channel: Vec<f64> = a.iter().zip(b).map(|(&x, &y)| channel_diff(x, y)).collect();
    let mut d = ImageDiff {
        pixels: a.len() / 3,
        ..ImageDiff::default()
    };
    let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
    for px in per_channel.chunks_exact(3) {
        let m = px.iter().copied().fold(0.0, f64::max);
        d.max = d.max.max(m);
        d.pixels_differing += usize::from(m > 0.0);
        d.pixels_over += usize::from(m > threshold);
        sum += px.iter().sum::<f64>();
        sum_sq += px.iter().map(|x| x * x).sum::<f64>();
    }
    let n = a.len().max(1) as f64;
    d.mean_abs = sum / n;
    d.rmse = (sum_sq / n).sqrt();
    (d, per_channel)
}

/// Compares the images in two files (PNG with PNG, EXR with EXR).
///
/// # Errors
/// [`Error::Images`] when a file cannot be read, the formats differ or
/// the sizes differ.
pub fn diff_files(a: &Path, b: &Path, threshold: f64) -> Result<(ImageDiff, RgbImage)> {
    let (ia, ib) = (read_image(a)?, read_image(b)?);
    if ia.kind != ib.kind {
        return Err(Error::Images {
            path: b.to_path_buf(),
            msg: format!(
                "is {} but {} is {}: compare PNG with PNG and EXR with EXR",
                kind_name(ib.kind),
                a.display(),
                kind_name(ia.kind)
            ),
        });
    }
    if (ia.width, ia.height) != (ib.width, ib.height) {
        return Err(Error::Images {
            path: b.to_path_buf(),
            msg: format!(
                "is {} x {} but {} is {} x {}",
                ib.width,
                ib.height,
                a.display(),
                ia.width,
                ia.height
            ),
        });
    }
    let (d, per_channel) = diff_values(&ia.values, &ib.values, threshold);
    let diff = RgbImage {
        values: per_channel.iter().map(|&x| x as f32).collect(),
        ..ia
    };
    Ok((d, diff))
}

/// "8-bit sRGB" or "linear float".
#[must_use]
pub fn kind_name(kind: ImageValues) -> &'static str {
    match kind {
        ImageValues::Srgb8 => "8-bit sRGB",
        ImageValues::Linear => "linear float",
    }
}

/// Writes a difference image (from [`diff_files`]) magnified by `gain`:
/// as 8-bit PNG (values clamped) or as linear EXR, by the path's
/// extension, atomically.
///
/// # Errors
/// As [`crate::write_image`].
pub fn write_diff_image(path: &Path, diff: &RgbImage, gain: f32) -> Result<()> {
    let scale = match diff.kind {
        // 8-bit steps back to [0, 1] display values, then to linear so that
        // the PNG writer's sRGB encoding gives the magnified step back.
        ImageValues::Srgb8 => gain / 255.0,
        ImageValues::Linear => gain,
    };
    let pixels: Vec<gridrt_tracer::Rgb> = diff
        .values
        .chunks_exact(3)
        .map(|c| {
            let v = |x: f32| {
                let y = (x * scale).min(1.0e30);
                if diff.kind == ImageValues::Srgb8 {
                    srgb_to_linear(y.min(1.0))
                } else {
                    y
                }
            };
            gridrt_tracer::Rgb::new(v(c[0]), v(c[1]), v(c[2]))
        })
        .collect();
    crate::write_image(path, diff.width, diff.height, &pixels)
}

/// The inverse of [`crate::linear_to_srgb`] on [0, 1].
fn srgb_to_linear(s: f32) -> f32 {
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nan_and_infinity_compare_sensibly() {
        assert_eq!(channel_diff(f32::NAN, f32::NAN), 0.0);
        assert_eq!(channel_diff(f32::NAN, 1.0), f64::INFINITY);
        assert_eq!(channel_diff(f32::INFINITY, f32::INFINITY), 0.0);
        assert_eq!(channel_diff(2.0, -1.0), 3.0);
    }

    #[test]
    fn numbers_of_a_small_diff() {
        let a = [0.0f32; 12];
        let mut b = a;
        b[4] = 6.0;
        let (d, _) = diff_values(&a, &b, 2.0);
        assert_eq!((d.pixels, d.pixels_differing, d.pixels_over), (4, 1, 1));
        assert_eq!(d.max, 6.0);
        assert!((d.rmse - (36.0f64 / 12.0).sqrt()).abs() < 1e-12);
        assert!((d.mean_abs - 0.5).abs() < 1e-12);
        let (same, _) = diff_values(&a, &a, 0.0);
        assert_eq!(same.pixels_differing, 0);
    }

    #[test]
    fn files_of_other_size_or_format_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let px = vec![gridrt_tracer::Rgb::new(0.5, 0.25, 1.0); 6];
        let a = dir.path().join("a.png");
        let b = dir.path().join("b.png");
        let c = dir.path().join("c.exr");
        crate::write_image(&a, 3, 2, &px).unwrap();
        crate::write_image(&b, 2, 3, &px).unwrap();
        crate::write_image(&c, 3, 2, &px).unwrap();
        let (d, diff) = diff_files(&a, &a, 0.0).unwrap();
        assert_eq!(d.pixels_differing, 0);
        assert_eq!(diff.values.len(), 18);
        assert!(diff_files(&a, &b, 0.0)
            .unwrap_err()
            .to_string()
            .contains("2 x 3"));
        assert!(diff_files(&a, &c, 0.0)
            .unwrap_err()
            .to_string()
            .contains("PNG with PNG"));
        let out = dir.path().join("d.png");
        write_diff_image(&out, &diff, 32.0).unwrap();
        assert!(out.is_file());
    }
}
