//! The hierarchy of nested grids on clustered scenes: a dense cluster in a
//! huge box, fans of triangles around one vertex, stacks of coincident
//! triangles, clusters far from the origin. Same answers as exhaustive
//! with and without mailboxing, automatic and explicit nesting, and the
//! memory budget never exceeded, whatever the settings.

use crate::support::prims::{Sphere, Triangle};
use crate::support::scenes::{suffern_spheres, wavy_sheet};
use crate::support::Checker;
use gridrt_grid::{CellStorage, Grid, GridConfig, Ray, Real, Vec3};
use proptest::prelude::*;

/// Automatic nesting, nesting from 2 and 8 references (dense and hashed),
/// a budget small enough to stop the recursion early, and a coarse flat
/// grid whose crowded cells test their references by groups; mailbox on
/// and off for each.
fn configs() -> Vec<GridConfig> {
    let mut v = Vec::new();
    for mailbox in [false, true] {
        v.push(GridConfig {
            mailbox,
            ..GridConfig::default()
        });
        for (nest, storage) in [(2, CellStorage::Dense), (8, CellStorage::Hashed)] {
            v.push(GridConfig {
                mailbox,
                storage,
                nest_min_refs: nest,
                ..GridConfig::default()
            });
        }
        v.push(GridConfig {
            mailbox,
            nest_min_refs: 2,
            memory_budget: Some(24 << 10),
            ..GridConfig::default()
        });
        // A coarse flat grid: crowded cells tested by groups with boxes.
        v.push(GridConfig {
            mailbox,
            auto: false,
            dims: Some([3, 3, 3]),
            ..GridConfig::default()
        });
    }
    v
}

/// `n` cases; a failing one is kept in
/// `proptest-regressions/hierarchy.txt` beside `tests/` and run first from
/// then on.
fn cases(n: u32) -> ProptestConfig {
    ProptestConfig {
        cases: n,
        ..ProptestConfig::default()
    }
}

/// A triangle from three points `c + s·p`.
fn tri(c: Vec3, s: Real, p: [[Real; 3]; 3]) -> Triangle {
    let v = p.map(|q| c + Vec3::from_array(q) * s);
    Triangle::new(v[0], v[1], v[2])
}

/// Small triangles in a cluster of size `s` around `c`, a few huge ones
/// around it (a room `room` wide), and rays from all around, aimed at the
/// cluster or passing beside it, from near and from several rooms away;
/// every ray checked against exhaustive.
fn check_cluster(c: Vec3, s: Real, room: Real, small: &[[[Real; 3]; 3]], aims: &[[Real; 6]]) {
    let mut scene: Vec<Triangle> = small.iter().map(|&p| tri(c, s, p)).collect();
    let r = room;
    // A floor under the cluster and two walls.
    scene.push(tri(c, 1.0, [[-r, -s, -r], [r, -s, -r], [0.0, -s, r]]));
    scene.push(tri(c, 1.0, [[-r, -r, -r], [r, -r, -r], [0.0, r, -r]]));
    scene.push(tri(c, 1.0, [[-r, -r, -r], [-r, r, -r], [-r, 0.0, r]]));
    let checker = Checker::new(scene, &configs());
    for (k, a) in aims.iter().enumerate() {
        let from = c + Vec3::new(a[0], a[1], a[2]) * (2.0 * s);
        let to = c + Vec3::new(a[3], a[4], a[5]) * (0.5 * s);
        checker.check(&Ray::new(from, to - from), 0.0, Real::INFINITY);
        // The same line from across the room.
        let far = to + (from - to) * (r / (2.0 * s));
        checker.check(&Ray::new(far, to - far), 0.0, Real::INFINITY);
        // From ten times the room's half-width away on the open side (no
        // floor or wall in the way), beyond the reach of narrower pads than
        // the room's: at the centre of a small triangle, and beside the
        // cluster through its cell.
        let t = small[k % small.len()].map(Vec3::from_array);
        let at = c + (t[0] + t[1] + t[2]) * (s / 3.0);
        let side = ((from - to).abs() + Vec3::splat(0.1)).normalize();
        let farther = at + side * (10.0 * r);
        checker.check(&Ray::new(farther, at - farther), 0.0, Real::INFINITY);
        let beside = at + Vec3::new(0.0, 3.0 * s, 0.0);
        checker.check(&Ray::new(farther, beside - farther), 0.0, Real::INFINITY);
    }
}

