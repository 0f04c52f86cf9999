//! Samplers, sample-space maps and reconstruction filters.
//!
//! A sample is a function of the pixel, the sample index, the number of
//! samples per pixel and the dimension only, through integer hashes
//! (`SampleStream`): no state is carried between pixels, so an image is
//! bit-identical whatever the tiling and the thread count. Dimensions are
//! consumed in 2D pairs (pixel position, lens, light, BSDF, …); each pair of
//! each pixel gets its own scramble and its own shuffle of the sample index,
//! as pbrt-v4's padded samplers do, so pairs are not correlated.

mod cmj;
mod filter;
pub mod maps;
mod sobol;

#[cfg(test)]
pub(crate) use cmj::cmj;
pub(crate) use cmj::pixel_pattern;
pub use filter::Filter;
pub(crate) use filter::FilterTable;

use cmj::{permute, randfloat, Strata, ONE_MINUS_ULP};
use gridrt_bbox::Real;
use std::fmt;

/// How the samples of a pixel are placed (Suffern ch. 5, pbrt-v4 ch. 8).
/// Every kind is deterministic per pixel and sample index.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum SamplerKind {
    /// Independent uniform random numbers (hashed, so reproducible).
    Random,
    /// The centres of a regular `m × ⌈n/m⌉` grid of strata (`m = ⌊√n⌋`):
    /// no randomness at all within a pixel.
    Regular,
    /// One random point in each cell of that grid (stratified sampling).
    Jittered,
    /// Correlated multi-jittered sampling (Kensler 2013): stratified in 2D
    /// and in each 1D projection (the default).
    #[default]
    MultiJittered,
    /// The Hammersley point set `(i/n, φ₂(i))`, randomised by a random
    /// digit scramble and a shift per pixel.
    Hammersley,
    /// Owen-scrambled Sobol points (Burley 2020), a (0, 2)-sequence in every
    /// pair of dimensions.
    Sobol,
}

impl SamplerKind {
    /// The name the scene format and the command line use.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Random => "random",
            SamplerKind::Regular => "regular",
            SamplerKind::Jittered => "jittered",
            SamplerKind::MultiJittered => "multi-jittered",
            SamplerKind::Hammersley => "hammersley",
            SamplerKind::Sobol => "sobol",
        }
    }
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A 32-bit mix (Wellons' `lowbias32`): cheap and well spread.
#[inline]
fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// The samples of one pixel: its hashes and the strata of its sample count,
/// computed once for all of its samples ([`PixelSamples::stream`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PixelSamples {
    kind: SamplerKind,
    /// The first pair's pattern (the historical pixel pattern).
    first: u32,
    /// A hash of the pixel, the root of every other pair's seeds.
    base: u32,
    /// Samples per pixel.
    n: u32,
    /// The multi-jittered strata of `n` samples.
    strata: Strata,
}

impl PixelSamples {
    /// `n` samples of `kind` for pixel 0; [`PixelSamples::at`] moves them to
    /// another pixel without recomputing the strata.
    #[inline]
    pub(crate) fn new(kind: SamplerKind, n: u32) -> Self {
        debug_assert!(n > 0);
        Self {
            kind,
            first: 0,
            base: 0,
            n,
            strata: Strata::new(n),
        }
        .at(0)
    }

    /// The same samples for the pixel with image index `pixel`.
    #[inline]
    #[must_use]
    pub(crate) fn at(self, pixel: u64) -> Self {
        Self {
            first: pixel_pattern(pixel, 0),
            base: pixel_pattern(pixel, 0x5eed),
            ..self
        }
    }

    /// Sample `index` of the pixel's `n`.
    #[inline]
    pub(crate) fn stream(&self, index: u32) -> SampleStream<'_> {
        debug_assert!(index < self.n);
        SampleStream {
            pixel: self,
            index,
            pair: 0,
        }
    }
}

/// The samples of one pixel sample: dimension pairs are drawn in order with
/// [`SampleStream::next_2d`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct SampleStream<'p> {
    /// The pixel's hashes and strata, borrowed: a copy made per sample
    /// would be read back through wider loads than its stores, which
    /// stalls store-to-load forwarding on every sample.
    pixel: &'p PixelSamples,
    /// Sample index in `0..n`.
    index: u32,
    /// The next dimension pair.
    pair: u32,
}

