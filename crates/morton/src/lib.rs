//! Morton (Z-order) codes in 2D and 3D: interleave the bits of integer cell
//! coordinates into one key, so that cells near each other in space tend to
//! be near each other in memory.
//!
//! The bits are interleaved with x lowest, as in the lecture:
//! `… z1 y1 x1 z0 y0 x0` in 3D and `… y1 x1 y0 x0` in 2D. So (5, 2, 1) =
//! (101, 010, 001) becomes 001 010 101 = 85.
//!
//! **Architecture invariant**: this crate knows unsigned integers only — no
//! vectors, no boxes, no grids — and has no dependencies. The grid turns
//! points into cell indices; this crate only turns cell indices into keys.
//!
//! ```
//! use gridrt_morton::{decode3, encode2, encode3, MAX_COORD3};
//!
//! assert_eq!(encode3(5, 2, 1), 85);
//! assert_eq!(decode3(85), (5, 2, 1));
//! assert_eq!(encode2(3, 5), 0b10_01_11);
//! // 21 bits per axis fit in 63 bits.
//! assert_eq!(encode3(MAX_COORD3, MAX_COORD3, MAX_COORD3), u64::MAX >> 1);
//! ```
//!
//! # What is here
//! - [`encode2`]/[`decode2`] (32 bits per axis) and [`encode3`]/[`decode3`]
//!   (21 bits per axis, see [`MAX_COORD3`]): portable "magic mask" bit
//!   spreading, the default everywhere.
//! - [`bmi2`]: the same four functions by the x86-64 BMI2 instructions
//!   `pdep`/`pext`, behind a run-time checked token ([`bmi2::Bmi2`]), plus
//!   batch versions for 3D. Faster on recent CPUs; see the crate README for
//!   measured ratios and why it is not the default.
//! - [`naive`]: one-bit-at-a-time loops, the obviously correct reference
//!   for tests and benchmarks.
//!
//! # Features
//! None: the crate has no optional parts and no dependencies. The BMI2 path
//! is chosen at run time (or at compile time when the build enables the
//! `bmi2` target feature), never by a Cargo feature.
#![warn(missing_docs)]

pub mod bmi2;
pub mod naive;

/// The largest coordinate [`encode3`] keeps: `2²¹ − 1`. Three 21-bit axes
/// fill 63 of a code's 64 bits. Larger inputs are masked (see [`encode3`]).
pub const MAX_COORD3: u32 = (1 << 21) - 1;

// Bit spreading by "magic masks": each step moves the upper half of every
// group of bits up by a shift and masks off the rest, halving the group size
// (Fabian Giesen, "Decoding Morton Codes", 2009,
// https://fgiesen.wordpress.com/2009/12/13/decoding-morton-codes/; the 64-bit
// 3D masks are those of Jeroen Baert's libmorton, `morton3D_64_encode` with
// magic bits; pbrt-v4's `LeftShift3` is the 32-bit version of the same).

/// The positions of x's bits in a 3D code: every third bit, 0 to 60.
pub(crate) const X3_MASK: u64 = 0x1249_2492_4924_9249;
/// The positions of x's bits in a 2D code: every other bit, 0 to 62.
pub(crate) const X2_MASK: u64 = 0x5555_5555_5555_5555;

/// Spreads the low 21 bits of `v` to every third bit: `b20…b1b0` →
/// `b20 0 0 … 0 0 b1 0 0 b0`. Higher bits of `v` are dropped.
#[inline]
#[must_use]
fn spread3(v: u32) -> u64 {
    let mut x = u64::from(v & MAX_COORD3);
    x = (x | x << 32) & 0x001F_0000_0000_FFFF;
    x = (x | x << 16) & 0x001F_0000_FF00_00FF;
    x = (x | x << 8) & 0x100F_00F0_0F00_F00F;
    x = (x | x << 4) & 0x10C3_0C30_C30C_30C3;
    x = (x | x << 2) & X3_MASK;
    x
}

/// The inverse of [`spread3`]: gathers every third bit (from bit 0) into
/// the low 21 bits.
#[inline]
#[must_use]
fn compact3(c: u64) -> u32 {
    let mut x = c & X3_MASK;
    x = (x ^ (x >> 2)) & 0x10C3_0C30_C30C_30C3;
    x = (x ^ (x >> 4)) & 0x100F_00F0_0F00_F00F;
    x = (x ^ (x >> 8)) & 0x001F_0000_FF00_00FF;
    x = (x ^ (x >> 16)) & 0x001F_0000_0000_FFFF;
    x = (x ^ (x >> 32)) & u64::from(MAX_COORD3);
    // Lossless: the mask above leaves 21 bits.
    x as u32
}

