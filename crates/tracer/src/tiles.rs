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

/// Tiles of up to `TILE` columns of `cols` by `TILE` of `rows` listed rows.
/// The bands of `TILE` rows come in bit-reversed order (van der Corput), so
/// that at any moment the bands done sample the whole frame: the share of
/// pixels done then tracks the share of the work done, and a progress
/// estimate converges instead of running short while the cheap bands go
/// first. Inside a band the tiles go left to right, so that each tile finds
/// in the cache the cells and primitives its left neighbour's rays brought
/// in: neighbouring rays cross the same cells, and a scene larger than the
/// cache pays for every cell it reloads. No pixel depends on the order.
pub(crate) fn tiles(rows: usize, cols: (u32, u32)) -> Vec<Tile> {
    let (c0, c1) = cols;
    let bands = rows.div_ceil(TILE as usize);
    let bits = usize::BITS - bands.saturating_sub(1).leading_zeros();
    let mut order: Vec<usize> = (0..bands).collect();
    order.sort_by_key(|&b| {
        b.reverse_bits()
            .checked_shr(usize::BITS - bits)
            .unwrap_or(0)
    });
    let mut tiles = Vec::new();
    for band in order {
        let k0 = band * TILE as usize;
        for x0 in (c0..c1).step_by(TILE as usize) {
            tiles.push(Tile {
                x0,
                x1: (x0 + TILE).min(c1),
                k0,
                k1: (k0 + TILE as usize).min(rows),
            });
        }
    }
    tiles
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
        // Bands in bit-reversed order, each left to right: the second band
        // is half way down the rows.
        let ts = tiles(64, (0, 64));
        let starts: Vec<_> = ts.iter().map(|t| (t.k0, t.x0)).collect();
        assert_eq!(&starts[..5], &[(0, 0), (0, 16), (0, 32), (0, 48), (32, 0)]);
        assert_eq!(&starts[8..9], &[(16, 0)]);
    }
}
