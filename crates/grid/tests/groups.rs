//! Crowded cells tested by groups of four references with a box each
//! (`GridConfig::cell_groups`): the same answers as exhaustive, bit for
//! bit, on a tessellated surface at the origin and far from it, with and
//! without the mailbox, in dense and hashed cells; fewer tests per ray.

use crate::support::prims::Triangle;
use crate::support::scenes::{wavy_sheet, Lcg};
use crate::support::Checker;
use gridrt_grid::{Accelerator, CellStorage, Grid, GridConfig, QueryCounters, Ray, Real, Vec3};

/// Rays from above the sheet at its vertices and across it, some leaving
/// it from points on it (as secondary rays do), some grazing it.
fn rays(at: Vec3, size: Real, n: usize) -> Vec<Ray> {
    let mut rng = Lcg::new(7);
    (0..n)
        .map(|k| {
            let on = at + Vec3::new(rng.range(0.0, 1.0), 0.0, rng.range(0.0, 1.0)) * size;
            let d = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            match k % 3 {
                0 => Ray::new(
                    on + Vec3::new(0.1, 0.6, 0.2) * size,
                    on - (on + Vec3::new(0.1, 0.6, 0.2) * size),
                ),
                1 => Ray::new(on, d),
                _ => Ray::new(
                    on - Vec3::new(d.x, 0.0, d.z) * size,
                    Vec3::new(d.x, 0.001, d.z),
                ),
            }
        })
        .collect()
}

/// The flat grid of `prims` with multiplier `m`, with or without group
/// boxes, in `memory_budget` bytes (`None`: the default budget).
fn flat_grid(
    prims: &[Triangle],
    m: Real,
    cell_groups: bool,
    memory_budget: Option<usize>,
) -> Grid<Triangle> {
    let config = GridConfig {
        m,
        auto: false,
        cell_groups,
        memory_budget,
        ..GridConfig::default()
    };
    Grid::build(prims.to_vec(), &config)
}

fn configs() -> Vec<GridConfig> {
    let mut v = Vec::new();
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        for mailbox in [false, true] {
            for m in [0.3, 0.75] {
                v.push(GridConfig {
                    storage,
                    mailbox,
                    m,
                    auto: false,
                    ..GridConfig::default()
                });
            }
        }
    }
    v
}

#[test]
fn grouped_cells_answer_as_exhaustive_at_every_offset() {
    for offset in [0.0, 1e3, 1e5] {
        let at = Vec3::new(offset, -offset * 0.5, offset * 0.25);
        let sheet = wavy_sheet(40, at, 1.0);
        let checker = Checker::new(sheet, &configs());
        for g in &checker.grids {
            assert!(g.stats().grouped_cells > 0, "no groups: {:?}", g.stats());
        }
        for ray in rays(at, 1.0, 1500) {
            checker.check(&ray, 0.0, Real::INFINITY);
            checker.check(&ray, 0.0, 0.7);
        }
    }
}

#[test]
fn groups_cut_the_tests_per_ray_and_stay_in_the_budget() {
    let sheet = wavy_sheet(60, Vec3::ZERO, 1.0);
    let build = |cell_groups, memory_budget| flat_grid(&sheet, 0.3, cell_groups, memory_budget);
    let tests = |g: &Grid<Triangle>| {
        let mut c = QueryCounters::default();
        let mut s = g.scratch();
        for ray in rays(Vec3::ZERO, 1.0, 3000) {
            g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut s, &mut c);
        }
        c.tests
    };
    let (with, without) = (build(true, None), build(false, None));
    assert_eq!(without.stats().grouped_cells, 0);
    assert!(with.stats().grouped_cells > 0);
    assert!(with.stats().bytes > without.stats().bytes);
    let (tw, tn) = (tests(&with), tests(&without));
    assert!(2 * tw < tn, "with groups {tw} tests, without {tn}");
}

#[test]
fn groups_stay_in_the_memory_budget() {
    // Long slivers across a cube: many references a primitive, so that the
    // grid outgrows the floor of the budget (16 bytes a primitive).
    let mut rng = Lcg::new(3);
    let mut point = || {
        Vec3::new(
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
        )
    };
    let slivers: Vec<Triangle> = (0..600)
        .map(|_| {
            let (a, b) = (point(), point());
            Triangle::new(a, b, b + Vec3::splat(1e-3))
        })
        .collect();
    let build = |cell_groups, memory_budget| flat_grid(&slivers, 0.5, cell_groups, memory_budget);
    let with = build(true, None);
    assert!(with.stats().grouped_cells > 0);
    // Budgets short of the grid with groups: the build keeps to each,
    // dropping the groups, the distance map or cells.
    let floor = 16 * slivers.len() + 4096;
    assert!(with.stats().bytes > floor + 1000);
    for budget in (floor..with.stats().bytes).step_by(997) {
        let tight = build(true, Some(budget));
        assert_eq!(tight.stats().budget, budget);
        assert!(
            tight.stats().bytes <= budget,
            "{} > {budget}",
            tight.stats().bytes
        );
    }
}