impl SampleStream<'_> {
    /// The next 2D sample in `[0, 1)²`.
    #[inline]
    pub(crate) fn next_2d(&mut self) -> (Real, Real) {
        let pair = self.pair;
        self.pair += 1;
        self.get(pair)
    }

    /// A seed for pair `pair` and purpose `c`.
    #[inline]
    fn seed(&self, pair: u32, c: u32) -> u32 {
        mix32(self.pixel.base ^ pair.wrapping_mul(0x9e37_79b9) ^ c.wrapping_mul(0x85eb_ca6b))
    }

    /// Dimension pair `pair` of this sample.
    ///
    /// For [`SamplerKind::MultiJittered`] the first pair is exactly the
    /// renderer's historical pixel pattern, `cmj(s, n, pixel_pattern(pixel,
    /// 0))`, so images made with it do not change.
    #[inline]
    fn get(&self, pair: u32) -> (Real, Real) {
        let (s, n, kind) = (self.index, self.pixel.n, self.pixel.kind);
        let seed = if pair == 0 {
            self.pixel.first
        } else {
            self.seed(pair, 0)
        };
        match kind {
            SamplerKind::Random => (
                randfloat(s, self.seed(pair, 1)),
                randfloat(s, self.seed(pair, 2)),
            ),
            SamplerKind::Regular | SamplerKind::Jittered => {
                let m = ((n as f64).sqrt() as u32).max(1);
                let rows = n.div_ceil(m);
                // A shuffled stratum per pair, so pairs are not correlated.
                let k = if pair == 0 { s } else { permute(s, n, seed) };
                let (jx, jy) = if kind == SamplerKind::Regular {
                    (0.5, 0.5)
                } else {
                    (
                        randfloat(s, seed.wrapping_mul(0x967a_889b)),
                        randfloat(s, seed.wrapping_mul(0x368c_c8b7)),
                    )
                };
                let x = (((k % m) as Real + jx) / m as Real).min(ONE_MINUS_ULP);
                let y = (((k / m) as Real + jy) / rows as Real).min(ONE_MINUS_ULP);
                (x, y)
            }
            SamplerKind::MultiJittered => self.pixel.strata.cmj(s, seed),
            SamplerKind::Hammersley => {
                let k = permute(s, n, seed);
                // One shift per pixel and pair (a Cranley-Patterson rotation).
                let shift = randfloat(0, seed.wrapping_mul(0x68bc_21eb));
                let mut x = k as Real / n as Real + shift;
                if x >= 1.0 {
                    x -= 1.0;
                }
                let y = sobol::to_unit(k.reverse_bits() ^ seed.wrapping_mul(0x02e5_be93));
                (x.min(ONE_MINUS_ULP), y)
            }
            SamplerKind::Sobol => {
                let k = permute(s, n, seed);
                sobol::sobol_2d(k, self.seed(pair, 0x50b0), self.seed(pair, 0x50b1))
            }
        }
    }
}

/// Point `k` of `n` of a Hammersley set shifted by `u` modulo 1 (a
/// Cranley-Patterson rotation): `n` well-spread points in `[0, 1)²` drawn
/// from one 2D sample, for estimators that take many directions at one
/// shading point (ambient occlusion). Every point of `[0, 1)²` is equally
/// likely for each `k` when `u` is uniform, so the average is unbiased.
#[inline]
pub(crate) fn rotated_hammersley(k: u32, n: u32, u: (Real, Real)) -> (Real, Real) {
    debug_assert!(k < n);
    let wrap = |x: Real| (if x >= 1.0 { x - 1.0 } else { x }).min(ONE_MINUS_ULP);
    let x = (k as Real + 0.5) / n as Real;
    let y = sobol::to_unit(k.reverse_bits());
    (wrap(x + u.0), wrap(y + u.1))
}

/// Dimension pair `pair` of sample `s` of `n` of pixel `pixel`.
#[cfg(test)]
pub(crate) fn sample_2d(kind: SamplerKind, pixel: u64, s: u32, n: u32, pair: u32) -> (Real, Real) {
    PixelSamples::new(kind, n).at(pixel).stream(s).get(pair)
}

#[cfg(test)]
mod tests {
    use super::*;

    const KINDS: [SamplerKind; 6] = [
        SamplerKind::Random,
        SamplerKind::Regular,
        SamplerKind::Jittered,
        SamplerKind::MultiJittered,
        SamplerKind::Hammersley,
        SamplerKind::Sobol,
    ];

