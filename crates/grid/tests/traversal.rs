//! The 3D-DDA as an iterator and as a visitor: a connected walk with
//! contiguous intervals that covers every cell the ray really crosses.

use crate::support::prims::{Shape, Sphere};
use crate::support::scenes::Lcg;
use gridrt_grid::{Aabb, CellStorage, CellVisit, Grid, GridConfig, Ray, Real, Vec3};
use std::ops::ControlFlow;

fn scene(n: usize, seed: u64) -> Vec<Shape> {
    let mut rng = Lcg::new(seed);
    (0..n)
        .map(|_| {
            let c = Vec3::new(
                rng.range(-3.0, 3.0),
                rng.range(-1.0, 1.0),
                rng.range(-2.0, 2.0),
            );
            Shape::Sphere(Sphere::new(c, rng.range(0.01, 0.4)))
        })
        .collect()
}

fn random_ray(rng: &mut Lcg) -> (Ray, Real, Real) {
    let o = Vec3::new(
        rng.range(-5.0, 5.0),
        rng.range(-3.0, 3.0),
        rng.range(-4.0, 4.0),
    );
    let mut d = Vec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    // Often axis-parallel or in a coordinate plane, with zeros of both signs.
    match rng.next_u32() % 6 {
        0 => d.x = 0.0,
        1 => d.y = -0.0,
        2 => {
            d.x = -0.0;
            d.z = 0.0;
        }
        _ => {}
    }
    if d == Vec3::ZERO {
        d = Vec3::X;
    }
    let (t0, t1) = match rng.next_u32() % 3 {
        0 => (0.0, Real::INFINITY),
        1 => (rng.range(0.0, 3.0), rng.range(3.0, 9.0)),
        _ => (rng.range(-2.0, 1.0), Real::INFINITY),
    };
    (Ray::new(o, d), t0, t1)
}

#[test]
fn the_walk_is_connected_with_contiguous_intervals() {
    let g = Grid::build(scene(300, 1), &GridConfig::default());
    let dims = g.dims();
    let mut rng = Lcg::new(2);
    for _ in 0..2000 {
        let (ray, t0, t1) = random_ray(&mut rng);
        let visits: Vec<CellVisit> = g.cells_along(&ray, t0, t1).collect();
        assert!(
            visits.len() <= (dims[0] + dims[1] + dims[2]) as usize,
            "too many cells"
        );
        for v in &visits {
            assert!((0..3).all(|a| v.index[a] < dims[a]));
            assert!(v.t_enter <= v.t_exit, "{v:?}");
            assert!(
                v.t_enter >= t0 && v.t_exit <= t1,
                "{v:?} outside [{t0}, {t1}]"
            );
        }
        for w in visits.windows(2) {
            assert_eq!(w[0].t_exit, w[1].t_enter);
            let steps: u32 = (0..3).map(|a| w[0].index[a].abs_diff(w[1].index[a])).sum();
            assert_eq!(steps, 1, "{:?} -> {:?}", w[0], w[1]);
            // Never along an axis the ray does not move on.
            for a in 0..3 {
                if ray.dir[a] == 0.0 {
                    assert_eq!(w[0].index[a], w[1].index[a]);
                }
            }
        }
    }
}

