//! Construction: the lecture's resolution, degenerate extents, caps,
//! storage and parallel/sequential agreement, stats and counters.

use crate::support::prims::{Shape, Sphere, Triangle};
use crate::support::scenes::{self, Lcg};
use gridrt_grid::{
    Aabb, Accelerator, CellStorage, Exhaustive, Grid, GridConfig, PrimHit, Primitive,
    QueryCounters, Ray, Real, Vec3,
};

fn lecture_dims(b: Aabb, n: usize, m: f64) -> [u32; 3] {
    let w = b.extent();
    let w = [w.x as f64, w.y as f64, w.z as f64];
    let s = (w[0] * w[1] * w[2] / n as f64).cbrt();
    w.map(|wa| (m * wa / s).floor() as u32 + 1)
}

#[test]
fn resolution_follows_the_lecture_formula() {
    for &n in &[10usize, 100, 1000, 5000] {
        for m in [1.0, 2.0, 3.0] {
            let s = scenes::suffern_spheres(n);
            let g = Grid::build(
                s,
                &GridConfig {
                    m: m as Real,
                    // The flat grid: `auto` tests ten spheres directly.
                    auto: false,
                    ..GridConfig::default()
                },
            );
            let want = lecture_dims(g.bounds(), n, m);
            let got = g.dims();
            // Equal up to rounding of the floor.
            for a in 0..3 {
                assert!(
                    got[a].abs_diff(want[a]) <= 1,
                    "n = {n}, m = {m}: {got:?} vs {want:?}"
                );
            }
            g.check_invariants().expect("invariants");
        }
    }
}

#[test]
fn the_lectures_m_2_gives_about_eight_cells_per_object() {
    let g = Grid::build(
        scenes::suffern_spheres(1000),
        &GridConfig {
            m: 2.0,
            ..GridConfig::default()
        },
    );
    let per = g.stats().cells as f64 / 1000.0;
    assert!((7.0..10.0).contains(&per), "{per} cells per object");
}

#[test]
fn flat_and_degenerate_scenes() {
    // All triangles in the plane z = 1: one layer of cells, about m² per triangle.
    let mut rng = Lcg::new(1);
    let flat: Vec<Shape> = (0..400)
        .map(|_| {
            let p = Vec3::new(rng.range(0.0, 10.0), rng.range(0.0, 10.0), 1.0);
            Shape::Triangle(Triangle::new(
                p,
                p + Vec3::new(0.2, 0.0, 0.0),
                p + Vec3::new(0.0, 0.2, 0.0),
            ))
        })
        .collect();
    let g = Grid::build(
        flat.clone(),
        &GridConfig {
            m: 2.0,
            ..GridConfig::default()
        },
    );
    let d = g.dims();
    assert_eq!(d[2], 1);
    assert!(d[0] >= 30 && d[0] <= 50, "{d:?}");
    g.check_invariants().expect("invariants");
    let e = Exhaustive::new(flat);
    let mut s = g.scratch();
    for i in 0..200 {
        let o = Vec3::new(rng.range(0.0, 10.0), rng.range(0.0, 10.0), 5.0);
        let r = Ray::new(
            o,
            Vec3::new(0.0, 0.0, -1.0) + Vec3::new(rng.range(-0.1, 0.1), 0.0, 0.0) * (i % 2) as Real,
        );
        assert_eq!(
            g.closest_hit(&r, 0.0, Real::INFINITY, &mut s),
            e.closest_hit(&r, 0.0, Real::INFINITY, &mut ())
        );
    }
    // A line of spheres along x: one cell across y and z.
    let line: Vec<Shape> = (0..50)
        .map(|i| Shape::Sphere(Sphere::new(Vec3::new(i as Real, 0.0, 0.0), 0.0)))
        .collect();
    let config = GridConfig::default();
    let g = Grid::build(line, &config);
    assert_eq!(&g.dims()[1..], &[1, 1]);
    // About m cells per sphere along the line (s = length / n).
    assert_eq!(g.dims()[0], (config.m * 50.0) as u32 + 1);
    // Every object at one point.
    let point = vec![Shape::Sphere(Sphere::new(Vec3::splat(3.0), 0.0)); 20];
    let g = Grid::build(point, &GridConfig::default());
    assert_eq!(g.dims(), [1, 1, 1]);
    assert_eq!(g.stats().references, 20);
}

