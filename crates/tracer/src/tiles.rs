//! The tiles a render is cut into, and the order they are rendered in.

/// Side of a square tile, in pixels.
pub(crate) const TILE: u32 = 16;

/// Columns `x0..x1` of the listed rows `k0..k1` (indices into a render's
/// list of rows).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Tile {
    pub(crate) x0: u32,
    pub(crate) x1: u32,
    pub(crate) k0: usize,
    pub(crate) k1: usize,
}

/// Tiles of up to `TILE` columns of `cols` by `TILE` of `rows` listed rows,
/// spread over the image in bit-reversed order (van der Corput), so that at
/// any moment the tiles done sample the whole frame: the share of pixels
/// done then tracks the share of the work done, and a progress estimate
/// converges instead of running short while the cheap tiles go first. No
/// pixel depends on the order.
pub(crate) fn tiles(rows: usize, cols: (u32, u32)) -> Vec<Tile> {
    let mut tiles = Vec::new();
    let (c0, c1) = cols;
    for k0 in (0..rows).step_by(TILE as usize) {
        for x0 in (c0..c1).step_by(TILE as usize) {
            tiles.push(Tile {
                x0,
                x1: (x0 + TILE).min(c1),
                k0,
                k1: (k0 + TILE as usize).min(rows),
            });
        }
    }
    let bits = usize::BITS - tiles.len().saturating_sub(1).leading_zeros();
    let key = |i: usize| {
        if bits == 0 {
            0
        } else {
            i.reverse_bits() >> (usize::BITS - bits)
        }
    };
    let mut order: Vec<usize> = (0..tiles.len()).collect();
    order.sort_by_key(|&i| key(i));
    order.into_iter().map(|i| tiles[i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_every_pixel_once() {
        for (rows, cols) in [(0, (0, 0)), (1, (0, 1)), (37, (5, 70)), (64, (0, 64))] {
            let ts = tiles(rows, cols);
            let mut seen = vec![0u8; rows * (cols.1 - cols.0) as usize];
            for t in &ts {
                assert!(t.x1 - t.x0 <= TILE && t.k1 - t.k0 <= TILE as usize);
                for k in t.k0..t.k1 {
                    for x in t.x0..t.x1 {
                        seen[k * (cols.1 - cols.0) as usize + (x - cols.0) as usize] += 1;
                    }
                }
            }
            assert!(
                seen.iter().all(|&n| n == 1),
                "{rows} rows, columns {cols:?}"
            );
        }
        // Bit-reversed: the second tile is half way through the list.
        let ts = tiles(64, (0, 64));
        assert_eq!((ts[0].k0, ts[1].k0), (0, 32));
    }
}
