//! Comparing two 8-bit RGB images against a tolerance: the numbers come
//! from `gridrt_io::diff_values` (what `gridrt diff` prints), plus a
//! magnified difference image.

use serde::Deserialize;

/// How far an image may stray from its reference. The default is exact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tolerance {
    /// Largest allowed root-mean-square error over all channels, in 8-bit steps.
    pub max_rmse: f64,
    /// Largest allowed difference of one channel, in 8-bit steps.
    pub max_pixel: u8,
    /// A pixel "differs" when one of its channels differs by more than this.
    pub pixel_threshold: u8,
    /// Largest allowed fraction (0–1) of pixels that differ.
    pub max_fraction_over: f64,
}

/// What a comparison found.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diff {
    /// Root-mean-square error over all channels, in 8-bit steps.
    pub rmse: f64,
    /// Largest difference of one channel, in 8-bit steps.
    pub max_pixel: u8,
    /// Fraction of pixels with a channel differing by more than the threshold.
    pub fraction_over: f64,
    /// Pixels with any difference at all.
    pub pixels_differing: usize,
}

impl Diff {
    /// The reasons this diff breaks the tolerance (empty when it passes).
    pub fn violations(&self, tol: &Tolerance) -> Vec<String> {
        let mut v = Vec::new();
        if self.rmse > tol.max_rmse {
            v.push(format!("RMSE {:.4} > {:.4}", self.rmse, tol.max_rmse));
        }
        if self.max_pixel > tol.max_pixel {
            v.push(format!(
                "max pixel difference {} > {}",
                self.max_pixel, tol.max_pixel
            ));
        }
        if self.fraction_over > tol.max_fraction_over {
            v.push(format!(
                "{:.4}% of pixels differ by more than {} > {:.4}%",
                100.0 * self.fraction_over,
                tol.pixel_threshold,
                100.0 * tol.max_fraction_over
            ));
        }
        v
    }
}

/// Each channel's difference is multiplied by this in the regression's diff
/// images.
pub const DIFF_GAIN: u32 = 32;

/// Compares two images of the same size, given as tightly packed RGB8 bytes.
/// Returns the numbers and a difference image (each channel's difference
/// magnified by `gain`, clamped to 255).
///
/// # Panics
/// If the buffers differ in length (callers check sizes first).
pub fn compare(reference: &[u8], actual: &[u8], threshold: u8, gain: u32) -> (Diff, Vec<u8>) {
    let as_f32 = |b: &[u8]| b.iter().map(|&x| f32::from(x)).collect::<Vec<f32>>();
    // The numbers `gridrt diff` prints, from the same code.
    let (d, per_channel) =
        gridrt_io::diff_values(&as_f32(reference), &as_f32(actual), f64::from(threshold));
    // 8-bit values differ by whole steps of at most 255.
    let step = |x: f64| x.min(255.0) as u8;
    let diff_img = per_channel
        .iter()
        .map(|&x| (u32::from(step(x)) * gain).min(255) as u8)
        .collect();
    let pixels = d.pixels.max(1);
    let diff = Diff {
        rmse: d.rmse,
        max_pixel: step(d.max),
        fraction_over: d.pixels_over as f64 / pixels as f64,
        pixels_differing: d.pixels_differing,
    };
    (diff, diff_img)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_pass_exact_tolerance() {
        let img = vec![10u8, 20, 30, 40, 50, 60];
        let (d, diff) = compare(&img, &img, 0, 8);
        assert_eq!(d, Diff::default());
        assert!(d.violations(&Tolerance::default()).is_empty());
        assert!(diff.iter().all(|&b| b == 0));
    }

    #[test]
    fn one_changed_channel_fails_exact_and_is_measured() {
        let a = vec![0u8; 12];
        let mut b = a.clone();
        b[4] = 6;
        let (d, diff) = compare(&a, &b, 2, 10);
        assert_eq!(d.max_pixel, 6);
        assert_eq!(d.pixels_differing, 1);
        assert!((d.fraction_over - 0.25).abs() < 1e-12);
        assert!((d.rmse - (36.0f64 / 12.0).sqrt()).abs() < 1e-12);
        assert_eq!(diff[4], 60);
        assert_eq!(d.violations(&Tolerance::default()).len(), 3);
        let loose = Tolerance {
            max_rmse: 2.0,
            max_pixel: 6,
            pixel_threshold: 2,
            max_fraction_over: 0.25,
        };
        assert!(d.violations(&loose).is_empty());
    }
}
