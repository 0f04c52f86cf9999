//! Correlated multi-jittered sampling (Kensler, "Correlated Multi-Jittered
//! Sampling", Pixar technical memo 13-01, 2013) and the integer hashes the
//! other samplers share.
//!
//! A sample depends only on the pixel index, the sample index and the sample
//! count, through integer hashes: no state is carried between pixels, so an
//! image is bit-identical whatever the tiling and the thread count.

use gridrt_bbox::Real;

/// Kensler's hash-based permutation of `0..l`: the `i`-th element of the
/// permutation number `p`.
#[inline]
pub(crate) fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    debug_assert!(l > 0 && i < l);
    if l == 1 {
        // The only permutation of one element (what the loop gives too),
        // without its dozen multiplications: one sample per pixel asks
        // for it three times per dimension pair.
        return 0;
    }
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    rem(i.wrapping_add(p), l)
}

/// `a % l`, by a mask when `l` is a power of two (the common sample
/// counts), sparing the division.
#[inline]
fn rem(a: u32, l: u32) -> u32 {
    if l.is_power_of_two() {
        a & (l - 1)
    } else {
        a % l
    }
}

/// Kensler's hash to a float in `[0, 1)`.
#[inline]
pub(crate) fn randfloat(mut i: u32, p: u32) -> Real {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | p >> 18);
    // The top 24 bits, so the result is exactly representable and < 1.
    (i >> 8) as Real * (1.0 / 16_777_216.0)
}

/// A 32-bit hash of a pixel index (and a seed), used as the CMJ pattern.
#[inline]
pub(crate) fn pixel_pattern(pixel: u64, seed: u32) -> u32 {
    // SplitMix64's finaliser, folded to 32 bits.
    let mut z = pixel
        .wrapping_add(u64::from(seed) << 32)
        .wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z ^ (z >> 32)) as u32
}

/// Sample `s` of `n` in the unit square for the pattern `p`: stratified in
/// both dimensions and jittered inside its stratum (the `m × ⌈n/m⌉` grid,
/// `m = ⌊√n⌋`, works for any `n`, not only squares).
#[cfg(test)]
pub(crate) fn cmj(s: u32, n: u32, p: u32) -> (Real, Real) {
    Strata::new(n).cmj(s, p)
}

/// The `m × rows` strata of `n` samples (`m = ⌊√n⌋`, `rows = ⌈n/m⌉`),
/// computed once per sample stream rather than per dimension pair.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Strata {
    n: u32,
    m: u32,
    rows: u32,
    /// `1/n`, `1/m`, `1/rows`: used for the divisions by powers of two,
    /// where they are exact and so give the same bits as dividing.
    inv: [Real; 3],
}

impl Strata {
    /// The strata of `n > 0` samples.
    #[inline]
    pub(crate) fn new(n: u32) -> Self {
        let m = ((n as f64).sqrt() as u32).max(1);
        let rows = n.div_ceil(m);
        let inv = [n, m, rows].map(|d| 1.0 / d as Real);
        Self { n, m, rows, inv }
    }

    /// `x / d` for `d` the count `i` (0: n, 1: m, 2: rows).
    #[inline]
    fn div(&self, x: Real, i: usize) -> Real {
        let d = [self.n, self.m, self.rows][i];
        if d.is_power_of_two() {
            x * self.inv[i]
        } else {
            x / d as Real
        }
    }

    /// Correlated multi-jittered sample `s` for the pattern `p`.
    #[inline]
    pub(crate) fn cmj(&self, s: u32, p: u32) -> (Real, Real) {
        if self.n == 1 {
            // One stratum: every permutation below gives 0 and every
            // division is by 1, so the sample is its jitter, bit for bit.
            // One sample per pixel asks for it once per dimension pair.
            return jitter(0, p);
        }
        self.stratified(s, p)
    }