#[test]
fn cell_cap_and_odd_configs_never_panic() {
    let s = scenes::suffern_spheres(2000);
    for max_cells in [0u64, 1, 7, 1000, 50_000] {
        for m in [2.0, 0.0, -1.0, Real::NAN, Real::INFINITY, 1e6] {
            let c = GridConfig {
                m,
                max_cells,
                ..GridConfig::default()
            };
            let g = Grid::build(s.clone(), &c);
            assert!(g.stats().cells <= max_cells.max(1), "{c:?}: {:?}", g.dims());
            g.check_invariants().expect("invariants");
        }
    }
    let g = Grid::build(
        s.clone(),
        &GridConfig {
            dims: Some([0, 3, 1_000_000]),
            max_cells: 5000,
            ..GridConfig::default()
        },
    );
    assert!(g.stats().cells <= 5000 && g.dims()[0] == 1);
    // A cap beyond the hard limit is clamped, not trusted.
    let g = Grid::build(
        s,
        &GridConfig {
            max_cells: u64::MAX,
            ..GridConfig::default()
        },
    );
    g.check_invariants().expect("invariants");
}

#[test]
fn huge_primitives_over_a_fine_grid_stay_bounded() {
    // Big triangles across everything plus many small spheres.
    let mut s: Vec<Shape> = scenes::suffern_spheres(3000)
        .into_iter()
        .map(Shape::Sphere)
        .collect();
    for k in 0..300 {
        let z = -1.0 + k as Real / 150.0;
        s.push(Shape::Triangle(Triangle::new(
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(1.0, -1.0, z),
            Vec3::new(0.0, 1.0, z),
        )));
    }
    let g = Grid::build(
        s,
        &GridConfig {
            m: 8.0,
            ..GridConfig::default()
        },
    );
    assert!(g.stats().references <= 4 << 26);
    g.check_invariants().expect("invariants");
}

/// Builds sequentially and in parallel, in a pool
/// of four workers (so the ranges come in several chunks and the dense
/// build splits its cells into slabs, each with its own window of
/// records), and checks that every cell holds the same primitives in the
/// same order and every primitive has the same slot.
#[test]
fn parallel_and_sequential_builds_agree() {
    let mut s: Vec<Shape> = scenes::suffern_spheres(40_000)
        .into_iter()
        .map(Shape::Sphere)
        .collect();
    s.extend(
        scenes::uv_sphere_mesh(&scenes::suffern_spheres(20), 8, 5)
            .into_iter()
            .map(Shape::Triangle),
    );
    // Ranges across many layers, first cells spread over the grid, and
    // boxes that cannot be gridded in several chunks.
    for (i, r) in [0.3, 0.5, 0.05, 0.8].into_iter().enumerate() {
        let c = -0.9 + 0.5 * i as Real;
        s.insert(
            i * 10_000,
            Shape::Sphere(Sphere::new(Vec3::new(c, -c, c), r)),
        );
        let nan = Vec3::new(c, Real::NAN, c);
        s.insert(i * 10_000 + 7, Shape::Sphere(Sphere::new(nan, 0.1)));
    }
    let check = || {
        for storage in [CellStorage::Dense, CellStorage::Hashed] {
            for exact_insertion in [false, true] {
                let c = GridConfig {
                    storage,
                    exact_insertion,
                    m: 2.0,
                    ..GridConfig::default()
                };
                let seq = GridConfig {
                    parallel_build: false,
                    ..c
                };
                let par = GridConfig {
                    parallel_build: true,
                    ..c
                };
                let a = Grid::build(s.clone(), &seq);
                {
                    let b = Grid::build(s.clone(), &par);
                    let what = (storage, exact_insertion);
                    b.check_invariants().expect("invariants");
                    let (sa, sb) = (a.stats(), b.stats());
                    assert_eq!(
                        (sa.dims, sa.references, sa.occupied_cells),
                        (sb.dims, sb.references, sb.occupied_cells),
                        "{what:?}"
                    );
                    assert_eq!(sa.max_refs_per_cell, sb.max_refs_per_cell);
                    assert_eq!(a.unbounded_primitives(), b.unbounded_primitives());
                    assert_eq!(a.primitive_ids(), b.primitive_ids(), "{what:?}");
                    let d = a.dims();
                    for k in 0..d[2] {
                        for j in 0..d[1] {
                            for i in 0..d[0] {
                                let (ra, rb) = (a.cell_refs([i, j, k]), b.cell_refs([i, j, k]));
                                assert_eq!(ra, rb, "cell {:?} {what:?}", [i, j, k]);
                            }
                        }
                    }
                }
            }
        }
    };
    #[cfg(feature = "rayon")]
    rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .expect("a pool")
        .install(check);
    #[cfg(not(feature = "rayon"))]
    check();
}

