//! Nested grids in crowded cells: a detailed object in a large empty scene
//! (the "teapot in a stadium") gets grids inside its crowded cells, and the
//! answers stay exactly the exhaustive ones.

use crate::support::prims::{Sphere, Triangle};
use crate::support::scenes::{uv_sphere_mesh, Lcg};
use crate::support::Checker;
use gridrt_grid::{Accelerator, CellStorage, Grid, GridConfig, QueryCounters, Ray, Real, Vec3};

/// Two finely tessellated balls near the origin and two small triangles at
/// the far corners of a box 200 units wide.
fn stadium() -> Vec<Triangle> {
    let balls = [
        Sphere::new(Vec3::new(0.0, 0.0, 0.0), 0.5),
        Sphere::new(Vec3::new(0.6, 0.2, -0.3), 0.25),
    ];
    let mut tris = uv_sphere_mesh(&balls, 24, 13);
    for c in [-100.0 as Real, 100.0] {
        let p = Vec3::splat(c);
        tris.push(Triangle::new(p, p + Vec3::X, p + Vec3::Y));
    }
    tris
}

/// Rays from all around aimed at points near the balls.
fn rays(n: usize) -> Vec<Ray> {
    let mut rng = Lcg::new(7);
    (0..n)
        .map(|_| {
            let from = Vec3::new(
                rng.range(-50.0, 50.0),
                rng.range(-50.0, 50.0),
                rng.range(-50.0, 50.0),
            );
            let to = Vec3::new(
                rng.range(-0.6, 0.9),
                rng.range(-0.6, 0.6),
                rng.range(-0.6, 0.6),
            );
            Ray::new(from, to - from)
        })
        .collect()
}

/// The primitive tests of 500 of [`rays`]' closest-hit queries.
fn tests(g: &Grid<Triangle>) -> u64 {
    let mut c = QueryCounters::default();
    let mut s = g.scratch();
    for ray in rays(500) {
        g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut s, &mut c);
    }
    c.tests
}

#[test]
fn crowded_cells_get_nested_grids_and_stay_exact() {
    let tris = stadium();
    let configs: Vec<GridConfig> = [CellStorage::Dense, CellStorage::Hashed]
        .into_iter()
        .flat_map(|storage| {
            [(false, None), (true, None), (false, Some(1.5))].map(|(mailbox, nest_m)| GridConfig {
                storage,
                mailbox,
                nest_min_refs: 16,
                nest_m,
                ..GridConfig::default()
            })
        })
        .collect();
    let checker = Checker::new(tris.clone(), &configs);
    for g in &checker.grids {
        assert!(
            g.stats().nested_cells > 0,
            "{:?}: no nested grid",
            g.config()
        );
    }
    let mut hits = 0;
    for ray in rays(3000) {
        hits += usize::from(checker.check(&ray, 0.0, Real::INFINITY).is_some());
        checker.check(&ray, 1.0, 60.0);
    }
    assert!(hits > 1000, "only {hits} rays hit the balls");
}

#[test]
fn nesting_cuts_the_tests_per_ray() {
    let tris = stadium();
    // Without group boxes, which also cut the flat grid's tests.
    let flat = Grid::build(
        tris.clone(),
        &GridConfig {
            auto: false,
            cell_groups: false,
            ..GridConfig::default()
        },
    );
    assert_eq!(flat.stats().nested_cells, 0);
    let nested = Grid::build(
        tris,
        &GridConfig {
            nest_min_refs: 16,
            cell_groups: false,
            ..GridConfig::default()
        },
    );
    let (f, n) = (tests(&flat), tests(&nested));
    assert!(
        n * 2 < f,
        "nested grids test {n} primitives, the flat grid {f}"
    );
}

#[test]
fn nested_grids_follow_their_own_m() {
    let tris = stadium();
    let config = |m: Real, nest_m: Option<Real>| GridConfig {
        m,
        nest_min_refs: 16,
        nest_m,
        ..GridConfig::default()
    };
    let same = Grid::build(tris.clone(), &config(0.5, None));
    let explicit = Grid::build(tris.clone(), &config(0.5, Some(0.5)));
    let finer = Grid::build(tris, &config(0.5, Some(1.5)));
    // The outer grid is the same; `None` means the outer grid's m.
    assert_eq!(same.dims(), finer.dims());
    assert_eq!(same.stats().references, finer.stats().references);
    assert_eq!(same.stats().bytes, explicit.stats().bytes);
    // Finer nested grids hold more cells, so more bytes, and a ray tests
    // fewer triangles in them.
    assert!(finer.stats().bytes > same.stats().bytes);
    let (a, b) = (tests(&same), tests(&finer));
    assert!(b < a, "nest_m 1.5 tests {b} triangles, the default {a}");
}