#[test]
fn the_walk_covers_every_cell_the_ray_crosses() {
    for dims in [None, Some([5, 1, 7]), Some([1, 1, 1])] {
        let g = Grid::build(
            scene(200, 3),
            &GridConfig {
                dims,
                ..GridConfig::default()
            },
        );
        let d = g.dims();
        let mut rng = Lcg::new(4);
        for _ in 0..300 {
            let (ray, t0, t1) = random_ray(&mut rng);
            let visited: Vec<[u32; 3]> = g.cells_along(&ray, t0, t1).map(|v| v.index).collect();
            for k in 0..d[2] {
                for j in 0..d[1] {
                    for i in 0..d[0] {
                        let b = g.cell_bounds([i, j, k]).expect("in the grid");
                        // Shrink the cell a little: a ray that only grazes a face,
                        // edge or corner may legitimately be walked past it.
                        let shrunk = Aabb::new(
                            b.min + (b.max - b.min) * 0.001,
                            b.max - (b.max - b.min) * 0.001,
                        );
                        if let Some((a, z)) = shrunk.hit(&ray, t0, t1) {
                            if z > a && !shrunk.is_empty() {
                                assert!(
                                    visited.contains(&[i, j, k]),
                                    "cell {:?} crossed on [{a}, {z}] but not visited; ray {ray:?}",
                                    [i, j, k]
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn visitor_and_iterator_agree() {
    for storage in [CellStorage::Dense, CellStorage::Hashed] {
        let g = Grid::build(
            scene(300, 5),
            &GridConfig {
                storage,
                ..GridConfig::default()
            },
        );
        let mut rng = Lcg::new(6);
        for _ in 0..500 {
            let (ray, t0, t1) = random_ray(&mut rng);
            let want: Vec<CellVisit> = g.cells_along(&ray, t0, t1).collect();
            let mut got = Vec::new();
            let flow = g.visit_cells(&ray, t0, t1, |v, refs| {
                // References are slots; `cell_refs` names primitives.
                let prims: Vec<u32> = refs.iter().map(|&r| g.primitive_of(r)).collect();
                assert_eq!(prims, g.cell_refs(v.index));
                got.push(v);
                ControlFlow::<()>::Continue(())
            });
            assert!(flow.is_continue());
            assert_eq!(got, want);
            // Breaking stops the walk at once.
            let mut n = 0;
            let flow = g.visit_cells(&ray, t0, t1, |_, _| {
                n += 1;
                if n == 2 {
                    ControlFlow::Break(7)
                } else {
                    ControlFlow::Continue(())
                }
            });
            if want.len() >= 2 {
                assert_eq!(flow, ControlFlow::Break(7));
                assert_eq!(n, 2);
            }
        }
    }
}

#[test]
fn negative_zero_never_steps_and_max_face_clamps() {
    let g = Grid::build(
        scene(100, 7),
        &GridConfig {
            dims: Some([6, 6, 6]),
            ..GridConfig::default()
        },
    );
    let b = g.bounds();
    let mid = b.centroid();
    for dir in [
        Vec3::new(-0.0, -0.0, -1.0),
        Vec3::new(1.0, -0.0, 0.0),
        Vec3::new(0.0, -1.0, -0.0),
    ] {
        let o = mid - dir * 100.0;
        let visits: Vec<_> = g
            .cells_along(&Ray::new(o, dir), 0.0, Real::INFINITY)
            .collect();
        assert_eq!(visits.len(), 6);
        for a in 0..3 {
            if dir[a] == 0.0 {
                assert!(visits.iter().all(|v| v.index[a] == visits[0].index[a]));
            }
        }
    }
    // Origin exactly on the max corner, walking back inside.
    let first = g
        .cells_along(&Ray::new(b.max, -Vec3::ONE), 0.0, Real::INFINITY)
        .next()
        .expect("a cell");
    assert_eq!(first.index, [5, 5, 5]);
    // Lying in the max face x = max, moving along y: all cells have i = 5.
    let o = Vec3::new(b.max.x, b.min.y - 1.0, mid.z);
    let v: Vec<_> = g
        .cells_along(&Ray::new(o, Vec3::Y), 0.0, Real::INFINITY)
        .collect();
    assert_eq!(v.len(), 6);
    assert!(v.iter().all(|c| c.index[0] == 5));
}

#[test]
fn point_and_empty_ranges() {
    let g = Grid::build(scene(100, 8), &GridConfig::default());
    let c = g.bounds().centroid();
    let ray = Ray::new(c, Vec3::new(0.3, 0.2, 1.0));
    // t_min == t_max: the cell (or the two cells) holding that single point.
    let v: Vec<_> = g.cells_along(&ray, 0.0, 0.0).collect();
    assert!(!v.is_empty() && v.len() <= 4);
    assert!(v.iter().all(|x| x.t_enter == 0.0 && x.t_exit == 0.0));
    assert_eq!(g.cells_along(&ray, 1.0, 0.5).count(), 0);
    assert_eq!(g.cells_along(&ray, Real::NAN, 1.0).count(), 0);
    // Pointing away from the grid from outside.
    let away = Ray::new(g.bounds().max + Vec3::ONE, Vec3::ONE);
    assert_eq!(g.cells_along(&away, 0.0, Real::INFINITY).count(), 0);
}