    /// [`Strata::cmj`] through the strata, for any `n`.
    #[inline]
    fn stratified(&self, s: u32, p: u32) -> (Real, Real) {
        let (n, m, rows) = (self.n, self.m, self.rows);
        debug_assert!(s < n);
        let s = permute(s, n, p.wrapping_mul(0x5163_3e2d));
        let (col, row) = if m.is_power_of_two() {
            (s & (m - 1), s >> m.trailing_zeros())
        } else {
            (s % m, s / m)
        };
        let sx = permute(col, m, p.wrapping_mul(0x68bc_21eb));
        let sy = permute(row, rows, p.wrapping_mul(0x02e5_be93));
        let (jx, jy) = jitter(s, p);
        let x = self.div(sx as Real + self.div(sy as Real + jx, 2), 1);
        let y = self.div(s as Real + jy, 0);
        // Rounding can reach 1.0 in the last stratum; stay inside the pixel.
        (x.min(ONE_MINUS_ULP), y.min(ONE_MINUS_ULP))
    }
}

/// The jitter of (permuted) sample `s` for the pattern `p` inside its
/// stratum, in `[0, 1)²`.
#[inline]
fn jitter(s: u32, p: u32) -> (Real, Real) {
    (
        randfloat(s, p.wrapping_mul(0x967a_889b)),
        randfloat(s, p.wrapping_mul(0x368c_c8b7)),
    )
}

/// The largest [`Real`] below 1.
pub(crate) const ONE_MINUS_ULP: Real = 1.0 - Real::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_is_the_stratified_sample() {
        let one = Strata::new(1);
        for p in (0..2000u32).map(|k| k.wrapping_mul(0x9e37_79b9)) {
            let (fast, slow) = (one.cmj(0, p), one.stratified(0, p));
            assert_eq!(fast.0.to_bits(), slow.0.to_bits(), "p = {p}");
            assert_eq!(fast.1.to_bits(), slow.1.to_bits(), "p = {p}");
        }
    }

    #[test]
    fn permute_is_a_permutation() {
        for l in [1u32, 2, 3, 7, 16, 33] {
            for p in [0u32, 1, 0xdead_beef] {
                let mut seen = vec![false; l as usize];
                for i in 0..l {
                    let j = permute(i, l, p) as usize;
                    assert!(!seen[j]);
                    seen[j] = true;
                }
            }
        }
    }

    /// Kensler's formula with plain remainders and divisions.
    fn cmj_by_division(s: u32, n: u32, p: u32) -> (Real, Real) {
        let m = ((n as f64).sqrt() as u32).max(1);
        let rows = n.div_ceil(m);
        let s = permute(s, n, p.wrapping_mul(0x5163_3e2d));
        let sx = permute(s % m, m, p.wrapping_mul(0x68bc_21eb));
        let sy = permute(s / m, rows, p.wrapping_mul(0x02e5_be93));
        let (jx, jy) = jitter(s, p);
        let x = (sx as Real + (sy as Real + jx) / rows as Real) / m as Real;
        let y = (s as Real + jy) / n as Real;
        (x.min(ONE_MINUS_ULP), y.min(ONE_MINUS_ULP))
    }

    #[test]
    fn strata_give_the_same_bits_as_dividing() {
        for n in [1u32, 2, 3, 4, 8, 9, 12, 16, 64, 100, 256, 1000, 1024] {
            let strata = Strata::new(n);
            for p in [0u32, 1, 0x1234_5678, 0xdead_beef] {
                for s in 0..n {
                    let (a, b) = (strata.cmj(s, p), cmj_by_division(s, n, p));
                    assert_eq!(
                        (a.0.to_bits(), a.1.to_bits()),
                        (b.0.to_bits(), b.1.to_bits())
                    );
                }
            }
        }
    }

    #[test]
    fn cmj_is_stratified_in_both_dimensions() {
        for n in [4u32, 9, 16, 5, 12] {
            for pixel in 0..20u64 {
                let p = pixel_pattern(pixel, 0);
                let pts: Vec<_> = (0..n).map(|s| cmj(s, n, p)).collect();
                // One sample per row stratum of height 1/n.
                let mut rows = vec![0; n as usize];
                for &(x, y) in &pts {
                    assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
                    rows[(y * n as Real) as usize] += 1;
                }
                assert!(rows.iter().all(|&c| c == 1), "n = {n}: {rows:?}");
                // And the same samples again: deterministic.
                assert_eq!(pts, (0..n).map(|s| cmj(s, n, p)).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn patterns_differ_between_pixels() {
        assert_ne!(pixel_pattern(0, 0), pixel_pattern(1, 0));
        assert_ne!(pixel_pattern(7, 0), pixel_pattern(7, 1));
    }
}