fn unit() -> impl Strategy<Value = Real> + Clone {
    -1.0 as Real..1.0
}

fn points3() -> impl Strategy<Value = [[Real; 3]; 3]> {
    let p = || [unit(), unit(), unit()];
    [p(), p(), p()]
}

fn aims(n: usize) -> impl Strategy<Value = Vec<[Real; 6]>> {
    prop::collection::vec([unit(), unit(), unit(), unit(), unit(), unit()], n)
}

proptest! {
    #![proptest_config(cases(3))]

    #[test]
    fn a_dense_cluster_in_a_huge_room(
        small in prop::collection::vec(points3().prop_map(|p| p.map(|q| q.map(|x| x * 0.05))), 20..120),
        aims in aims(12),
    ) {
        check_cluster(Vec3::new(0.3, 0.1, -0.2), 1.0, 500.0, &small, &aims);
    }

    #[test]
    fn a_cluster_of_small_triangles_seen_from_afar(
        small in prop::collection::vec((points3(), [unit(), unit(), unit()]), 60..200),
        aims in aims(12),
    ) {
        // Triangles a hundredth of the cluster wide, so that nested grids
        // separate them; in `f32` their pads are narrower than the room's,
        // and the rays from 5,000 units away are beyond their reach.
        let small: Vec<[[Real; 3]; 3]> = small
            .iter()
            .map(|(p, c)| p.map(|q| std::array::from_fn(|k| 0.05 * c[k] + 0.0005 * q[k])))
            .collect();
        check_cluster(Vec3::new(0.3, 0.1, -0.2), 2.0, 500.0, &small, &aims);
    }

    #[test]
    fn a_cluster_far_from_the_origin(
        small in prop::collection::vec(points3().prop_map(|p| p.map(|q| q.map(|x| x * 0.05))), 20..120),
        aims in aims(12),
        at in prop::sample::select(vec![1e3 as Real, -2e4, 1e5]),
    ) {
        check_cluster(Vec3::new(at, 0.5 * at, -at), 1.0, 300.0, &small, &aims);
    }

    #[test]
    fn fans_around_one_vertex(
        rim in prop::collection::vec([unit(), unit(), unit()], 30..150),
        aims in aims(12),
    ) {
        // Every triangle shares the vertex at the cluster's centre.
        let small: Vec<[[Real; 3]; 3]> = rim
            .windows(2)
            .map(|w| [[0.0; 3], w[0], w[1]])
            .collect();
        check_cluster(Vec3::new(1.0, 2.0, 3.0), 0.5, 200.0, &small, &aims);
    }

    #[test]
    fn coincident_triangles(
        base in points3(),
        copies in 50usize..150,
        others in prop::collection::vec(points3(), 0..40),
        aims in aims(12),
    ) {
        let mut small = vec![base; copies];
        small.extend(others);
        check_cluster(Vec3::new(-2.0, 0.0, 1.0), 0.5, 200.0, &small, &aims);
    }

    #[test]
    fn long_slivers_through_a_dense_cluster(
        small in prop::collection::vec(points3().prop_map(|p| p.map(|q| q.map(|x| x * 0.05))), 20..120),
        slivers in prop::collection::vec(points3(), 1..60),
        aims in aims(12),
    ) {
        // Slivers 600 units long and a thousandth wide, each through the
        // cluster's box: they cross the crowded cell and every cell on their
        // way, tested on entry while few and nested with the cluster when
        // many.
        let mut all = small;
        for [dir, at, width] in slivers {
            let d = Vec3::from_array(dir).try_normalize().unwrap_or(Vec3::X) * 300.0;
            let at = Vec3::from_array(at) * 0.05;
            let w = Vec3::from_array(width) * 0.001;
            all.push([(at - d).to_array(), (at + d).to_array(), (at + w).to_array()]);
        }
        check_cluster(Vec3::new(0.3, 0.1, -0.2), 1.0, 500.0, &all, &aims);
    }
}