/// Spreads the 32 bits of `v` to every other bit of a `u64`.
#[inline]
#[must_use]
fn spread2(v: u32) -> u64 {
    let mut x = u64::from(v);
    x = (x | x << 16) & 0x0000_FFFF_0000_FFFF;
    x = (x | x << 8) & 0x00FF_00FF_00FF_00FF;
    x = (x | x << 4) & 0x0F0F_0F0F_0F0F_0F0F;
    x = (x | x << 2) & 0x3333_3333_3333_3333;
    x = (x | x << 1) & X2_MASK;
    x
}

/// The inverse of [`spread2`]: gathers every other bit (from bit 0).
#[inline]
#[must_use]
fn compact2(c: u64) -> u32 {
    let mut x = c & X2_MASK;
    x = (x ^ (x >> 1)) & 0x3333_3333_3333_3333;
    x = (x ^ (x >> 2)) & 0x0F0F_0F0F_0F0F_0F0F;
    x = (x ^ (x >> 4)) & 0x00FF_00FF_00FF_00FF;
    x = (x ^ (x >> 8)) & 0x0000_FFFF_0000_FFFF;
    x = (x ^ (x >> 16)) & 0x0000_0000_FFFF_FFFF;
    // Lossless: the mask above leaves 32 bits.
    x as u32
}

/// The 3D Morton code of `(x, y, z)`: bits interleaved as
/// `… z1 y1 x1 z0 y0 x0`, x lowest. Bit 63 is always 0.
///
/// **Out-of-range rule**: each coordinate keeps only its low 21 bits
/// (`v & MAX_COORD3`); higher bits are ignored, silently and in release and
/// debug builds alike, so `encode3(x, y, z) == encode3(x & MAX_COORD3, y &
/// MAX_COORD3, z & MAX_COORD3)`. Callers whose coordinates may exceed
/// [`MAX_COORD3`] (a grid with more than 2²¹ cells along an axis) must check
/// that themselves.
///
/// ```
/// use gridrt_morton::{encode3, MAX_COORD3};
/// assert_eq!(encode3(5, 2, 1), 0b000_001_010_101); // the lecture's 85
/// assert_eq!(encode3(1, 0, 0), 0b001);
/// assert_eq!(encode3(0, 0, 1), 0b100);
/// assert_eq!(encode3(MAX_COORD3 + 1, 0, 0), 0); // bit 21 is dropped
/// ```
///
/// See also [`decode3`], [`bmi2::Bmi2::encode3`], [`naive::encode3`].
#[inline]
#[must_use]
pub fn encode3(x: u32, y: u32, z: u32) -> u64 {
    spread3(x) | spread3(y) << 1 | spread3(z) << 2
}

/// The coordinates of a 3D Morton code: the inverse of [`encode3`] for
/// coordinates up to [`MAX_COORD3`]. Bit 63 (unused by [`encode3`]) is
/// ignored, so every `u64` decodes to coordinates in range.
///
/// ```
/// use gridrt_morton::{decode3, encode3};
/// assert_eq!(decode3(85), (5, 2, 1));
/// assert_eq!(decode3(encode3(123_456, 7, 2_000_000)), (123_456, 7, 2_000_000));
/// assert_eq!(decode3(1 << 63), (0, 0, 0));
/// ```
#[inline]
#[must_use]
pub fn decode3(code: u64) -> (u32, u32, u32) {
    (compact3(code), compact3(code >> 1), compact3(code >> 2))
}

/// The 2D Morton code of `(x, y)`: bits interleaved as `… y1 x1 y0 x0`,
/// x lowest. All 32 bits of each coordinate are kept.
///
/// ```
/// use gridrt_morton::encode2;
/// // Row y = 1 of the lecture's table: 000010 000011 000110 000111 …
/// assert_eq!(encode2(0, 1), 0b000010);
/// assert_eq!(encode2(3, 1), 0b000111);
/// assert_eq!(encode2(u32::MAX, u32::MAX), u64::MAX);
/// ```
///
/// See also [`decode2`], [`bmi2::Bmi2::encode2`], [`naive::encode2`].
#[inline]
#[must_use]
pub fn encode2(x: u32, y: u32) -> u64 {
    spread2(x) | spread2(y) << 1
}