#[test]
fn hashed_and_dense_hold_the_same_cells() {
    let s = scenes::suffern_spheres(5000);
    let h = Grid::build(
        s.clone(),
        &GridConfig {
            storage: CellStorage::Hashed,
            ..GridConfig::default()
        },
    );
    let d = Grid::build(
        s,
        &GridConfig {
            storage: CellStorage::Dense,
            ..GridConfig::default()
        },
    );
    assert_eq!(h.dims(), d.dims());
    assert_eq!(h.stats().references, d.stats().references);
    assert_eq!(h.stats().occupied_cells, d.stats().occupied_cells);
    let n = h.dims();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let mut a = h.cell_refs([i, j, k]).to_vec();
                let mut b = d.cell_refs([i, j, k]).to_vec();
                a.sort_unstable();
                b.sort_unstable();
                assert_eq!(a, b);
            }
        }
    }
    assert_eq!(h.cell_refs([n[0], 0, 0]), &[] as &[u32]);
}

#[test]
fn stats_are_filled() {
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        let g = Grid::build(
            scenes::suffern_spheres(1000),
            &GridConfig {
                storage,
                ..GridConfig::default()
            },
        );
        let s = g.stats();
        assert_eq!(
            s.cells,
            s.dims.iter().map(|&d| u64::from(d)).product::<u64>()
        );
        assert!(s.occupied_cells > 0 && s.occupied_cells <= s.cells);
        assert!(s.references >= 1000);
        assert!(
            (s.mean_refs_per_occupied - s.references as f64 / s.occupied_cells as f64).abs() < 1e-9
        );
        assert!(s.max_refs_per_cell >= 1);
        assert!(s.bytes > s.table_bytes && s.table_bytes > 0);
        assert_eq!(g.storage(), storage);
        if storage == CellStorage::Dense {
            assert_eq!(s.table_bytes, 4 * (s.cells as usize + 1));
        } else {
            assert!(s.table_bytes >= 16 * 2 * s.occupied_cells as usize);
        }
    }
}

#[test]
fn exact_insertion_drops_references_and_stays_exact() {
    let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(30), 16, 9);
    let loose = Grid::build(
        tris.clone(),
        &GridConfig {
            exact_insertion: false,
            m: 3.0,
            ..GridConfig::default()
        },
    );
    let tight = Grid::build(
        tris.clone(),
        &GridConfig {
            exact_insertion: true,
            m: 3.0,
            ..GridConfig::default()
        },
    );
    tight.check_invariants().expect("invariants");
    assert!(tight.stats().references < loose.stats().references);
    let e = Exhaustive::new(tris);
    let mut rng = Lcg::new(9);
    let mut s = tight.scratch();
    for _ in 0..2000 {
        let o = Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), 3.0);
        let t = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let r = Ray::new(o, t - o);
        assert_eq!(
            tight.closest_hit(&r, 0.0, Real::INFINITY, &mut s),
            e.closest_hit(&r, 0.0, Real::INFINITY, &mut ())
        );
    }
}

