//! Owen-scrambled Sobol points (Burley, "Practical Hash-based Owen
//! Scrambling", JCGT 9(4), 2020): the first two Sobol dimensions, each
//! scrambled by a hash-based nested uniform scramble, with the sample index
//! shuffled per pixel and per dimension pair (pbrt-v4's `PaddedSobolSampler`).

use super::cmj::ONE_MINUS_ULP;
use gridrt_bbox::Real;

/// Direction numbers of Sobol dimension 1 (primitive polynomial `x + 1`,
/// `m₁ = 1`, so `m_k = m_{k−1} ⊕ 2·m_{k−1}`), as 32-bit columns.
const DIR1: [u32; 32] = {
    let mut v = [0u32; 32];
    let mut m: u64 = 1;
    let mut k = 0;
    while k < 32 {
        // m_k has k + 1 bits; its column is m_k · 2^(31 − k).
        v[k] = (m << (31 - k)) as u32;
        m ^= m << 1;
        k += 1;
    }
    v
};

/// Sobol dimension `dim` (0 or 1) of point `index`, as a 32-bit fraction.
#[inline]
fn sobol_bits(index: u32, dim: u32) -> u32 {
    if dim == 0 {
        // The van der Corput sequence: the index's bits reversed.
        return index.reverse_bits();
    }
    let mut x = 0u32;
    let mut i = index;
    let mut k = 0;
    while i != 0 {
        if i & 1 != 0 {
            x ^= DIR1[k];
        }
        i >>= 1;
        k += 1;
    }
    x
}

/// Laine and Karras's hash, which permutes a value so that each bit depends
/// only on the bits below it (Burley's improved constants).
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// A nested uniform (Owen) scramble of a base-2 fraction: each bit is
/// flipped by a hash of the bits above it.
#[inline]
pub(crate) fn owen_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// A 32-bit fraction as a [`Real`] in `[0, 1)`.
#[inline]
pub(crate) fn to_unit(x: u32) -> Real {
    ((x >> 8) as Real * (1.0 / 16_777_216.0)).min(ONE_MINUS_ULP)
}

/// Point `index` of the Owen-scrambled 2D Sobol sequence with the seeds
/// `(sx, sy)`.
#[inline]
pub(crate) fn sobol_2d(index: u32, sx: u32, sy: u32) -> (Real, Real) {
    (
        to_unit(owen_scramble(sobol_bits(index, 0), sx)),
        to_unit(owen_scramble(sobol_bits(index, 1), sy)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dimension_one_starts_as_published() {
        // Joe and Kuo's second dimension in index (not Gray-code) order.
        let want = [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875];
        for (i, w) in want.iter().enumerate() {
            assert_eq!(sobol_bits(i as u32, 1) as f64 / 4_294_967_296.0, *w);
        }
    }

    #[test]
    fn scrambled_points_stay_a_0_m_2_net() {
        // Every elementary interval of area 1/16 holds one of 16 points,
        // before and after scrambling.
        for seed in [0u32, 1, 0x1234_5678] {
            let pts: Vec<(u32, u32)> = (0..16)
                .map(|i| {
                    (
                        owen_scramble(sobol_bits(i, 0), seed),
                        owen_scramble(sobol_bits(i, 1), seed ^ 0x9e37),
                    )
                })
                .collect();
            for bx in 0..=4u32 {
                let by = 4 - bx;
                let mut seen = std::collections::HashSet::new();
                for &(x, y) in &pts {
                    let cx = if bx == 0 { 0 } else { x >> (32 - bx) };
                    let cy = if by == 0 { 0 } else { y >> (32 - by) };
                    assert!(seen.insert((cx, cy)), "seed {seed}, {bx}x{by} strata");
                }
            }
        }
    }
}
