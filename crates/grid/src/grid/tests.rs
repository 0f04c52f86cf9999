//! Unit tests of the grid's queries against the exhaustive baseline.

use super::*;
use crate::{Exhaustive, PrimHit};
use gridrt_bbox::Vec3;

/// A ball, just enough for these tests (and the cluster rule's).
#[derive(Clone, Debug)]
pub(crate) struct Ball(pub Vec3, pub Real);

impl Primitive for Ball {
    type Shared = ();
    type RayData = ();
    type Four = ();
    fn ray_data(_: &Ray) {}
    fn bounds(&self, _: &()) -> Aabb {
        Aabb::new(self.0 - Vec3::splat(self.1), self.0 + Vec3::splat(self.1))
    }
    fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t0: Real, t1: Real) -> Option<PrimHit> {
        // From the point of closest approach, so that a ray from afar
        // keeps its hit within rounding of the ball (as pbrt-v4's sphere).
        let oc = ray.origin - self.0;
        let a = ray.dir.dot(ray.dir);
        let mid = -oc.dot(ray.dir) / a;
        let near = oc + ray.dir * mid;
        let disc = self.1 * self.1 - near.dot(near);
        if disc < 0.0 {
            return None;
        }
        let s = (disc / a).sqrt();
        [mid - s, mid + s]
            .into_iter()
            .find(|t| (t0..=t1).contains(t))
            .map(|t| PrimHit::new(t, 0.0, 0.0))
    }
}

/// The default configuration with every finite box gridded, outsized or
/// not ([`GridConfig::set_aside_outsized`] off).
fn outsized_kept_in() -> GridConfig {
    GridConfig {
        set_aside_outsized: false,
        ..GridConfig::default()
    }
}

fn lcg(s: &mut u64) -> Real {
    *s = s
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*s >> 40) as Real / (1u64 << 24) as Real
}

#[test]
fn mailbox_ids_wrap_around_safely() {
    let mut s = GridScratch::default();
    assert_eq!(s.begin(3), 1);
    s.stamps[1] = 1;
    s.ray = u32::MAX;
    // The id wraps to 0, which would match fresh stamps: all are cleared.
    s.stamps[2] = u32::MAX;
    assert_eq!(s.begin(3), 1);
    assert_eq!(s.stamps, vec![0, 0, 0]);
    // A scratch sized for other primitives is resized and reset.
    assert_eq!(s.begin(5), 1);
    assert_eq!(s.stamps.len(), 5);
}

#[test]
fn sparse_scenes_skip_empty_blocks_and_stay_exact() {
    // Clusters of balls far apart: most blocks of the grid are empty.
    let mut seed = 1;
    let mut prims = Vec::new();
    for c in 0..6 {
        let centre = Vec3::new(
            c as Real * 7.0 - 20.0,
            (c % 3) as Real * 9.0 - 9.0,
            (c % 2) as Real * 11.0,
        );
        for _ in 0..80 {
            let p = centre + Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed));
            prims.push(Ball(p, 0.02 + 0.05 * lcg(&mut seed)));
        }
    }
    let e = Exhaustive::new(prims.clone());
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        for mailbox in [false, true] {
            let g = Grid::build(
                prims.clone(),
                &GridConfig {
                    storage,
                    mailbox,
                    m: 3.0,
                    ..GridConfig::default()
                },
            );
            assert!(g.blocks.useful, "the walk should skip empty blocks here");
            g.check_invariants().expect("invariants");
            let mut sc = g.scratch();
            let mut hits = 0;
            for i in 0..3000 {
                let o = Vec3::new(
                    lcg(&mut seed) * 60.0 - 30.0,
                    lcg(&mut seed) * 40.0 - 20.0,
                    lcg(&mut seed) * 40.0 - 15.0,
                );
                let target = prims[i % prims.len()].0
                    + Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 0.2;
                let r = Ray::new(o, target - o);
                let want = e.closest_hit(&r, 0.0, Real::INFINITY, &mut ());
                assert_eq!(g.closest_hit(&r, 0.0, Real::INFINITY, &mut sc), want);
                assert_eq!(
                    g.any_hit(&r, 0.0, 0.9, &mut sc),
                    e.any_hit(&r, 0.0, 0.9, &mut ())
                );
                hits += usize::from(want.is_some());
            }
            assert!(hits > 1000, "{hits}");
        }
    }
}