    #[test]
    fn samples_lie_in_the_unit_square_and_repeat() {
        for kind in KINDS {
            for n in [1u32, 2, 5, 16, 37] {
                for pair in 0..4 {
                    for s in 0..n {
                        let a = sample_2d(kind, 12_345, s, n, pair);
                        assert!((0.0..1.0).contains(&a.0) && (0.0..1.0).contains(&a.1));
                        assert_eq!(a, sample_2d(kind, 12_345, s, n, pair));
                    }
                }
            }
        }
    }

    #[test]
    fn the_first_pair_of_multi_jittered_is_the_historical_pattern() {
        for s in 0..9 {
            assert_eq!(
                sample_2d(SamplerKind::MultiJittered, 77, s, 9, 0),
                cmj(s, 9, pixel_pattern(77, 0))
            );
        }
    }

    /// Mean of `f` over `n` samples of pair `pair`, averaged over pixels.
    fn mean(kind: SamplerKind, n: u32, pair: u32, f: impl Fn(Real, Real) -> f64) -> f64 {
        let pixels = 64u64;
        let mut sum = 0.0;
        for p in 0..pixels {
            for s in 0..n {
                let (x, y) = sample_2d(kind, p, s, n, pair);
                sum += f(x, y);
            }
        }
        sum / (pixels as f64 * f64::from(n))
    }

    #[test]
    fn every_sampler_integrates_a_smooth_function() {
        // ∫∫ x·y = 1/4 and ∫∫ sin(πx) = 2/π over the unit square. The
        // regular grid is the midpoint rule: its error is deterministic
        // (0.016 for sin with 4 columns), the others' is noise.
        for kind in KINDS {
            let tol = if kind == SamplerKind::Regular {
                0.02
            } else {
                0.01
            };
            for pair in [0, 3] {
                let xy = mean(kind, 16, pair, |x, y| crate::float::to_f64(x * y));
                assert!((xy - 0.25).abs() < tol, "{kind} pair {pair}: {xy}");
                let s = mean(kind, 16, pair, |x, _| {
                    (std::f64::consts::PI * crate::float::to_f64(x)).sin()
                });
                assert!(
                    (s - 2.0 / std::f64::consts::PI).abs() < tol,
                    "{kind} pair {pair}: {s}"
                );
            }
        }
    }

    #[test]
    fn stratified_samplers_fill_every_row_stratum() {
        // 16 samples: one per horizontal stratum of height 1/4 × 4 each for
        // the grid samplers, one per 1/16 for the (0, 2) and CMJ ones.
        for kind in [
            SamplerKind::Jittered,
            SamplerKind::Regular,
            SamplerKind::MultiJittered,
            SamplerKind::Sobol,
        ] {
            for pair in 0..3 {
                let mut rows = [0u32; 4];
                for s in 0..16 {
                    let (_, y) = sample_2d(kind, 5, s, 16, pair);
                    rows[(y * 4.0) as usize] += 1;
                }
                assert_eq!(rows, [4; 4], "{kind} pair {pair}");
            }
        }
    }

    #[test]
    fn pairs_and_pixels_are_decorrelated() {
        for kind in [SamplerKind::Sobol, SamplerKind::MultiJittered] {
            assert_ne!(sample_2d(kind, 1, 0, 4, 1), sample_2d(kind, 1, 0, 4, 2));
            assert_ne!(sample_2d(kind, 1, 0, 4, 1), sample_2d(kind, 2, 0, 4, 1));
        }
    }

    #[test]
    fn rotated_hammersley_keeps_one_point_per_column_and_row() {
        let n = 16;
        for u in [(0.0, 0.0), (0.37, 0.91), (0.999, 0.5)] {
            let mut cols = [0u32; 16];
            let mut rows = [0u32; 16];
            for k in 0..n {
                let (x, y) = rotated_hammersley(k, n, u);
                assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
                cols[(x * n as Real) as usize] += 1;
                rows[(y * n as Real) as usize] += 1;
            }
            // A shifted (0, 2)-net keeps its strata, up to wrap-around.
            assert!(cols.iter().all(|&c| c == 1), "{u:?}: {cols:?}");
            assert!(rows.iter().all(|&c| c <= 2), "{u:?}: {rows:?}");
        }
    }
}