#[test]
fn absurd_settings_stay_within_the_budget() {
    // One sphere, every cell nested, a thousand cells per axis asked for.
    let one = vec![Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.5)];
    let c = GridConfig {
        m: 1000.0,
        nest_min_refs: 1,
        nest_m: Some(1000.0),
        ..GridConfig::default()
    };
    let g = Grid::build(one, &c);
    g.check_invariants().expect("a valid grid");
    let s = g.stats();
    assert!(
        s.bytes <= s.budget && s.budget <= gridrt_grid::MIN_BUDGET,
        "{s:?}"
    );

    // A dense cluster with nesting from one reference and a tiny budget.
    let small: Vec<Triangle> = (0..500)
        .map(|i| {
            let a = i as Real * 0.01;
            let c = Vec3::new(1e5 + a.sin(), a.cos(), 0.001 * a);
            Triangle::new(c, c + Vec3::X * 0.01, c + Vec3::Y * 0.01)
        })
        .collect();
    for budget in [0, 10_000, 100_000, 1 << 20] {
        let c = GridConfig {
            nest_min_refs: 1,
            m: 4.0,
            memory_budget: Some(budget),
            ..GridConfig::default()
        };
        let g = Grid::build(small.clone(), &c);
        g.check_invariants().expect("a valid grid");
        let s = g.stats();
        assert!(s.bytes <= s.budget, "{budget}: {s:?}");
        assert!(s.budget >= budget, "{budget}: {s:?}");
    }
}

/// 3,000 small triangles in a unit ball at the origin.
fn small_cluster() -> Vec<Triangle> {
    (0..3000)
        .map(|i| {
            let a = i as Real;
            let c = Vec3::new((a * 0.37).sin(), (a * 0.11).cos(), (a * 0.07).sin()) * 0.5;
            Triangle::new(c, c + Vec3::X * 0.02, c + Vec3::Z * 0.02)
        })
        .collect()
}

#[test]
fn auto_nests_a_crowded_cell_and_leaves_a_uniform_scene_flat() {
    // A fine cluster in a huge room: the flat grid puts it in one cell.
    let mut scene = small_cluster();
    for k in [-1.0 as Real, 1.0] {
        let p = Vec3::splat(1000.0 * k);
        scene.push(Triangle::new(p, p + Vec3::X, p + Vec3::Y));
    }
    let g = Grid::build(scene, &GridConfig::default());
    g.check_invariants().expect("a valid grid");
    assert!(g.stats().nested_cells > 0 && g.stats().nest_min_refs > 0);

    // A uniform scene (Suffern's random spheres): no cell stands out.
    let uniform = suffern_spheres(10_000);
    let g = Grid::build(uniform, &GridConfig::default());
    assert_eq!(g.stats().nested_cells, 0, "{:?}", g.stats());
}

