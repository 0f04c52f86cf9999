//! Morton (Z-order) helpers the grid needs on top of `gridrt-morton`'s
//! encoding: the per-axis bit masks and stepping a code by one cell along
//! one axis without decoding it.
//!
//! Codes follow `gridrt-morton`'s convention: 21 bits per axis, x in the
//! lowest bit, then y, then z (`… z1 y1 x1 z0 y0 x0`).

/// The bits of a Morton code that belong to each axis (x, y, z), 21 bits each.
pub(crate) const AXIS_MASK: [u64; 3] = [
    0x1249_2492_4924_9249,
    0x1249_2492_4924_9249 << 1,
    0x1249_2492_4924_9249 << 2,
];

/// The largest cell index per axis that a 63-bit Morton code can hold.
pub(crate) const MAX_AXIS_CELLS: u32 = 1 << 21;

/// The Morton code of cell `(x, y, z)` (each index below 2^21), from `gridrt-morton`.
#[inline]
#[must_use]
pub(crate) fn encode3(x: u32, y: u32, z: u32) -> u64 {
    debug_assert!(x < MAX_AXIS_CELLS && y < MAX_AXIS_CELLS && z < MAX_AXIS_CELLS);
    gridrt_morton::encode3(x, y, z)
}

/// The cell `(x, y, z)` of a Morton code, from `gridrt-morton`.
#[inline]
#[must_use]
pub(crate) fn decode3(m: u64) -> [u32; 3] {
    let (x, y, z) = gridrt_morton::decode3(m);
    [x, y, z]
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
