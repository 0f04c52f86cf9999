//! Serialisation helpers for types that live in crates without serde.

use gridrt_grid::GridStats;
use serde::{Serialize, Serializer};
use std::time::Duration;

/// A duration as seconds (`f64`).
pub(crate) fn duration_secs<S: Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

/// The fields of [`GridStats`], with the build time in seconds.
#[derive(Serialize)]
struct GridStatsSer {
    dims: [u32; 3],
    cells: u64,
    occupied_cells: u64,
    references: u64,
    mean_refs_per_occupied: f64,
    max_refs_per_cell: u32,
    bytes: usize,
    table_bytes: usize,
    unbounded_prims: u64,
    nested_cells: u64,
    build_time: f64,
}

/// `Option<GridStats>` as an object of its fields, or `null`.
pub(crate) fn grid_stats<S: Serializer>(g: &Option<GridStats>, s: S) -> Result<S::Ok, S::Error> {
    g.as_ref()
        .map(|g| GridStatsSer {
            dims: g.dims,
            cells: g.cells,
            occupied_cells: g.occupied_cells,
            references: g.references,
            mean_refs_per_occupied: g.mean_refs_per_occupied,
            max_refs_per_cell: g.max_refs_per_cell,
            bytes: g.bytes,
            table_bytes: g.table_bytes,
            unbounded_prims: g.unbounded_prims,
            nested_cells: g.nested_cells,
            build_time: g.build_time.as_secs_f64(),
        })
        .serialize(s)
}