/// The coordinates of a 2D Morton code: the exact inverse of [`encode2`].
///
/// ```
/// use gridrt_morton::{decode2, encode2};
/// assert_eq!(decode2(0b110110), (6, 5));
/// assert_eq!(decode2(encode2(0xDEAD_BEEF, 42)), (0xDEAD_BEEF, 42));
/// ```
#[inline]
#[must_use]
pub fn decode2(code: u64) -> (u32, u32) {
    (compact2(code), compact2(code >> 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lecture's 8×8 table, transcribed cell by cell: row y, column x.
    const LECTURE_TABLE: [[u64; 8]; 8] = [
        [
            0b000000, 0b000001, 0b000100, 0b000101, 0b010000, 0b010001, 0b010100, 0b010101,
        ],
        [
            0b000010, 0b000011, 0b000110, 0b000111, 0b010010, 0b010011, 0b010110, 0b010111,
        ],
        [
            0b001000, 0b001001, 0b001100, 0b001101, 0b011000, 0b011001, 0b011100, 0b011101,
        ],
        [
            0b001010, 0b001011, 0b001110, 0b001111, 0b011010, 0b011011, 0b011110, 0b011111,
        ],
        [
            0b100000, 0b100001, 0b100100, 0b100101, 0b110000, 0b110001, 0b110100, 0b110101,
        ],
        [
            0b100010, 0b100011, 0b100110, 0b100111, 0b110010, 0b110011, 0b110110, 0b110111,
        ],
        [
            0b101000, 0b101001, 0b101100, 0b101101, 0b111000, 0b111001, 0b111100, 0b111101,
        ],
        [
            0b101010, 0b101011, 0b101110, 0b101111, 0b111010, 0b111011, 0b111110, 0b111111,
        ],
    ];

    #[test]
    fn lecture_example_5_2_1_is_85() {
        assert_eq!(encode3(5, 2, 1), 85);
        assert_eq!(encode3(0b0101, 0b0010, 0b0001), 0b000001010101);
        assert_eq!(decode3(85), (5, 2, 1));
    }

    #[test]
    fn lecture_table_cell_by_cell() {
        for (y, row) in LECTURE_TABLE.iter().enumerate() {
            for (x, &code) in row.iter().enumerate() {
                let (x, y) = (x as u32, y as u32);
                assert_eq!(encode2(x, y), code, "encode2({x}, {y})");
                assert_eq!(decode2(code), (x, y), "decode2({code:#08b})");
                assert_eq!(naive::encode2(x, y), code, "naive::encode2({x}, {y})");
            }
        }
    }

    #[test]
    fn lecture_table_is_a_permutation_of_0_to_63() {
        let mut seen = [false; 64];
        for &code in LECTURE_TABLE.iter().flatten() {
            assert!(!seen[code as usize], "{code:#08b} twice");
            seen[code as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn unit_axes_land_on_their_bits() {
        assert_eq!(encode3(1, 0, 0), 1);
        assert_eq!(encode3(0, 1, 0), 2);
        assert_eq!(encode3(0, 0, 1), 4);
        assert_eq!(encode3(2, 0, 0), 8);
        assert_eq!(encode3(1 << 20, 0, 0), 1 << 60);
        assert_eq!(encode3(0, 0, 1 << 20), 1 << 62);
        assert_eq!(encode2(1 << 31, 0), 1 << 62);
        assert_eq!(encode2(0, 1 << 31), 1 << 63);
    }

    #[test]
    fn masks_cover_each_axis_exactly() {
        assert_eq!(spread3(MAX_COORD3), X3_MASK);
        assert_eq!(X3_MASK.count_ones(), 21);
        assert_eq!(X3_MASK | X3_MASK << 1 | X3_MASK << 2, u64::MAX >> 1);
        assert_eq!(spread2(u32::MAX), X2_MASK);
        assert_eq!(X2_MASK | X2_MASK << 1, u64::MAX);
    }

    #[test]
    fn encode3_masks_out_of_range_coordinates_to_21_bits() {
        for v in [MAX_COORD3 + 1, 1 << 31, u32::MAX, 0xABCD_EF01] {
            let low = v & MAX_COORD3;
            assert_eq!(encode3(v, 0, 0), encode3(low, 0, 0), "{v:#x}");
            assert_eq!(encode3(1, v, 2), encode3(1, low, 2), "{v:#x}");
            assert_eq!(encode3(3, 4, v), encode3(3, 4, low), "{v:#x}");
            assert_eq!(decode3(encode3(v, v, v)), (low, low, low));
        }
        assert_eq!(encode3(u32::MAX, u32::MAX, u32::MAX), u64::MAX >> 1);
    }

    #[test]
    fn decode3_ignores_bit_63() {
        assert_eq!(decode3(u64::MAX), (MAX_COORD3, MAX_COORD3, MAX_COORD3));
        assert_eq!(decode3(85 | 1 << 63), (5, 2, 1));
    }
}

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
