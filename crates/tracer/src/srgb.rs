//! Linear light to sRGB: the transfer function of 8-bit images (PNG), and
//! its 8-bit code values, shared by the renderer (which can keep an image
//! as sRGB bytes while it renders) and the image writers.

use crate::scene::Rgb;

/// Linear to sRGB, the exact piecewise transfer function (IEC 61966-2-1),
/// clamped to [0, 1]; NaN gives 0.
///
/// ```
/// use gridrt_tracer::linear_to_srgb;
/// assert_eq!(linear_to_srgb(0.0), 0.0);
/// assert_eq!(linear_to_srgb(1.0), 1.0);
/// assert!((linear_to_srgb(0.5) - 0.7354).abs() < 1e-4); // not 0.5^(1/2.2) = 0.7297
/// assert_eq!(linear_to_srgb(f32::NAN), 0.0);
/// ```
#[must_use]
pub fn linear_to_srgb(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        0.0
    } else if x >= 1.0 {
        1.0
    } else if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Linear to an 8-bit sRGB code value: [`linear_to_srgb`], scaled and
/// rounded.
fn srgb8_exact(x: f32) -> u8 {
    (linear_to_srgb(x) * 255.0 + 0.5) as u8
}

/// Linear to an 8-bit sRGB code value: [`linear_to_srgb`] scaled by 255
/// and rounded, without a `powf` per channel. The code of `x` is the
/// number of the 255 thresholds at or below it, threshold `k` being the
/// least `f32` whose exact code is at least `k`. A table gives the code at
/// the start of each of the 128 equal steps of every octave from 2⁻¹³ to 1,
/// where no step holds two thresholds; one comparison with the next
/// threshold finishes. The two agree wherever the exact code never
/// decreases as `x` grows, which holds while `powf` does not decrease; a
/// test compares them around every threshold and across [0, 1]. NaN gives
/// 0.
///
/// ```
/// use gridrt_tracer::srgb8;
/// assert_eq!((srgb8(0.0), srgb8(0.5), srgb8(1.0), srgb8(7.0)), (0, 188, 255, 255));
/// ```
#[inline]
#[must_use]
pub fn srgb8(x: f32) -> u8 {
    // NaN fails the comparison: code 0, as `srgb8_exact` gives.
    if !(x >= STEPS_FROM) {
        return 0;
    }
    if x >= 1.0 {
        return 255;
    }
    let t = Srgb8Table::get();
    let code = t.step_code[step_of(x)];
    code + u8::from(x >= t.threshold[usize::from(code) + 1])
}

/// Below this (2⁻¹³) every code is 0: the first threshold is above it.
const STEPS_FROM: f32 = 1.0 / 8192.0;
/// Mantissa bits that pick a step within an octave (128 steps).
const STEP_BITS: u32 = 7;
/// The octaves from [`STEPS_FROM`] to 1.
const OCTAVES: usize = 13;

/// The step of `x` in [[`STEPS_FROM`], 1): its exponent and top mantissa
/// bits, counted from `STEPS_FROM`'s.
fn step_of(x: f32) -> usize {
    ((x.to_bits() - STEPS_FROM.to_bits()) >> (23 - STEP_BITS)) as usize
}

/// The tables of [`srgb8`].
struct Srgb8Table {
    /// The exact code at the first float of each step.
    step_code: [u8; OCTAVES << STEP_BITS],
    /// `threshold[k]`: the least float whose code is at least `k`, for `k`
    /// in 1..=255; `threshold[256]` is infinite (no code above 255).
    threshold: [f32; 257],
}

impl Srgb8Table {
    fn get() -> &'static Srgb8Table {
        static TABLE: std::sync::OnceLock<Srgb8Table> = std::sync::OnceLock::new();
        TABLE.get_or_init(|| Srgb8Table {
            step_code: std::array::from_fn(|i| {
                let first = STEPS_FROM.to_bits() + ((i as u32) << (23 - STEP_BITS));
                srgb8_exact(f32::from_bits(first))
            }),
            threshold: std::array::from_fn(|k| match k {
                0 => 0.0,
                256 => f32::INFINITY,
                k => least_with_code(k as u8),
            }),
        })
    }
}

/// The 8-bit sRGB codes of linear `pixels` into `out`, three bytes a
/// pixel (R, G, B, each [`srgb8`]): the bytes of a PNG.
///
/// # Panics
/// If `out.len() != 3 · pixels.len()`.
pub fn srgb8_into(out: &mut [u8], pixels: &[Rgb]) {
    assert_eq!(out.len(), 3 * pixels.len(), "three bytes a pixel");
    for (o, p) in out.chunks_exact_mut(3).zip(pixels) {
        o.copy_from_slice(&[srgb8(p.x), srgb8(p.y), srgb8(p.z)]);
    }
}

/// The least `f32` in [0, 1] whose [`srgb8_exact`] is at least `code`: a
/// binary search over the bit patterns, which for non-negative floats are
/// ordered as the values are.
fn least_with_code(code: u8) -> f32 {
    let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if srgb8_exact(f32::from_bits(mid)) >= code {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    f32::from_bits(lo)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_is_continuous_and_monotonic() {
        let knee = 0.003_130_8_f32;
        let below = 12.92 * knee;
        let above = 1.055 * knee.powf(1.0 / 2.4) - 0.055;
        assert!((below - above).abs() < 1e-6);
        let mut last = 0.0;
        for i in 0..=1000 {
            let s = linear_to_srgb(i as f32 / 1000.0);
            assert!(s >= last);
            last = s;
        }
        assert_eq!(srgb8(0.5), 188);
        assert_eq!(srgb8(2.0), 255);
        assert_eq!(srgb8(-1.0), 0);
    }

    #[test]
    fn srgb8_by_thresholds_equals_the_exact_code() {
        for x in [
            0.0,
            -0.0,
            -1.0,
            1.0,
            2.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ] {
            assert_eq!(srgb8(x), srgb8_exact(x), "{x}");
        }
        // Each code's first float and its two neighbours.
        for code in 1..=255u8 {
            let t = least_with_code(code).to_bits();
            for b in [t - 1, t, t + 1] {
                let x = f32::from_bits(b);
                assert_eq!(srgb8(x), srgb8_exact(x), "{x:e}");
            }
        }
        // No step of the table holds two thresholds.
        let steps: Vec<usize> = (1..=255u8).map(least_with_code).map(step_of).collect();
        assert!(steps.windows(2).all(|w| w[0] < w[1]), "{steps:?}");
        assert!(least_with_code(1) >= STEPS_FROM);
        // Floats spread over [0, 1] by bit pattern (a prime stride).
        for b in (0..=1.0f32.to_bits()).step_by(257) {
            let x = f32::from_bits(b);
            assert_eq!(srgb8(x), srgb8_exact(x), "{x:e}");
        }
    }
}
