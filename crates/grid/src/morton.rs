//! Morton (Z-order) helpers the grid needs on top of plain encoding: per-axis
//! spread tables and stepping a code by one cell along one axis.
//!
//! Encoding follows `gridrt-morton`'s convention: 21 bits per axis, x in the
//! lowest bit, then y, then z (`… z1 y1 x1 z0 y0 x0`).

/// The bits of a Morton code that belong to each axis (x, y, z), 21 bits each.
pub(crate) const AXIS_MASK: [u64; 3] = [
    0x1249_2492_4924_9249,
    0x1249_2492_4924_9249 << 1,
    0x1249_2492_4924_9249 << 2,
];

/// The largest cell index per axis that a 63-bit Morton code can hold.
pub(crate) const MAX_AXIS_CELLS: u32 = 1 << 21;

/// Spreads the low 21 bits of `x` so that bit `b` lands on bit `3b`
/// (the "magic bits" method; pbrt-v4 `LeftShift3`).
#[inline]
#[must_use]
pub(crate) fn spread3(x: u32) -> u64 {
    let mut v = u64::from(x) & 0x1f_ffff;
    v = (v | (v << 32)) & 0x001f_0000_0000_ffff;
    v = (v | (v << 16)) & 0x001f_0000_ff00_00ff;
    v = (v | (v << 8)) & 0x100f_00f0_0f00_f00f;
    v = (v | (v << 4)) & 0x10c3_0c30_c30c_30c3;
    v = (v | (v << 2)) & 0x1249_2492_4924_9249;
    v
}

/// Undoes [`spread3`]: gathers bits `0, 3, 6, …` into the low 21 bits.
#[inline]
#[must_use]
pub(crate) fn compact3(v: u64) -> u32 {
    let mut v = v & 0x1249_2492_4924_9249;
    v = (v ^ (v >> 2)) & 0x10c3_0c30_c30c_30c3;
    v = (v ^ (v >> 4)) & 0x100f_00f0_0f00_f00f;
    v = (v ^ (v >> 8)) & 0x001f_0000_ff00_00ff;
    v = (v ^ (v >> 16)) & 0x001f_0000_0000_ffff;
    v = (v ^ (v >> 32)) & 0x1f_ffff;
    v as u32
}

/// The Morton code of cell `(x, y, z)`; each index must be below 2^21.
#[inline]
#[must_use]
pub(crate) fn encode3(x: u32, y: u32, z: u32) -> u64 {
    debug_assert!(x < MAX_AXIS_CELLS && y < MAX_AXIS_CELLS && z < MAX_AXIS_CELLS);
    spread3(x) | (spread3(y) << 1) | (spread3(z) << 2)
}

/// The cell `(x, y, z)` of a Morton code.
#[inline]
#[must_use]
pub(crate) fn decode3(m: u64) -> [u32; 3] {
    [compact3(m), compact3(m >> 1), compact3(m >> 2)]
}

/// The code of the neighbour one cell further along `axis` (`+1`, or `−1`
/// when `negative`), without decoding: the bits of the other axes are held
/// fixed while the axis' own bits are incremented through the gaps
/// (Raman & Wise 2008, "Converting to and from dilated integers").
#[inline]
#[must_use]
pub(crate) fn step(m: u64, axis: usize, negative: bool) -> u64 {
    let mask = AXIS_MASK[axis];
    let moved = if negative {
        (m & mask).wrapping_sub(1)
    } else {
        (m | !mask).wrapping_add(1)
    };
    (moved & mask) | (m & !mask)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn lecture_example() {
        // The lecture's example: (5, 2, 1) interleaves to 000001010101 = 85.
        assert_eq!(encode3(5, 2, 1), 85);
        assert_eq!(decode3(85), [5, 2, 1]);
    }

    proptest! {
        #[test]
        fn decode_undoes_encode(x in 0u32..1 << 21, y in 0u32..1 << 21, z in 0u32..1 << 21) {
            prop_assert_eq!(decode3(encode3(x, y, z)), [x, y, z]);
        }

        #[test]
        fn step_matches_reencoding(x in 1u32..(1 << 21) - 1, y in 1u32..(1 << 21) - 1, z in 1u32..(1 << 21) - 1, axis in 0usize..3) {
            let m = encode3(x, y, z);
            let mut up = [x, y, z];
            up[axis] += 1;
            let mut down = [x, y, z];
            down[axis] -= 1;
            prop_assert_eq!(step(m, axis, false), encode3(up[0], up[1], up[2]));
            prop_assert_eq!(step(m, axis, true), encode3(down[0], down[1], down[2]));
        }
    }
}
