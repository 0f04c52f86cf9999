//! How the walk finds a cell's references: the dense table (also of the
//! nested grids) and the hashed one.

use super::bit;
use crate::dda::CellLookup;
use crate::hash_table::CellTable;
use crate::morton;
use crate::nested::Sub;

pub(super) struct DenseLookup<'a> {
    occ: &'a [u64],
    offsets: &'a [u32],
    refs: &'a [u32],
    nx: u64,
    nxy: u64,
}

impl<'a> DenseLookup<'a> {
    /// The lookup of a dense table over cells `dims`.
    pub(super) fn new(dims: [u32; 3], occ: &'a [u64], offsets: &'a [u32], refs: &'a [u32]) -> Self {
        let [nx, ny, _] = dims.map(u64::from);
        Self {
            occ,
            offsets,
            refs,
            nx,
            nxy: nx * ny,
        }
    }
}

/// Bytes of a nested grid's table, and of its references, that
/// [`Sub::prefetch`] asks for: four cache lines.
const PREFETCH_BYTES: usize = 4 * crate::mem::LINE_BYTES;

impl Sub {
    /// Asks for the start of the arrays a walk of this nested grid reads
    /// (its planes, occupancy bits, table and references), once a ray is
    /// known to enter its box ([`crate::dda::Dda::new_then`]) and before
    /// the walk's set-up, which needs the planes, then the bits, then the
    /// table, each found only when the one before has arrived: for a ray
    /// whose nested grid is not in the cache (one bouncing off a large
    /// mesh), those misses overlap instead of following one another.
    #[inline(always)]
    pub(super) fn prefetch(&self) {
        use crate::mem::{prefetch_head, LINE_BYTES};
        for a in 0..3 {
            prefetch_head(&self.geom.planes[a], LINE_BYTES);
            prefetch_head(&self.geom.walk[a], LINE_BYTES);
        }
        prefetch_head(&self.occ, LINE_BYTES);
        // A nested grid's table is short: its first lines, and the
        // references' first.
        prefetch_head(&self.offsets, PREFETCH_BYTES);
        prefetch_head(&self.refs, PREFETCH_BYTES);
    }

    /// The lookup of a nested grid's dense table.
    pub(super) fn lookup(&self) -> DenseLookup<'_> {
        DenseLookup::new(self.geom.dims, &self.occ, &self.offsets, &self.refs)
    }
}

impl<'a> CellLookup<'a> for DenseLookup<'a> {
    #[inline(always)]
    fn start(&self, idx: [u32; 3], neg: [bool; 3]) -> (u64, [u64; 3]) {
        let key = u64::from(idx[0]) + self.nx * u64::from(idx[1]) + self.nxy * u64::from(idx[2]);
        let s = [1, self.nx, self.nxy];
        (
            key,
            std::array::from_fn(|a| if neg[a] { s[a].wrapping_neg() } else { s[a] }),
        )
    }
    #[inline(always)]
    fn step(st: &[u64; 3], key: u64, axis: usize) -> u64 {
        key.wrapping_add(st[axis])
    }
    #[inline(always)]
    fn occupied(&self, key: u64) -> bool {
        bit(self.occ, key)
    }
    #[inline(always)]
    fn refs(&self, key: u64) -> &'a [u32] {
        let k = key as usize;
        debug_assert!(k + 1 < self.offsets.len());
        // SAFETY: the walk only produces keys of cells inside the grid, and
        // `offsets` has one entry per cell plus one; the offsets are
        // nondecreasing and end at `refs.len()` (checked by `check_invariants`).
        unsafe {
            let s = *self.offsets.get_unchecked(k) as usize;
            let e = *self.offsets.get_unchecked(k + 1) as usize;
            self.refs.get_unchecked(s..e)
        }
    }
}

pub(super) struct HashedLookup<'a> {
    pub(super) occ: &'a [u64],
    pub(super) table: &'a CellTable,
    pub(super) refs: &'a [u32],
    pub(super) spread: [&'a [u64]; 3],
}

impl<'a> CellLookup<'a> for HashedLookup<'a> {
    #[inline(always)]
    fn start(&self, idx: [u32; 3], neg: [bool; 3]) -> (u64, [u64; 3]) {
        let key = self.spread[0][idx[0] as usize]
            | self.spread[1][idx[1] as usize]
            | self.spread[2][idx[2] as usize];
        (key, neg.map(u64::from))
    }
    #[inline(always)]
    fn step(st: &[u64; 3], key: u64, axis: usize) -> u64 {
        morton::step(key, axis, st[axis] != 0)
    }
    #[inline(always)]
    fn occupied(&self, key: u64) -> bool {
        bit(self.occ, key)
    }
    #[inline(always)]
    fn refs(&self, key: u64) -> &'a [u32] {
        let (s, len) = self.table.get(key);
        let (s, e) = (s as usize, s as usize + len as usize);
        debug_assert!(e <= self.refs.len());
        // SAFETY: every run stored in the table lies within `refs`
        // (checked by `check_invariants`); empty cells give (0, 0).
        unsafe { self.refs.get_unchecked(s..e) }
    }
}