#[test]
fn dense_scenes_walk_every_cell() {
    let mut seed = 3;
    let prims: Vec<Ball> = (0..2000)
        .map(|_| {
            Ball(
                Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)),
                0.02,
            )
        })
        .collect();
    let g = Grid::build(prims, &GridConfig::default());
    assert!(!g.blocks.useful);
}

#[test]
fn the_distance_map_skips_only_empty_cells() {
    // Small clusters in a large box, walked along every kind of direction:
    // the walk that skips by the distance map must visit exactly the
    // occupied cells the cell-by-cell walk meets, in order, and answer as
    // the exhaustive baseline does.
    let mut seed = 7;
    let mut prims = Vec::new();
    for c in 0..5 {
        let centre = Vec3::new(
            (c * 13 % 40) as Real - 20.0,
            (c * 7 % 30) as Real - 15.0,
            (c * 11 % 50) as Real - 25.0,
        );
        for _ in 0..40 {
            let p = centre + Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 2.0;
            prims.push(Ball(p, 0.05 + 0.1 * lcg(&mut seed)));
        }
    }
    let e = Exhaustive::new(prims.clone());
    let dirs = [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::new(1.0, -1.0, 0.0)];
    for mailbox in [false, true] {
        let g = Grid::build(
            prims.clone(),
            &GridConfig {
                mailbox,
                m: 2.0,
                ..GridConfig::default()
            },
        );
        assert!(!g.far.is_empty(), "a sparse dense grid gets a distance map");
        assert!(g.far.iter().any(|&d| d > 3), "with room to skip");
        g.check_invariants().expect("invariants");
        let mut sc = g.scratch();
        for i in 0..4000 {
            let o = Vec3::new(
                lcg(&mut seed) * 60.0 - 30.0,
                lcg(&mut seed) * 50.0 - 25.0,
                lcg(&mut seed) * 70.0 - 35.0,
            );
            let d = if i % 5 == 0 {
                dirs[i % dirs.len()]
            } else {
                let target = prims[i % prims.len()].0;
                target - o + Vec3::new(lcg(&mut seed), lcg(&mut seed), 0.0)
            };
            let r = Ray::new(o, d);
            let t_max = if i % 3 == 0 { 2.0 } else { Real::INFINITY };
            let want = e.closest_hit(&r, 0.0, t_max, &mut ());
            let mut c = crate::QueryCounters::default();
            let got = g.closest_hit_counted(&r, 0.0, t_max, &mut sc, &mut c);
            assert_eq!(got, want, "ray {i}");
            assert_eq!(g.any_hit(&r, 0.0, t_max, &mut sc), want.is_some());
            if want.is_none() {
                // With nothing hit the query walks the whole range: it
                // visits every occupied cell the plain walk meets.
                let mut occupied = 0;
                let _ = g.visit_cells(&r, 0.0, t_max, |_, refs| {
                    occupied += u64::from(!refs.is_empty());
                    ControlFlow::<()>::Continue(())
                });
                assert_eq!(c.cells, occupied, "ray {i}");
            }
        }
    }
}