#[test]
fn primitives_keep_their_order_and_odd_boxes_are_kept_aside() {
    #[derive(Clone, Debug, PartialEq)]
    struct Odd(Aabb);
    impl Primitive for Odd {
        type Shared = ();
        type RayData = ();
        type Four = ();
        fn ray_data(_: &Ray) {}
        fn bounds(&self, _: &()) -> Aabb {
            self.0
        }
        fn closest_hit(&self, _: &(), _: &Ray, _: &(), _: Real, _: Real) -> Option<PrimHit> {
            None
        }
    }
    let v = |x: Real| Vec3::splat(x);
    let prims = vec![
        Odd(Aabb::new(v(0.0), v(1.0))),
        Odd(Aabb::new(v(Real::NAN), v(1.0))),
        Odd(Aabb::EMPTY),
        Odd(Aabb::new(v(2.0), v(3.0))),
        Odd(Aabb::new(v(-Real::INFINITY), v(0.0))),
    ];
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        let g = Grid::build(
            prims.clone(),
            &GridConfig {
                storage,
                ..GridConfig::default()
            },
        );
        g.check_invariants().expect("invariants");
        assert_eq!(g.unbounded_primitives(), [1, 2, 4]);
        assert_eq!(g.bounds(), Aabb::new(v(0.0), v(3.0)));
        // Slot order: the gridded primitives, then the unbounded ones.
        let ids = g.primitive_ids();
        assert_eq!(&ids[ids.len() - 3..], &[1, 2, 4]);
        for (slot, &p) in ids.iter().enumerate() {
            // (Debug strings: NaN != NaN.)
            let (a, b) = (&g.primitives()[slot], &prims[p as usize]);
            assert_eq!(format!("{a:?}"), format!("{b:?}"));
        }
        assert_eq!(format!("{:?}", g.into_primitives()), format!("{:?}", prims));
    }
}

#[test]
fn counters_count_cells_tests_and_mailbox_skips() {
    // Long thin boxes across many cells: mailboxing has something to skip.
    let mut rng = Lcg::new(12);
    let tris: Vec<Triangle> = (0..300)
        .map(|_| {
            let p = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            Triangle::new(
                p,
                p + Vec3::new(0.8, 0.05, 0.0),
                p + Vec3::new(0.0, 0.05, 0.8),
            )
        })
        .collect();
    let rays: Vec<Ray> = (0..500)
        .map(|_| {
            let o = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 3.0);
            Ray::new(
                o,
                Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), -1.0),
            )
        })
        .collect();
    let e = Exhaustive::new(tris.clone());
    let mut ec = QueryCounters::default();
    for r in &rays {
        e.closest_hit_counted(r, 0.0, Real::INFINITY, &mut ec);
    }
    assert_eq!(ec.rays, 500);
    assert_eq!(ec.tests, 500 * 300);
    assert_eq!(ec.cells, 0);
    let mut totals = Vec::new();
    for mailbox in [false, true] {
        let g = Grid::build(
            tris.clone(),
            &GridConfig {
                mailbox,
                m: 3.0,
                ..GridConfig::default()
            },
        );
        let mut s = g.scratch();
        let mut c = QueryCounters::default();
        for r in &rays {
            let a = g.closest_hit_counted(r, 0.0, Real::INFINITY, &mut s, &mut c);
            assert_eq!(a, e.closest_hit(r, 0.0, Real::INFINITY, &mut ()));
        }
        assert_eq!(c.rays, 500);
        assert!(c.cells > 500 && c.tests > 0);
        assert!(c.tests_per_ray() < 300.0);
        if mailbox {
            assert!(c.mailbox_skips > 0);
        } else {
            assert_eq!(c.mailbox_skips, 0);
        }
        totals.push(c);
    }
    // Mailboxing turns repeated tests into skips, cell for cell.
    assert_eq!(totals[0].tests, totals[1].tests + totals[1].mailbox_skips);
    let mut any = QueryCounters::default();
    let g = Grid::build(tris, &GridConfig::default());
    let mut s = g.scratch();
    for r in &rays {
        g.any_hit_counted(r, 0.0, Real::INFINITY, &mut s, &mut any);
    }
    assert_eq!(any.rays, 500);
}

#[test]
fn scratch_from_another_grid_is_resized_not_trusted() {
    let a = Grid::build(
        scenes::suffern_spheres(10),
        &GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
    );
    let b = Grid::build(
        scenes::suffern_spheres(1000),
        &GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
    );
    let mut s = a.scratch();
    let e = Exhaustive::new(scenes::suffern_spheres(1000));
    for r in scenes::suffern_rays().iter().step_by(97) {
        assert_eq!(
            b.closest_hit(r, 0.0, Real::INFINITY, &mut s),
            e.closest_hit(r, 0.0, Real::INFINITY, &mut ())
        );
    }
}

#[test]
fn grids_are_send_and_sync_and_scratch_is_send() {
    fn send_sync<T: Send + Sync>() {}
    fn send<T: Send>() {}
    send_sync::<Grid<Sphere>>();
    send_sync::<Exhaustive<Sphere>>();
    send::<<Grid<Sphere> as Accelerator>::Scratch>();
    send_sync::<gridrt_grid::CellIter<'static>>();
}

