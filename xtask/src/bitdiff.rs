//! Bit-for-bit comparison of two linear framebuffers (grid vs exhaustive).

use gridrt_tracer::Framebuffer;
use std::fmt;

/// How two framebuffers that should be identical differ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BitDiff {
    /// Pixels whose channels differ in at least one bit.
    pub pixels: usize,
    /// Pixels compared.
    pub compared: usize,
    /// The largest absolute difference of one channel (NaN when a NaN is
    /// involved).
    pub max_abs: f32,
    /// The first differing pixel, (x, y) with y = 0 at the top.
    pub first: (u32, u32),
}

impl fmt::Display for BitDiff {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} of {} pixels differ (largest channel difference {:e}, first at x {}, y {})",
            self.pixels, self.compared, self.max_abs, self.first.0, self.first.1
        )
    }
}

/// Compares `a` and `b` bit for bit (the `f32` channels' bit patterns, so
/// `-0.0 ≠ 0.0` and a NaN equals only the same NaN), over the rows `rows`
/// (`None`: every row; y = 0 at the top). `Ok(None)` means identical.
///
/// # Errors
/// A message when the sizes differ or a row is outside the image.
pub fn bitwise_diff(
    a: &Framebuffer,
    b: &Framebuffer,
    rows: Option<&[u32]>,
) -> Result<Option<BitDiff>, String> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(format!(
            "the images differ in size: {}×{} and {}×{}",
            a.width, a.height, b.width, b.height
        ));
    }
    let all: Vec<u32>;
    let rows = match rows {
        Some(r) => r,
        None => {
            all = (0..a.height).collect();
            &all
        }
    };
    let w = a.width as usize;
    let mut out = BitDiff {
        pixels: 0,
        compared: 0,
        max_abs: 0.0,
        first: (0, 0),
    };
    for &y in rows {
        if y >= a.height {
            return Err(format!("row {y} is outside the {}-row image", a.height));
        }
        let start = y as usize * w;
        for (x, (p, q)) in a.pixels[start..start + w]
            .iter()
            .zip(&b.pixels[start..start + w])
            .enumerate()
        {
            out.compared += 1;
            let (p, q) = (p.to_array(), q.to_array());
            if p.iter().zip(&q).any(|(s, t)| s.to_bits() != t.to_bits()) {
                if out.pixels == 0 {
                    out.first = (x as u32, y);
                }
                out.pixels += 1;
                for (s, t) in p.iter().zip(&q) {
                    let d = (s - t).abs();
                    // NaN propagates on purpose: it is worth seeing.
                    out.max_abs = if d.is_nan() || out.max_abs.is_nan() {
                        f32::NAN
                    } else {
                        out.max_abs.max(d)
                    };
                }
            }
        }
    }
    Ok((out.pixels > 0).then_some(out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_tracer::Rgb;

    fn fb(w: u32, h: u32) -> Framebuffer {
        Framebuffer::new(w, h)
    }

    #[test]
    fn identical_images_have_no_diff() {
        let mut a = fb(3, 2);
        a.pixels[4] = Rgb::new(0.5, 0.25, 1.0);
        assert_eq!(bitwise_diff(&a, &a.clone(), None), Ok(None));
    }

    #[test]
    fn one_bit_and_the_sign_of_zero_count() {
        let a = fb(3, 2);
        let mut b = a.clone();
        b.pixels[5] = Rgb::new(-0.0, 0.0, 0.0);
        let d = bitwise_diff(&a, &b, None).unwrap().unwrap();
        assert_eq!(
            (d.pixels, d.compared, d.first, d.max_abs),
            (1, 6, (2, 1), 0.0)
        );
        b.pixels[1] = Rgb::new(0.0, f32::from_bits(1), 0.0);
        let d = bitwise_diff(&a, &b, None).unwrap().unwrap();
        assert_eq!((d.pixels, d.first), (2, (1, 0)));
    }

    #[test]
    fn only_the_given_rows_are_compared() {
        let a = fb(2, 3);
        let mut b = a.clone();
        b.pixels[2] = Rgb::ONE; // row 1
        assert_eq!(bitwise_diff(&a, &b, Some(&[0, 2])), Ok(None));
        let d = bitwise_diff(&a, &b, Some(&[1])).unwrap().unwrap();
        assert_eq!((d.pixels, d.compared, d.max_abs), (1, 2, 1.0));
        assert!(bitwise_diff(&a, &b, Some(&[3])).is_err());
    }

    #[test]
    fn nan_is_reported_and_sizes_must_match() {
        let a = fb(1, 1);
        let mut b = a.clone();
        b.pixels[0] = Rgb::new(f32::NAN, 0.0, 0.0);
        assert!(bitwise_diff(&a, &b, None)
            .unwrap()
            .unwrap()
            .max_abs
            .is_nan());
        assert!(bitwise_diff(&a, &fb(2, 1), None).is_err());
    }
}
