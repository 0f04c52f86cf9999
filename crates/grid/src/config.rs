use gridrt_bbox::Real;
use std::time::Duration;

/// How the grid stores its cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CellStorage {
    /// Only occupied cells get space: a hash table keyed by the Morton code of
    /// the cell's (i, j, k), as the lecture asks.
    #[default]
    Hashed,
    /// One offset per cell, occupied or not.
    Dense,
}

/// Parameters of a grid build.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridConfig {
    /// The lecture's multiplier `m`: about `m³` cells per primitive.
    pub m: Real,
    /// Sparse hashed cells or a dense table.
    pub storage: CellStorage,
    /// Ask each primitive whether it really touches a cell
    /// ([`crate::Primitive::overlaps_box`]) instead of inserting it into every
    /// cell its bounding box overlaps.
    pub exact_insertion: bool,
    /// Skip primitives already tested by the same ray (mailboxing).
    pub mailbox: bool,
    /// The most cells a grid may have; the resolution is scaled down
    /// uniformly to stay below it, so memory stays bounded.
    pub max_cells: u64,
}

/// What a built grid looks like, for reports and tests.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridStats {
    /// Cells per axis.
    pub dims: [u32; 3],
    /// `dims[0]·dims[1]·dims[2]`.
    pub cells: u64,
    /// Cells holding at least one reference.
    pub occupied_cells: u64,
    /// Primitive references over all cells.
    pub references: u64,
    /// `references / occupied_cells` (0 for an empty grid).
    pub mean_refs_per_occupied: f64,
    /// The most references in one cell.
    pub max_refs_per_cell: u32,
    /// Heap bytes held by the grid's tables (not the primitives).
    pub bytes: usize,
    /// Wall-clock time of the build.
    pub build_time: Duration,
}

impl Default for GridConfig {
    fn default() -> Self {
        Self {
            m: 2.0,
            storage: CellStorage::Hashed,
            exact_insertion: false,
            mailbox: true,
            max_cells: 1 << 26,
        }
    }
}