#[test]
fn suffern_scene_matches_the_peers_pixel_counts() {
    // The Embree peer's published counts (LCG scene, seed 15) at N = 10, 100, 1000.
    let rays = scenes::suffern_rays();
    for (n, want) in [(10usize, 16972usize), (100, 35175), (1000, 64037)] {
        let g = Grid::build(scenes::suffern_spheres(n), &GridConfig::default());
        let mut s = g.scratch();
        let hits: Vec<Option<u32>> = rays
            .iter()
            .map(|r| {
                g.closest_hit(r, 0.0, Real::INFINITY, &mut s)
                    .map(|h| h.prim)
            })
            .collect();
        assert_eq!(scenes::checksum(&hits).0, want, "N = {n}");
    }
}

/// A grid built from a borrowed slice (each primitive cloned into its
/// slot) is the grid built from the vector: same slots, same cells, same
/// answers.
#[test]
fn building_from_a_slice_is_building_from_the_vector() {
    let s: Vec<Sphere> = scenes::suffern_spheres(3000);
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        let c = GridConfig {
            storage,
            ..GridConfig::default()
        };
        let a = Grid::build(s.clone(), &c);
        let b = Grid::build_from_slice(&s, &c);
        b.check_invariants().expect("invariants");
        assert_eq!(a.primitive_ids(), b.primitive_ids());
        assert_eq!(
            format!("{:?}", a.primitives()),
            format!("{:?}", b.primitives())
        );
        let mut rng = Lcg::new(5);
        let (mut sa, mut sb) = (a.scratch(), b.scratch());
        for _ in 0..200 {
            let mut u = || rng.next_f32() as Real - 0.5;
            let o = Vec3::new(u(), u(), 4.0);
            let ray = Ray::new(o, Vec3::new(u(), u(), -1.0));
            let (ha, hb) = (
                a.closest_hit(&ray, 0.0, Real::INFINITY, &mut sa),
                b.closest_hit(&ray, 0.0, Real::INFINITY, &mut sb),
            );
            assert_eq!(ha, hb);
            assert_eq!(ha.map(|h| h.slot), hb.map(|h| h.slot));
        }
    }
}

/// `auto` over at most `AUTO_DIRECT_MAX` primitives: one cell, tested
/// without a walk, and the exhaustive answers for closest and any hit;
/// one primitive more gets the lecture's grid.
#[test]
fn auto_tests_a_handful_of_primitives_directly() {
    use crate::support::Checker;
    use gridrt_grid::AUTO_DIRECT_MAX;
    let mut rng = Lcg::new(7);
    let mut prims: Vec<Shape> = Vec::new();
    for i in 0..=AUTO_DIRECT_MAX {
        let c = Vec3::new(
            rng.range(-4.0, 4.0),
            rng.range(-4.0, 4.0),
            rng.range(-4.0, 4.0),
        );
        prims.push(if i % 2 == 0 {
            Shape::Sphere(Sphere::new(c, rng.range(0.1, 1.5)))
        } else {
            let d = |rng: &mut Lcg| Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.3);
            Shape::Triangle(Triangle::new(c, c + d(&mut rng), c + d(&mut rng)))
        });
    }
    let auto = GridConfig::default();
    let big = Grid::build(prims.clone(), &auto);
    assert!(big.stats().cells > 1, "{:?}", big.stats().dims);
    prims.pop();
    let few = Grid::build(prims.clone(), &auto);
    assert_eq!(few.stats().dims, [1, 1, 1]);
    assert_eq!(few.stats().references, AUTO_DIRECT_MAX as u64);
    let check = Checker::new(prims, &[auto]);
    let mut hits = 0;
    for i in 0..2000 {
        let o = Vec3::new(
            rng.range(-6.0, 6.0),
            rng.range(-6.0, 6.0),
            rng.range(-6.0, 6.0),
        );
        let d = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let t_max = if i % 3 == 0 { 2.0 } else { Real::INFINITY };
        hits += usize::from(check.check(&Ray::new(o, d), 0.0, t_max).is_some());
    }
    assert!(hits > 100, "{hits} hits");
}