/// A cluster of 4,000 small balls, 0.5 wide, in a scene 16,000 wide: in
/// `f32` its first-level nested grid narrows the pad, so it keeps a chain
/// of wide grids, each with a wider pad, for rays from farther than its
/// reach (in `f64` the pad is far below the cells, the nested grid keeps
/// its parent's and covers them). Rays from near and far get the
/// exhaustive answers without testing the cluster whole, rays from near
/// test about what they test in the cluster's own grid (330 per ray, 12
/// times as many, with a pad of at least a quarter of the parent's), and
/// `check_invariants` refuses a wide grid that lost a reference or took a
/// narrower pad.
#[test]
fn a_far_ray_walks_the_wide_grid_of_a_crowded_cell() {
    let mut s = 7u64;
    let mut balls: Vec<Ball> = (0..4000)
        .map(|_| {
            let c = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s)) * 0.5;
            Ball(c, 0.002)
        })
        .collect();
    balls.push(Ball(Vec3::splat(-8000.0), 1.0));
    balls.push(Ball(Vec3::splat(8000.0), 1.0));
    // The far balls stay in the cells (set aside, the grid would span the
    // cluster alone).
    let config = outsized_kept_in();
    let build = || Grid::build(balls.clone(), &config);
    let g = build();
    g.check_invariants().expect("a valid grid");
    let owner = g.nested.subs.iter().find(|s| s.wide.is_some());
    if cfg!(feature = "f64") {
        assert!(owner.is_none());
    } else {
        let owner = owner.expect("a wide grid beside the cluster's nested grid");
        let mut pads = Vec::new();
        for wg in owner.wide_grids() {
            assert!(wg.geom.cell_count() > 1 && wg.children.is_empty());
            pads.push(wg.geom.pad);
        }
        assert!(pads.len() >= 2, "a chain of wide grids: pads {pads:?}");
        assert!(pads.windows(2).all(|p| p[0] < p[1]), "pads {pads:?}");
    }

    let ex = Exhaustive::new(balls.clone());
    let (mut gs, mut es) = (g.scratch(), ex.scratch());
    // Per distance: 3, 900 and 9,000 units.
    let mut c = [crate::QueryCounters::default(); 3];
    for i in 0..300 {
        let to = balls[i * 13].0;
        let far = [3.0, 900.0, 9000.0][i % 3];
        let from = to + Vec3::new(0.3, 1.0, 0.6).normalize() * far;
        let ray = Ray::new(from, to - from);
        let hit = g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut gs, &mut c[i % 3]);
        let want = ex.closest_hit(&ray, 0.0, Real::INFINITY, &mut es);
        assert_eq!(hit.map(|h| (h.t, h.prim)), want.map(|h| (h.t, h.prim)));
        assert_eq!(
            g.any_hit(&ray, 0.0, Real::INFINITY, &mut gs),
            ex.any_hit(&ray, 0.0, Real::INFINITY, &mut es)
        );
    }
    let tests = c.map(|c| c.tests_per_ray());
    assert!(tests.iter().all(|&t| t < 400.0), "{tests:?} tests per ray");
    // Near rays test about what they test in the cluster's own grid: the
    // nested grid's pad follows its cells, not the scene around it.
    let alone = Grid::build(balls[..4000].to_vec(), &GridConfig::default());
    let (mut c_alone, mut s_alone) = (crate::QueryCounters::default(), alone.scratch());
    for i in (0..300).step_by(3) {
        let to = balls[i * 13].0;
        let from = to + Vec3::new(0.3, 1.0, 0.6).normalize() * 3.0;
        let ray = Ray::new(from, to - from);
        alone.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut s_alone, &mut c_alone);
    }
    assert!(
        tests[0] <= 1.5 * c_alone.tests_per_ray() + 8.0,
        "near rays: {} tests per ray, {} in the cluster alone",
        tests[0],
        c_alone.tests_per_ray()
    );
    if owner.is_none() {
        return;
    }

    fn wide_of(g: &mut Grid<Ball>) -> &mut crate::nested::Sub {
        let subs = &mut g.nested.subs;
        let i = subs.iter().position(|s| s.wide.is_some()).unwrap();
        subs[i].wide.as_deref_mut().unwrap()
    }
    let mut lost = build();
    let w = wide_of(&mut lost);
    let first = w.refs[0];
    w.refs.iter_mut().for_each(|r| {
        if *r == first {
            *r = first ^ 1;
        }
    });
    assert!(lost.check_invariants().is_err());
    let mut narrow = build();
    let w = wide_of(&mut narrow);
    w.geom.pad *= 0.5;
    assert!(narrow.check_invariants().is_err());
}

