//! Randomly generated closed meshes, placed at random scales and offsets,
//! probed by rays from inside through every vertex and along every edge:
//! no ray leaks, and the grid (with and without mailboxing, flat or
//! nested) returns exactly the exhaustive baseline's hit.

use gridrt_grid::{Accelerator, Exhaustive, Grid, GridConfig, Hit, Ray, Real};
use gridrt_tracer::hard_meshes::{random_star, ClosedMesh, DirLength};
use proptest::prelude::*;

/// Whether the mesh keeps its shape at this placement: its smallest
/// vertex distance from the centre (`r_min · scale`) spans 2¹² ulps of the
/// offset. Below that the centre may round onto the surface.
fn resolved(scale: f64, offset: f64, r_min: f64) -> bool {
    scale * r_min >= offset * f64::from(Real::EPSILON) * 4096.0
}

fn closest<A: Accelerator>(a: &A, r: &Ray, s: &mut A::Scratch) -> Option<Hit> {
    a.closest_hit(r, 0.0, Real::INFINITY, s)
}

/// Leaks and grid/exhaustive mismatches of one placement, as a report
/// line (empty when there are none).
#[allow(clippy::let_unit_value)] // the exhaustive accelerator's scratch is `()`
fn probe(mesh: &ClosedMesh, scale: f64, offset: f64) -> String {
    let tris = mesh.triangles(scale, offset);
    let ex = Exhaustive::new(tris.clone());
    let grids = [
        GridConfig::default(),
        GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
        GridConfig {
            nest_min_refs: 4,
            m: 0.3,
            mailbox: true,
            ..GridConfig::default()
        },
    ]
    .map(|c| Grid::build(tris.clone(), &c));
    let mut se = ex.scratch();
    let mut report = String::new();
    for len in [DirLength::Unit, DirLength::Short, DirLength::ToTarget] {
        let rays = mesh.probe_rays(scale, offset, len);
        let (mut leaks, mut mismatches) = (0, 0);
        for r in &rays {
            let want = closest(&ex, r, &mut se);
            leaks += usize::from(want.is_none());
            for g in &grids {
                mismatches += usize::from(closest(g, r, &mut g.scratch()) != want);
            }
        }
        if leaks + mismatches > 0 {
            report += &format!(
                "{} scale {scale:e} offset {offset:e} {len:?}: {leaks} leaks, \
                 {mismatches} mismatches of {} rays\n",
                mesh.name,
                rays.len()
            );
        }
    }
    report
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Any random star, at a scale from 10⁻⁸ to 10⁸ and an offset up to
    /// 10⁶ (where the precision resolves it), is watertight.
    #[test]
    fn random_closed_meshes_never_leak(
        seed in any::<u64>(),
        splits in 0u32..120,
        r_min in prop_oneof![Just(1.0), Just(0.9), 0.05f64..1.0],
        scale_exp in -8.0f64..8.0,
        offset in prop_oneof![Just(0.0), -1e6f64..1e6, Just(1e5), Just(-1e3)],
    ) {
        let scale = 10f64.powf(scale_exp);
        prop_assume!(resolved(scale, offset.abs(), r_min));
        let mesh = random_star(seed, splits, r_min);
        let report = probe(&mesh, scale, offset);
        prop_assert!(report.is_empty(), "{}", report);
    }
}

/// A fixed spread of placements of dense random stars, so the largest
/// meshes (hundreds of slivers) are always probed, not left to chance.
#[test]
fn dense_random_stars_at_extreme_placements_never_leak() {
    let mut report = String::new();
    for seed in 0..2u64 {
        let mesh = random_star(seed, 200, 0.2);
        for (scale, offset) in [
            (1e-8, 0.0),
            (1.0, 0.0),
            (1e8, 0.0),
            (3e-3, 1e3),
            (1.0, 1e5),
            (7.0, 1e6),
            (1e8, -1e6),
        ] {
            if resolved(scale, offset, 0.2) {
                report += &probe(&mesh, scale, offset);
            }
        }
    }
    assert!(report.is_empty(), "{report}");
}
