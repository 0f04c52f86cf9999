//! How far each empty cell of a dense grid is from the nearest occupied
//! one: a chessboard distance map (the "proximity clouds" of Cohen &
//! Sheffer 1994), so that a walk in an empty stretch of a sparse grid
//! leaves a whole cube of empty cells in one step instead of looking up
//! every cell in it ([`crate::dda::Dda::walk_far`]).
//!
//! `far[c]` is 0 for an occupied cell; for an empty one, the smallest
//! `max(|Δi|, |Δj|, |Δk|)` to an occupied cell (255 when none is closer):
//! every cell within `far[c] − 1` of `c` along each axis is empty.
//!
//! The map is the exact distance transform of the occupancy under the
//! chessboard metric, by two raster passes over the 26 neighbours (Rosenfeld
//! & Pfaltz 1966; Borgefors 1984 in 3D): a shortest path of king moves
//! between two cells can be ordered so that its steps forward in raster
//! order come first and those backward come last, and the forward pass
//! finds the first part, the backward pass the second. Every value is the
//! length of a path of king moves, never shorter than the distance, and the
//! passes find a shortest one, so the map is exact (a property test checks
//! it against the definition). An overestimate would let a walk skip an
//! occupied cell; an underestimate would only skip less.

/// The largest distance stored; farther cells keep it.
const FAR: u8 = u8::MAX;

/// Grids with more cells get no map: its two passes would cost more build
/// time than the walk saves.
pub(crate) const MAX_CELLS: usize = 1 << 23;

/// The chessboard distance map of a dense grid of `dims` cells whose cell
/// `c` (row-major) is occupied when `occupied(c)`.
pub(crate) fn far_map(dims: [u32; 3], occupied: impl Fn(usize) -> bool) -> Box<[u8]> {
    let [nx, ny, nz] = dims.map(|d| d as usize);
    // Worked on with a border of one cell that stays `FAR`, so that every
    // cell has all 26 neighbours and the passes test no bounds.
    let [px, py] = [nx + 2, ny + 2];
    let at = |i: usize, j: usize, k: usize| (i + 1) + (j + 1) * px + (k + 1) * px * py;
    let mut far = vec![FAR; px * py * (nz + 2)];
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if occupied(i + nx * (j + ny * k)) {
                    far[at(i, j, k)] = 0;
                }
            }
        }
    }
    pass(&mut far, [nx, ny, nz], false);
    pass(&mut far, [nx, ny, nz], true);
    let mut out = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            out.extend_from_slice(&far[at(0, j, k)..at(0, j, k) + nx]);
        }
    }
    out.into_boxed_slice()
}

/// One raster pass over the bordered map `far` of a grid of `dims`
/// cells: forward (layers, rows and cells in increasing order), each cell
/// lowered to one more than the least of its 13 neighbours before it (the 9
/// of the layer below, the 3 of the row below, the one on its left), or
/// backward, the same in decreasing order from the 13 after it. A row at
/// a time: the 12 neighbours in other rows are taken for the whole row at
/// once, in loops the compiler vectorises, and only the neighbour in the
/// row itself cell by cell.
fn pass(far: &mut [u8], [nx, ny, nz]: [usize; 3], back: bool) {
    let [px, py] = [nx + 2, ny + 2];
    let row = |j: usize, k: usize| (j + k * py) * px;
    // Per column of the row: the least of the four neighbouring rows, then
    // one more than the least of three neighbouring columns of that.
    let mut column = vec![FAR; px];
    let mut near = vec![FAR; px];
    for kk in 0..nz {
        let (k, kn) = if back {
            (nz - kk, nz - kk + 1)
        } else {
            (kk + 1, kk)
        };
        for jj in 0..ny {
            let (j, jn) = if back {
                (ny - jj, ny - jj + 1)
            } else {
                (jj + 1, jj)
            };
            let rows = [row(j - 1, kn), row(j, kn), row(j + 1, kn), row(jn, k)];
            let [a, b, c, d] = rows.map(|r| &far[r..r + px]);
            for ((((m, a), b), c), d) in column.iter_mut().zip(a).zip(b).zip(c).zip(d) {
                *m = (*a).min(*b).min(*c).min(*d);
            }
            let (l, mid, r) = (&column[..nx], &column[1..=nx], &column[2..]);
            for (((n, l), m), r) in near[1..=nx].iter_mut().zip(l).zip(mid).zip(r) {
                *n = (*l).min(*m).min(*r).saturating_add(1);
            }
            let cells = &mut far[row(j, k)..row(j, k) + px];
            // The border cell before the first stays `FAR`.
            let mut prev = FAR;
            let mut relax = |i: usize| {
                let d = cells[i].min(near[i]).min(prev.saturating_add(1));
                cells[i] = d;
                prev = d;
            };
            if back {
                (1..=nx).rev().for_each(&mut relax);
            } else {
                (1..=nx).for_each(&mut relax);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The distance by definition: the nearest occupied cell, capped.
    fn brute(dims: [u32; 3], occ: &[bool]) -> Vec<u8> {
        let [nx, ny, nz] = dims.map(|d| d as i64);
        let cell = |c: i64| [c % nx, c / nx % ny, c / (nx * ny)];
        (0..nx * ny * nz)
            .map(|c| {
                let p = cell(c);
                (0..nx * ny * nz)
                    .filter(|&q| occ[q as usize])
                    .map(|q| {
                        let q = cell(q);
                        (0..3).map(|a| (p[a] - q[a]).abs()).max().unwrap_or(0)
                    })
                    .min()
                    .map_or(FAR, |d| d.min(i64::from(FAR)) as u8)
            })
            .collect()
    }

    #[test]
    fn one_occupied_cell_gives_chessboard_rings() {
        // Cells (i, j, k) of a 5×4×3 grid, row-major; (1, 2, 1) occupied.
        let cell = |i: usize, j: usize, k: usize| i + 5 * (j + 4 * k);
        let far = far_map([5, 4, 3], |c| c == cell(1, 2, 1));
        assert_eq!(far[cell(1, 2, 1)], 0);
        assert_eq!(far[cell(0, 0, 0)], 2);
        assert_eq!(far[cell(4, 0, 2)], 3);
    }

    #[test]
    fn an_empty_grid_is_far_everywhere() {
        assert!(far_map([3, 3, 3], |_| false).iter().all(|&d| d == FAR));
    }

    proptest! {
        #[test]
        fn the_passes_give_the_exact_distance(
            dims in [1u32..7, 1u32..7, 1u32..7],
            seed in any::<u64>(),
            density in 0u32..40,
        ) {
            let n = dims.iter().product::<u32>() as usize;
            let mut s = seed | 1;
            let occ: Vec<bool> = (0..n)
                .map(|_| {
                    s ^= s << 13;
                    s ^= s >> 7;
                    s ^= s << 17;
                    (s % 100) < u64::from(density)
                })
                .collect();
            let far = far_map(dims, |c| occ[c]);
            prop_assert_eq!(far.to_vec(), brute(dims, &occ));
        }
    }
}