/// A cluster 0.05 wide, 1,000 units from the origin, in a scene 16,000
/// wide: in `f32` the chain of wide grids beside its nested grid ends
/// where the cluster fits in one cell of the wider pad, short of the
/// parent's, so a ray from 20,000 units is beyond every reach. Such a ray
/// that crosses the cluster's top cell but misses the cluster's box
/// (widened by the parent's pad) tests none of its 4,000 balls (it tested
/// them all before the box test); one aimed at the cluster tests them and
/// gets the exhaustive answer. `check_invariants` checks the box.
#[test]
fn a_ray_beyond_every_reach_tests_a_cluster_only_if_it_meets_its_box() {
    let mut s = 11u64;
    let mut balls: Vec<Ball> = (0..4000)
        .map(|_| {
            let c = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s)) * 0.05;
            Ball(c + Vec3::splat(1000.0), 0.0002)
        })
        .collect();
    balls.push(Ball(Vec3::splat(-8000.0), 1.0));
    balls.push(Ball(Vec3::splat(8000.0), 1.0));
    let config = outsized_kept_in();
    let g = Grid::build(balls.clone(), &config);
    g.check_invariants().expect("a valid grid");
    let ex = Exhaustive::new(balls.clone());
    let (mut gs, mut es) = (g.scratch(), ex.scratch());
    let (mut missing, mut aimed) = (
        crate::QueryCounters::default(),
        crate::QueryCounters::default(),
    );
    for i in 0..200 {
        let to = balls[i * 17].0;
        let from = to + Vec3::new(0.3, 1.0, 0.6).normalize() * 20_000.0;
        // Half of the rays pass a unit beside the cluster.
        let aim = if i % 2 == 0 { to } else { to + Vec3::X };
        let ray = Ray::new(from, aim - from);
        if !cfg!(feature = "f64") {
            let sub = g.nested.subs.iter().find(|s| s.wide.is_some());
            let sub = sub.expect("a chain of wide grids");
            assert!(sub.for_ray(&ray).is_none(), "beyond every reach");
        }
        let c = if i % 2 == 0 { &mut aimed } else { &mut missing };
        let hit = g.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut gs, c);
        let want = ex.closest_hit(&ray, 0.0, Real::INFINITY, &mut es);
        assert_eq!(hit.map(|h| (h.t, h.prim)), want.map(|h| (h.t, h.prim)));
        assert_eq!(
            g.any_hit(&ray, 0.0, Real::INFINITY, &mut gs),
            ex.any_hit(&ray, 0.0, Real::INFINITY, &mut es)
        );
    }
    // At most the two large balls, none of the cluster's 4,000.
    assert!(
        missing.tests_per_ray() <= 2.0,
        "{} tests per missing ray",
        missing.tests_per_ray()
    );
    assert!(aimed.tests_per_ray() >= 1.0);
    // `check_invariants` refuses a box that was not widened, and a box
    // that culls the cell and is not the hull of that box and of the
    // chain's entry boxes.
    let mut g = g;
    let sub = &mut g.nested.subs[0];
    let outer = sub.outer;
    sub.outer = sub.geom.bounds;
    assert!(g.check_invariants().is_err());
    let sub = &mut g.nested.subs[0];
    sub.outer = outer;
    g.check_invariants().expect("the box restored");
    let sub = &mut g.nested.subs[0];
    sub.cull = sub.geom.bounds;
    assert!(g.check_invariants().is_err());
}

