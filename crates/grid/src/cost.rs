//! The cost model behind [`crate::GridConfig::auto`]: whether a cell's
//! nested grid is expected to make the rays that cross the cell cheaper.
//!
//! The surface-area argument of the SAH (MacDonald & Booth 1990), as Ize,
//! Shirley & Parker (2007) and Kalojanov, Billeter & Slusallek (2011) apply
//! it to grids: a random ray that crosses a convex box `A` crosses a convex
//! box `B ⊂ A` with probability `SA(B) / SA(A)`. So a ray crossing a cell of
//! `n` references costs, in primitive tests,
//!
//! - flat: `n` (every reference is tested), or, where the flat cell would
//!   keep group boxes ([`crate::groups`]), `BLOCK · ⌈n / 16⌉ + Σ_g |g| ·
//!   SA(g) / SA(A)` over its groups `g` of four (every block of four group
//!   boxes is tested, and a group's references where its box is met);
//! - nested: `ENTER + d + p · (STEP · E_cells + E_tests)`, where `d` counts
//!   the references tested directly on entry (a wall, a floor), `p` is
//!   `SA(nested box) / SA(cell)`, `E_cells = Σ_c SA(c) / SA(box)` the nested
//!   cells a ray crossing the nested box visits on average, and
//!   `E_tests = Σ_c n_c · SA(c) / SA(box)` the references it tests in them.
//!
//! Both sides leave out that a ray stops at its first hit, which favours
//! the nested grid (its walk stops early, the flat cell tests everything):
//! the estimate leans to the flat cell. The cell is nested only when the
//! nested cost is at most [`COST_MARGIN`] of the flat one.

use crate::geom::{self, Geom};
use gridrt_bbox::Aabb;

/// What entering a nested grid costs, in primitive tests: finding it,
/// the slab test on its box and the walk's set-up (the grid, its planes,
/// offsets, occupancy bits and references lie in separate allocations).
/// Fitted with [`COST_BLOCK`] on the scene corpus (`cargo xtask scenes`):
/// the dragon, whose crowded cells hold some 40 to 350 triangles of one
/// sheet that their group boxes already sort out, traces as fast flat and
/// in less memory; the 1,024,000-triangle mesh, whose crowded cells hold
/// 150 to 1,100 triangles of several spheres, traces 1.5× faster with
/// them nested; see the crate README.
pub const COST_ENTER: f64 = 10.0;

/// What one step of a nested walk costs, in primitive tests (a plane
/// crossing, an occupancy bit, an offset, and the misses they bring).
pub const COST_STEP: f64 = 3.0;

/// What testing one block of four group boxes costs, in primitive tests:
/// its 24 bytes decoded into four boxes, slab-tested in lanes, and the
/// loop over the groups met. Fitted with [`COST_ENTER`]: a cost of one
/// leaves every cell of the mesh flat, which then traces at 0.64× the
/// speed.
pub const COST_BLOCK: f64 = 3.0;

/// A cell is nested only when the estimate says the nested grid costs at
/// most this fraction of the flat cell: the estimate is rough, and a
/// nested grid that saves little costs memory (about three references per
/// reference of the cell) and build time.
pub const COST_MARGIN: f64 = 0.75;

/// The fewest references of a cell that the build plans a nested grid
/// for. A cell of fewer, tested by its group boxes, seldom pays for
/// one by the estimate, and planning each would lengthen the build;
/// the top grid's sizing counts cells of this many as crowded
/// ([`crate::cluster`]).
#[must_use]
pub fn min_refs() -> u32 {
    54
}

/// The expected cost, in primitive tests, of a ray crossing cell box
/// `cell` when it holds a nested grid `g` of `refs` references in all and
/// `direct` references tested on entry.
pub(crate) fn nested(cell: &Aabb, g: &Geom, refs: u64, direct: usize) -> f64 {
    let e = g.bounds.extent();
    let [ex, ey, ez] = [e.x, e.y, e.z].map(geom::wide);
    let [nx, ny, nz] = g.dims.map(f64::from);
    let faces = ex * ey + ey * ez + ez * ex;
    // The share of the box's area that one nested cell has: a ray crossing
    // the box crosses a given nested cell with this probability.
    let share = if faces > 0.0 {
        (ex * ey / (nx * ny) + ey * ez / (ny * nz) + ez * ex / (nz * nx)) / faces
    } else {
        1.0
    };
    let cells = share * nx * ny * nz;
    let tests = share * refs as f64;
    let outer = geom::wide(cell.surface_area());
    let p = if outer > 0.0 {
        (2.0 * faces / outer).min(1.0)
    } else {
        1.0
    };
    COST_ENTER + direct as f64 + p * (COST_STEP * cells + tests)
}