/// `fixtures/scenes/teapot_stadium.ron` in miniature: a wall that crosses
/// the crowded cell along one axis (spanning it on that axis only) must
/// not stretch the nested grid over the whole cell, or the cluster falls
/// into one nested cell again and every ray tests all of it.
#[test]
fn a_wall_crossing_the_crowded_cell_is_tested_directly() {
    use gridrt_grid::QueryCounters;
    // 3000 small triangles in a unit ball at the origin, in a 2000-unit
    // room, and a long thin wall passing by the cluster at x = 2.
    let mut scene = small_cluster();
    for k in [-1.0 as Real, 1.0] {
        let p = Vec3::splat(1000.0 * k);
        scene.push(Triangle::new(p, p + Vec3::X, p + Vec3::Y));
    }
    scene.push(Triangle::new(
        Vec3::new(2.0, -0.2, -900.0),
        Vec3::new(2.0, 0.2, -900.0),
        Vec3::new(2.0, 0.0, 900.0),
    ));
    let auto = [
        GridConfig::default(),
        GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
    ];
    let checker = Checker::new(scene.clone(), &auto);
    let g = Grid::build(scene, &GridConfig::default());
    g.check_invariants().expect("a valid grid");
    let mut scratch = gridrt_grid::Accelerator::scratch(&g);
    let mut c = QueryCounters::default();
    for i in 0..100 {
        let a = i as Real * 0.2;
        let to = Vec3::new(a.sin(), a.cos(), (0.3 * a).sin()) * 0.4;
        let from = Vec3::new(0.3, 3.0, 4.0);
        let ray = Ray::new(from, to - from);
        checker.check(&ray, 0.0, Real::INFINITY);
        g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut scratch, &mut c);
    }
    assert!(g.stats().nested_cells > 0);
    assert!(c.tests_per_ray() < 100.0, "{c:?} {:?}", g.stats());
}

/// The stadium in miniature: 3,000 small triangles in a unit ball, a
/// 2,000-unit room of 20 medium triangles around it. `auto` sizes the top
/// grid for the room (a few cells per axis), and the room's triangles that
/// share the cluster's large cell stretch its nested grid, which then holds
/// the cluster in one of its cells: that cell is nested again because the
/// space around the cluster shrank, though its references did not split.
#[test]
fn a_small_cluster_in_a_large_room_gets_a_coarse_top_and_deep_nesting() {
    use gridrt_grid::QueryCounters;
    let mut scene = small_cluster();
    for i in 0..20 {
        let a = i as Real * 1.7;
        let p = Vec3::new(a.sin(), (0.5 * a).cos(), (1.3 * a).sin()) * 1000.0;
        scene.push(Triangle::new(p, p + Vec3::X * 30.0, p + Vec3::Y * 30.0));
    }
    // Three near the cluster, in its large cell, spanning little of it.
    for p in [[150.0, 0.0, 0.0], [-100.0, 80.0, 50.0], [0.0, -120.0, 90.0]] {
        let p = Vec3::from_array(p);
        scene.push(Triangle::new(p, p + Vec3::X * 30.0, p + Vec3::Z * 30.0));
    }
    let flat = Grid::build(
        scene.clone(),
        &GridConfig {
            auto: false,
            ..GridConfig::default()
        },
    );
    let g = Grid::build(scene.clone(), &GridConfig::default());
    g.check_invariants().expect("a valid grid");
    let cells = |d: [u32; 3]| d.iter().map(|&n| u64::from(n)).product::<u64>();
    assert!(
        cells(g.dims()) * 16 <= cells(flat.dims()),
        "{:?} against {:?}",
        g.dims(),
        flat.dims()
    );
    let st = g.stats();
    assert!(st.nest_levels >= 2, "{st:?}");
    // The levels add up to the hierarchy, and each deeper level holds the
    // crowded cells of the one above.
    assert_eq!(st.levels.len(), st.nest_levels as usize);
    assert_eq!(
        st.levels.iter().map(|l| l.grids).sum::<u64>(),
        st.nested_cells
    );
    assert!(flat.stats().levels.is_empty());
    for (i, l) in st.levels.iter().enumerate() {
        assert!(l.grids > 0 && l.occupied_cells <= l.cells, "{i}: {l:?}");
        assert!(l.references >= l.occupied_cells, "{i}: {l:?}");
        assert!(u64::from(l.max_refs_per_cell) <= l.references, "{i}: {l:?}");
        if i > 0 {
            let above = &st.levels[i - 1];
            assert!(
                l.grids <= above.occupied_cells,
                "{i}: {l:?} under {above:?}"
            );
            assert!(
                st.nest_min_refs <= above.max_refs_per_cell,
                "{i}: {above:?}"
            );
        }
    }
    let auto = [
        GridConfig::default(),
        GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
    ];
    let checker = Checker::new(scene, &auto);
    let mut scratch = gridrt_grid::Accelerator::scratch(&g);
    let mut c = QueryCounters::default();
    for i in 0..100 {
        let a = i as Real * 0.2;
        let to = Vec3::new(a.sin(), a.cos(), (0.3 * a).sin()) * 0.4;
        for from in [Vec3::new(0.3, 3.0, 4.0), Vec3::new(-900.0, 400.0, 700.0)] {
            let ray = Ray::new(from, to - from);
            checker.check(&ray, 0.0, Real::INFINITY);
            g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut scratch, &mut c);
        }
    }
    assert!(c.tests_per_ray() < 100.0, "{c:?} {:?}", g.stats());
}