/// 2,000 small balls in the unit cube and `big` balls 1,000 times larger
/// below them (the first and the last identical, so that their hits tie).
fn cluster_on_ground(big: usize) -> Vec<Ball> {
    let mut seed = 11;
    let ground = |k: usize| Ball(Vec3::new(0.5 + k as Real, -500.5, 0.5), 500.0);
    let mut prims: Vec<Ball> = (big > 0).then(|| ground(0)).into_iter().collect();
    prims.extend((0..2000).map(|_| {
        Ball(
            Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)),
            0.01,
        )
    }));
    prims.extend((1..big.saturating_sub(1)).map(ground));
    if big > 1 {
        prims.push(ground(0));
    }
    prims
}

#[test]
fn outsized_primitives_are_set_aside_and_the_answers_stay_exact() {
    // Fewer than four are tested one by one, more four at a time.
    for big in 1..=5 {
        set_aside_answers_are_exact(big);
    }
}

fn set_aside_answers_are_exact(big: usize) {
    let prims = cluster_on_ground(big);
    let twin = (big > 1).then_some(prims.len() as u32 - 1);
    let aside: Vec<u32> = std::iter::once(0).chain(2001..).take(big).collect();
    let e = Exhaustive::new(prims.clone());
    let mut seed = 5;
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        for mailbox in [false, true] {
            let config = GridConfig {
                storage,
                mailbox,
                ..GridConfig::default()
            };
            let g = Grid::build(prims.clone(), &config);
            g.check_invariants().expect("invariants");
            assert_eq!(g.unbounded_primitives(), aside);
            assert_eq!(g.stats().unbounded_prims, big as u64);
            // The grid spans the small balls, not the ground.
            assert!(g.geom.bounds.extent().max_element() < 1.1);
            let mut sc = g.scratch();
            let (mut ground, mut small) = (0, 0);
            for i in 0..4000 {
                let o = Vec3::new(
                    lcg(&mut seed) * 8.0 - 4.0,
                    lcg(&mut seed) * 6.0 - 1.0,
                    lcg(&mut seed) * 8.0 - 4.0,
                );
                let target = if i % 2 == 0 {
                    prims[1 + i % 2000].0
                } else {
                    Vec3::new(lcg(&mut seed), -0.5 * lcg(&mut seed), lcg(&mut seed))
                };
                let r = Ray::new(o, target - o);
                let want = e.closest_hit(&r, 0.0, Real::INFINITY, &mut ());
                assert_eq!(g.closest_hit(&r, 0.0, Real::INFINITY, &mut sc), want);
                assert_eq!(
                    g.any_hit(&r, 0.0, 0.5, &mut sc),
                    e.any_hit(&r, 0.0, 0.5, &mut ())
                );
                match want.map(|h| h.prim) {
                    Some(0) => ground += 1,
                    Some(p) => {
                        // The ground's twin (last) never wins a tie.
                        assert!(Some(p) != twin);
                        small += usize::from(p <= 2000);
                    }
                    None => {}
                }
            }
            assert!(ground > 500 && small > 500, "{ground} {small}");
        }
    }
}

#[test]
fn outsized_primitives_stay_in_the_cells_when_setting_them_aside_would_not_pay() {
    // Seventeen of them: more than a ray should test besides the grid.
    let g = Grid::build(cluster_on_ground(17), &GridConfig::default());
    assert!(g.unbounded_primitives().is_empty());
    g.check_invariants().expect("invariants");
    // One as large as the cluster's box: the box of the rest is no smaller.
    let mut prims = cluster_on_ground(0);
    for p in &mut prims {
        p.0 *= 100.0;
    }
    prims.push(Ball(Vec3::splat(50.0), 40.0));
    let g = Grid::build(prims, &GridConfig::default());
    assert!(g.unbounded_primitives().is_empty());
    g.check_invariants().expect("invariants");
    // Or when the configuration says so.
    let config = outsized_kept_in();
    let g = Grid::build(cluster_on_ground(3), &config);
    assert!(g.unbounded_primitives().is_empty());
    assert!(g.geom.bounds.extent().max_element() > 1000.0);
    g.check_invariants().expect("invariants");
}