/// The expected cost, in primitive tests, of a ray crossing cell box
/// `cell` that tests its references by group boxes: `groups` gives each
/// group's box (clipped to the cell) and its number of references.
pub(crate) fn grouped(cell: &Aabb, groups: impl Iterator<Item = (Aabb, usize)>) -> f64 {
    let outer = geom::wide(cell.surface_area());
    let (mut refs, mut tests) = (0usize, 0.0);
    for (b, n) in groups {
        refs += n;
        tests += if outer > 0.0 {
            n as f64 * (geom::wide(b.surface_area()) / outer).min(1.0)
        } else {
            n as f64
        };
    }
    COST_BLOCK * refs.div_ceil(16) as f64 + tests
}

/// Whether a nested grid of expected cost `nested` pays over the flat
/// cell's expected cost `flat`.
pub(crate) fn pays(flat: f64, nested: f64) -> bool {
    nested <= COST_MARGIN * flat
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_bbox::Vec3;

    #[test]
    fn a_cube_of_n_cells_per_axis_is_crossed_through_n_cells() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let g = Geom::new(b, [4, 4, 4]);
        // 64 references, one per nested cell: a ray crosses 4 cells and
        // tests 4 references; the nested box fills the cell (p = 1).
        let est = nested(&b, &g, 64, 0);
        assert!(
            (est - (COST_ENTER + 4.0 * COST_STEP + 4.0)).abs() < 1e-9,
            "{est}"
        );
        // A nested box of a quarter of the cell's area is crossed by a
        // quarter of the rays that cross the cell.
        let small = Geom::new(Aabb::new(Vec3::ZERO, Vec3::splat(0.5)), [4, 4, 4]);
        let est = nested(&b, &small, 64, 3);
        let want = COST_ENTER + 3.0 + 0.25 * (4.0 * COST_STEP + 4.0);
        assert!((est - want).abs() < 1e-9, "{est}");
    }

    #[test]
    fn a_flat_nested_grid_is_crossed_through_one_cell() {
        let cell = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let g = Geom::new(Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)), [8, 8, 1]);
        let est = nested(&cell, &g, 64, 0);
        // Half of the cell's area (two faces of six), one cell, one reference.
        let want = COST_ENTER + (2.0 / 6.0) * (COST_STEP + 1.0);
        assert!((est - want).abs() < 1e-6, "{est}");
    }

    #[test]
    fn grouped_cells_cost_their_blocks_and_the_groups_a_ray_meets() {
        let cell = Aabb::new(Vec3::ZERO, Vec3::ONE);
        // 32 references in 8 groups that fill the cell: every group is met.
        let est = grouped(&cell, (0..8).map(|_| (cell, 4)));
        assert!((est - (2.0 * COST_BLOCK + 32.0)).abs() < 1e-9, "{est}");
        // Groups of a quarter of the cell's area, by a quarter of the rays.
        let quarter = Aabb::new(Vec3::ZERO, Vec3::splat(0.5));
        let est = grouped(&cell, (0..8).map(|_| (quarter, 4)));
        assert!((est - (2.0 * COST_BLOCK + 8.0)).abs() < 1e-9, "{est}");
        // A last group of two is one block still.
        let est = grouped(&cell, [(cell, 4), (cell, 2)].into_iter());
        assert!((est - (COST_BLOCK + 6.0)).abs() < 1e-9, "{est}");
    }

    #[test]
    fn group_boxes_that_sort_a_cell_out_leave_it_flat() {
        let cell = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let est = nested(&cell, &Geom::new(cell, [4, 4, 4]), 64, 0);
        // Tested one by one, 64 references cost more than the nested grid ...
        assert!(pays(64.0, est));
        // ... but not when their 16 groups are small boxes a ray seldom meets.
        let tiny = Aabb::new(Vec3::ZERO, Vec3::splat(0.01));
        let flat = grouped(&cell, (0..16).map(|_| (tiny, 4)));
        assert!(!pays(flat, est), "{flat} {est}");
    }
}