/// A fan of 4,000 triangles around one vertex in a large room: the
/// references never separate near the common vertex, so nesting must not
/// make a ray test more primitives than the exhaustive baseline does
/// (without mailboxing, every nested cell around the vertex holds most of
/// the fan), for rays aimed at the vertex and at the rest of the fan.
#[test]
fn a_fan_of_4000_triangles_never_costs_more_than_exhaustive() {
    use gridrt_grid::QueryCounters;
    let n = 4000;
    // Off the flat grid's cell planes, so that one flat cell holds the fan.
    let centre = Vec3::new(41.25, -0.5, 41.75);
    let rim = |i: usize| {
        let a = i as Real * std::f64::consts::TAU as Real / n as Real;
        // A wavy rim, so the fan is not flat.
        centre + Vec3::new(a.cos(), 0.3 * (7.0 * a).sin(), a.sin())
    };
    let mut scene: Vec<Triangle> = (0..n)
        .map(|i| Triangle::new(centre, rim(i), rim(i + 1)))
        .collect();
    for k in [-1.0 as Real, 1.0] {
        let p = Vec3::splat(500.0 * k);
        scene.push(Triangle::new(p, p + Vec3::X, p + Vec3::Y));
    }
    let total = scene.len() as f64;
    let configs = [
        GridConfig::default(),
        GridConfig {
            nest_min_refs: 8,
            ..GridConfig::default()
        },
        GridConfig {
            nest_min_refs: 2,
            nest_m: Some(2.0),
            ..GridConfig::default()
        },
    ];
    let mut checked = configs.to_vec();
    checked.extend(configs.iter().map(|c| GridConfig {
        mailbox: true,
        ..*c
    }));
    let checker = Checker::new(scene.clone(), &checked);
    for c in &configs {
        let g = Grid::build(scene.clone(), c);
        g.check_invariants().expect("a valid grid");
        let mut scratch = gridrt_grid::Accelerator::scratch(&g);
        let mut near = QueryCounters::default();
        let mut all = QueryCounters::default();
        for i in 0..200 {
            let a = i as Real * 0.37;
            let from = centre + Vec3::new(0.7 * a.sin(), 2.0, 0.7 * a.cos());
            // Half of the rays at the common vertex (within 10⁻³), half anywhere on the fan.
            let to = if i % 2 == 0 {
                centre + Vec3::new(a.cos(), 0.0, a.sin()) * 1e-3
            } else {
                centre + Vec3::new(a.cos(), 0.0, a.sin()) * (0.1 + 0.8 * (i as Real / 200.0))
            };
            let ray = Ray::new(from, to - from);
            checker.check(&ray, 0.0, Real::INFINITY);
            let counters = if i % 2 == 0 { &mut near } else { &mut all };
            g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut scratch, counters);
        }
        assert!(
            near.tests_per_ray() <= total,
            "near the vertex: {near:?} {:?}",
            g.stats()
        );
        assert!(
            all.tests_per_ray() <= total,
            "on the fan: {all:?} {:?}",
            g.stats()
        );
    }
}

