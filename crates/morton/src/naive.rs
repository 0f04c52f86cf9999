//! The reference: one bit per loop iteration.
//!
//! Obviously correct and slow. It exists so that tests can check the fast
//! paths against it and benchmarks can show what the fast paths buy. Same
//! bit order and same out-of-range rule as the crate-level functions
//! ([`crate::encode3`] keeps the low 21 bits of each coordinate).
//!
//! ```
//! use gridrt_morton::naive;
//! assert_eq!(naive::encode3(5, 2, 1), 85);
//! assert_eq!(naive::decode3(85), (5, 2, 1));
//! ```

/// [`crate::encode3`], bit by bit: bit `i` of x goes to bit `3i`, of y to
/// `3i + 1`, of z to `3i + 2`, for `i < 21`.
#[inline]
#[must_use]
pub fn encode3(x: u32, y: u32, z: u32) -> u64 {
    let mut code = 0u64;
    for i in 0..21 {
        code |= u64::from(x >> i & 1) << (3 * i);
        code |= u64::from(y >> i & 1) << (3 * i + 1);
        code |= u64::from(z >> i & 1) << (3 * i + 2);
    }
    code
}

/// [`crate::decode3`], bit by bit. Bit 63 is ignored.
#[inline]
#[must_use]
pub fn decode3(code: u64) -> (u32, u32, u32) {
    let (mut x, mut y, mut z) = (0u32, 0u32, 0u32);
    for i in 0..21 {
        x |= ((code >> (3 * i) & 1) as u32) << i;
        y |= ((code >> (3 * i + 1) & 1) as u32) << i;
        z |= ((code >> (3 * i + 2) & 1) as u32) << i;
    }
    (x, y, z)
}

/// [`crate::encode2`], bit by bit: bit `i` of x goes to bit `2i`, of y to
/// `2i + 1`, for `i < 32`.
#[inline]
#[must_use]
pub fn encode2(x: u32, y: u32) -> u64 {
    let mut code = 0u64;
    for i in 0..32 {
        code |= u64::from(x >> i & 1) << (2 * i);
        code |= u64::from(y >> i & 1) << (2 * i + 1);
    }
    code
}

/// [`crate::decode2`], bit by bit.
#[inline]
#[must_use]
pub fn decode2(code: u64) -> (u32, u32) {
    let (mut x, mut y) = (0u32, 0u32);
    for i in 0..32 {
        x |= ((code >> (2 * i) & 1) as u32) << i;
        y |= ((code >> (2 * i + 1) & 1) as u32) << i;
    }
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_bits_land_where_the_lecture_says() {
        for i in 0..21 {
            assert_eq!(encode3(1 << i, 0, 0), 1 << (3 * i));
            assert_eq!(encode3(0, 1 << i, 0), 1 << (3 * i + 1));
            assert_eq!(encode3(0, 0, 1 << i), 1 << (3 * i + 2));
            assert_eq!(decode3(1 << (3 * i + 2)), (0, 0, 1 << i));
        }
        for i in 0..32 {
            assert_eq!(encode2(1 << i, 0), 1 << (2 * i));
            assert_eq!(encode2(0, 1 << i), 1 << (2 * i + 1));
            assert_eq!(decode2(1 << (2 * i + 1)), (0, 1 << i));
        }
    }

    #[test]
    fn out_of_range_bits_are_dropped() {
        assert_eq!(encode3(1 << 21, 1 << 22, u32::MAX << 21), 0);
        assert_eq!(decode3(1 << 63), (0, 0, 0));
    }
}
