//! The cell table a build produces (dense offsets or a hash table of
//! occupied cells) and the occupancy bitmap the walks skip empty cells by.

use crate::hash_table::CellTable;

/// How a built grid finds a cell's references.
#[derive(Clone, Debug)]
pub(crate) enum Cells {
    /// No cells (no primitive with a finite box).
    Empty,
    /// `offsets[c]..offsets[c + 1]` for the row-major cell index `c`.
    Dense { offsets: Box<[u32]> },
    /// Morton code → run, only for occupied cells.
    Hashed { table: CellTable },
}

impl Cells {
    /// The occupied cells of a grid with `dims` cells per axis that hold
    /// at least `min` references (none for 0): each cell's index, and
    /// where its run starts among the references and how long it is, in
    /// storage order.
    pub(crate) fn runs(&self, dims: [u32; 3], min: usize) -> Vec<([u32; 3], u32, u32)> {
        match self {
            _ if min == 0 => Vec::new(),
            Cells::Empty => Vec::new(),
            Cells::Dense { offsets } => {
                let [nx, ny, _] = dims;
                offsets
                    .windows(2)
                    .enumerate()
                    .filter(|(_, w)| (w[1] - w[0]) as usize >= min)
                    .map(|(c, w)| {
                        let c = c as u32;
                        ([c % nx, (c / nx) % ny, c / (nx * ny)], w[0], w[1] - w[0])
                    })
                    .collect()
            }
            Cells::Hashed { table } => table
                .occupied()
                .filter(|s| s.len as usize >= min)
                .map(|s| (crate::morton::decode3(s.key), s.start, s.len))
                .collect(),
        }
    }
}

/// What a cell-table build returns: the cells, the references, the Morton
/// spread tables (hashed storage), the occupied cell count and the most
/// references in one cell.
pub(crate) type CellsOut = (Cells, Box<[u32]>, [Box<[u64]>; 3], u64, u32);

/// One bit per cell of a dense table (`offsets[c]..offsets[c + 1]` are
/// cell `c`'s references): set when the cell holds references.
pub(crate) fn dense_occupancy(offsets: &[u32]) -> Box<[u64]> {
    let cells = offsets.len() - 1;
    // A word at a time, 64 comparisons of neighbouring offsets each: a
    // fixed-length loop the compiler turns into vector compares.
    let word = |w: usize| {
        let o = &offsets[w * 64..(w * 64 + 65).min(offsets.len())];
        o.windows(2)
            .enumerate()
            .fold(0u64, |bits, (b, p)| bits | u64::from(p[0] != p[1]) << b)
    };
    (0..cells.div_ceil(64)).map(word).collect()
}