/// A finely tessellated wavy sheet in a large room crowds thousands of
/// cells, whose references are many times one batch of nested-grid plans:
/// the batches build the same valid grids whatever the threads, and a
/// budget that runs out part way through a level is kept.
#[test]
fn a_surface_crowding_many_cells_nests_the_same_in_batches() {
    let mut scene = wavy_sheet(300, Vec3::ZERO, 1.0);
    for k in [-1.0 as Real, 1.0] {
        let p = Vec3::splat(1.5 * k);
        scene.push(Triangle::new(p, p + Vec3::X, p + Vec3::Y));
    }
    let unlimited = Grid::build(
        scene.clone(),
        &GridConfig {
            nest_min_refs: 48,
            ..GridConfig::default()
        },
    );
    let all = unlimited.stats().clone();
    assert!(
        all.references > 2 << 16 && all.nested_cells > 100,
        "{all:?}"
    );
    let half = all.bytes / 2;
    for budget in [None, Some(half)] {
        let stats: Vec<_> = [false, true]
            .map(|parallel_build| {
                let g = Grid::build(
                    scene.clone(),
                    &GridConfig {
                        nest_min_refs: 48,
                        parallel_build,
                        memory_budget: budget,
                        ..GridConfig::default()
                    },
                );
                g.check_invariants().expect("a valid grid");
                g.stats().clone()
            })
            .into();
        let s = &stats[0];
        assert!(s.nested_cells > 0 && s.bytes <= s.budget, "{s:?}");
        if budget.is_some() {
            assert!(s.nested_cells < all.nested_cells, "{s:?}");
        }
        assert_eq!(
            (s.nested_cells, s.nest_levels, s.bytes),
            (stats[1].nested_cells, stats[1].nest_levels, stats[1].bytes)
        );
    }
}

/// The first nested grid the budget cannot take ends the build, so the
/// grids built under a budget are the first ones of the unlimited build:
/// within the budget, a larger budget never nests fewer cells, and none
/// goes deeper than the unlimited build.
#[test]
fn a_larger_budget_never_nests_fewer_cells() {
    let mut scene = wavy_sheet(100, Vec3::ZERO, 1.0);
    let p = Vec3::splat(20.0);
    scene.push(Triangle::new(p, p + Vec3::X, p + Vec3::Y));
    let config = |memory_budget| GridConfig {
        nest_min_refs: 16,
        memory_budget,
        ..GridConfig::default()
    };
    let all = Grid::build(scene.clone(), &config(None)).stats().clone();
    let flat = Grid::build(
        scene.clone(),
        &GridConfig {
            auto: false,
            ..GridConfig::default()
        },
    )
    .stats()
    .bytes;
    assert!(all.nested_cells > 20 && all.nest_levels >= 2, "{all:?}");
    let mut last = 0;
    for k in 1..=6 {
        let budget = flat + (all.bytes - flat) * k / 7;
        let g = Grid::build(scene.clone(), &config(Some(budget)));
        g.check_invariants().expect("a valid grid");
        let s = g.stats();
        assert!(s.bytes <= budget, "{budget}: {s:?}");
        assert!(s.nested_cells >= last, "{budget}: {s:?}");
        assert!(s.nested_cells < all.nested_cells, "{budget}: {s:?}");
        assert!(s.nest_levels <= all.nest_levels, "{budget}: {s:?}");
        last = s.nested_cells;
    }
    assert!(last > 0);
}

/// A wavy sheet of 60×60 quads, `size` wide, centred at the origin, in a
/// 2,000-unit room: a floor under it and two walls.
fn sheet_in_a_room(size: Real) -> Vec<Triangle> {
    let centre = Vec3::new(0.5, 0.0, 0.5);
    let mut scene: Vec<Triangle> = wavy_sheet(60, Vec3::ZERO, 1.0)
        .iter()
        .map(|t| {
            let [a, b, c] = t.vertices().map(|v| (v - centre) * size);
            Triangle::new(a, b, c)
        })
        .collect();
    let r = 1000.0;
    let y = -size;
    scene.push(Triangle::new(
        Vec3::new(-r, y, -r),
        Vec3::new(r, y, -r),
        Vec3::new(0.0, y, r),
    ));
    scene.push(Triangle::new(
        Vec3::new(-r, -r, -r),
        Vec3::new(r, -r, -r),
        Vec3::new(0.0, r, -r),
    ));
    scene.push(Triangle::new(
        Vec3::new(-r, -r, -r),
        Vec3::new(-r, r, -r),
        Vec3::new(-r, 0.0, r),
    ));
    scene
}

/// Rays at points of the sheet of [`sheet_in_a_room`], from `away` times
/// its size.
fn rays_at_the_sheet(size: Real, away: Real) -> Vec<Ray> {
    (0..400)
        .map(|i| {
            let a = i as Real * 0.37;
            let to = Vec3::new(a.sin() * 0.45, 0.0, (1.3 * a).cos() * 0.45) * size;
            let from = to + Vec3::new(0.3, 1.0, 0.6).normalize() * (away * size);
            Ray::new(from, to - from)
        })
        .collect()
}

/// The teapot in a stadium at any scale: a nested grid's pad follows its
/// own cells, not the room, so an object 0.5 units wide in a 2,000-unit
/// room is nested nearly as well as one 20 units wide (with the room's pad,
/// 0.015 in f32, the small one's nested cells would each hold their
/// neighbours' triangles too, and rays test some 14 times as many). Rays
/// from near it, from across the room and from farther than the nested
/// grids' reach (they test their parent cells' references, or walk a wide
/// grid, instead) get the exhaustive answers.
#[test]
fn a_small_object_in_a_large_room_nests_alike_at_any_scale() {
    use gridrt_grid::QueryCounters;
    let tests_per_ray = |size: Real, away: Real| {
        let g = Grid::build(sheet_in_a_room(size), &GridConfig::default());
        g.check_invariants().expect("a valid grid");
        let mut scratch = gridrt_grid::Accelerator::scratch(&g);
        let mut c = QueryCounters::default();
        for ray in rays_at_the_sheet(size, away) {
            g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut scratch, &mut c);
        }
        c.tests_per_ray()
    };
    let (small, large) = (tests_per_ray(0.5, 3.0), tests_per_ray(20.0, 3.0));
    assert!(
        small <= 3.0 * large,
        "{small} tests per ray against {large}"
    );
    // From across the room, beyond the deeper grids' narrowed reach, a ray
    // tests their parent cells' references instead, not the whole sheet
    // (7,200 triangles).
    let far = tests_per_ray(0.5, 3e3);
    assert!(far <= 1000.0, "{far} tests per ray from afar");
    // From beyond the first-level grid's reach too (10,000 units away, a
    // telephoto view), a ray walks the wide grid kept beside it for such
    // rays, not the whole sheet.
    let telephoto = tests_per_ray(0.5, 2e4);
    assert!(
        telephoto <= 1000.0,
        "{telephoto} tests per ray from 10,000 units"
    );

    let size = 0.5;
    let configs = [
        GridConfig::default(),
        GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
        GridConfig {
            nest_min_refs: 2,
            ..GridConfig::default()
        },
    ];
    let checker = Checker::new(sheet_in_a_room(size), &configs);
    for away in [3.0, 2e3, 2e4] {
        for ray in rays_at_the_sheet(size, away) {
            checker.check(&ray, 0.0, Real::INFINITY);
        }
    }
}
