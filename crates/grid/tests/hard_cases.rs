//! The hard numerical cases of the issue, one named test each. Every test
//! compares the grid (all storages, mailbox on and off, exact insertion on
//! and off) with the exhaustive answer, bit for bit.

use crate::support::prims::{Shape, Sphere, Triangle};
use crate::support::{all_configs, Checker};
use gridrt_grid::{Aabb, Accelerator, Grid, GridConfig, PrimHit, Primitive, Ray, Real, Vec3};

fn v(x: Real, y: Real, z: Real) -> Vec3 {
    Vec3::new(x, y, z)
}

fn sph(x: Real, y: Real, z: Real, r: Real) -> Shape {
    Shape::Sphere(Sphere::new(v(x, y, z), r))
}

fn tri(a: Vec3, b: Vec3, c: Vec3) -> Shape {
    Shape::Triangle(Triangle::new(a, b, c))
}

/// Configs over the lattice scene: the automatic resolution and an 8³ grid
/// whose cell planes are exactly the integers 0..=8.
fn lattice_configs() -> Vec<GridConfig> {
    let mut v = all_configs();
    v.extend(all_configs().into_iter().map(|c| GridConfig {
        dims: Some([8, 8, 8]),
        ..c
    }));
    v
}

/// A scene in `[0, 8]³` whose geometry sits on the cell planes of an 8³ grid:
/// spheres of radius ½ at cell centres (touching six planes), unit quads
/// lying in cell planes (two triangles sharing a diagonal), triangles with
/// integer vertices across several cells, and duplicated primitives (exact ties).
fn lattice_scene() -> Vec<Shape> {
    let mut s = vec![sph(0.5, 0.5, 0.5, 0.5), sph(7.5, 7.5, 7.5, 0.5)];
    for i in (0..8).step_by(3) {
        for j in (1..8).step_by(3) {
            for k in (0..8).step_by(2) {
                s.push(sph(i as Real + 0.5, j as Real + 0.5, k as Real + 0.5, 0.5));
            }
        }
    }
    // Quads in the planes x = 4, y = 2 and z = 5.
    for a in 1..6 {
        let (p, q) = (a as Real, a as Real + 1.0);
        s.push(tri(v(4.0, p, p), v(4.0, q, p), v(4.0, q, q)));
        s.push(tri(v(4.0, p, p), v(4.0, q, q), v(4.0, p, q)));
        s.push(tri(v(p, 2.0, 1.0), v(q, 2.0, 1.0), v(q, 2.0, 2.0)));
        s.push(tri(v(p, 2.0, 1.0), v(q, 2.0, 2.0), v(p, 2.0, 2.0)));
        s.push(tri(v(p, 1.0, 5.0), v(q, 1.0, 5.0), v(q, 2.0, 5.0)));
    }
    // Long slanted triangles with integer vertices.
    s.push(tri(v(0.0, 0.0, 0.0), v(8.0, 3.0, 1.0), v(2.0, 8.0, 6.0)));
    s.push(tri(v(8.0, 0.0, 8.0), v(0.0, 8.0, 0.0), v(3.0, 3.0, 3.0)));
    // Exact duplicates: ties in t that the lower index must win.
    s.push(tri(v(4.0, 1.0, 1.0), v(4.0, 2.0, 1.0), v(4.0, 2.0, 2.0)));
    s.push(sph(3.5, 1.5, 0.5, 0.5));
    s
}

/// Origins on, beside and outside the cell planes of the lattice.
const COORDS: [Real; 9] = [-1.0, 0.0, 0.5, 1.0, 2.0, 4.0, 7.5, 8.0, 9.0];

fn axis_dirs() -> Vec<Vec3> {
    let mut d = Vec::new();
    for a in 0..3 {
        for s in [1.0, -1.0] {
            let mut x = Vec3::ZERO;
            x[a] = s;
            d.push(x);
            // The same with negative zeros in the other components.
            let mut y = Vec3::splat(-0.0);
            y[a] = s;
            d.push(y);
        }
    }
    d
}

fn check_all(
    c: &Checker<Shape>,
    origins: &[Vec3],
    dirs: &[Vec3],
    ranges: &[(Real, Real)],
) -> usize {
    let mut hits = 0;
    for &o in origins {
        for &d in dirs {
            for &(t0, t1) in ranges {
                hits += usize::from(c.check(&Ray::new(o, d), t0, t1).is_some());
            }
        }
    }
    hits
}

fn lattice_origins() -> Vec<Vec3> {
    let mut o = Vec::new();
    for &x in &COORDS {
        for &y in &COORDS {
            for &z in &COORDS {
                o.push(v(x, y, z));
            }
        }
    }
    o
}

#[test]
fn axis_parallel_rays_with_origin_on_cell_planes() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let hits = check_all(
        &c,
        &lattice_origins(),
        &axis_dirs(),
        &[(0.0, Real::INFINITY)],
    );
    assert!(hits > 1000, "the scene should be hit often, got {hits}");
}

#[test]
fn rays_along_cell_edges() {
    // Lines x = i, y = j (and the other two axis pairs) are cell edges.
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let mut origins = Vec::new();
    for i in 0..=8 {
        for j in 0..=8 {
            let (a, b) = (i as Real, j as Real);
            origins.extend([
                v(a, b, -1.0),
                v(a, b, 9.0),
                v(a, -1.0, b),
                v(9.0, a, b),
                v(a, b, 4.0),
            ]);
        }
    }
    let hits = check_all(
        &c,
        &origins,
        &axis_dirs(),
        &[(0.0, Real::INFINITY), (0.5, 6.0)],
    );
    assert!(hits > 100);
}

#[test]
fn rays_through_cell_corners() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let mut dirs = Vec::new();
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                dirs.push(v(sx, sy, sz));
                dirs.push(v(sx, sy, 0.0));
                dirs.push(v(sx, -0.0, sz));
                dirs.push(v(sx, 2.0 * sy, 3.0 * sz));
            }
        }
    }
    let hits = check_all(&c, &lattice_origins(), &dirs, &[(0.0, Real::INFINITY)]);
    assert!(hits > 1000);
}

#[test]
fn negative_zero_direction_components() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let dirs = [
        v(-0.0, 0.0, -1.0),
        v(0.0, -0.0, 1.0),
        v(1.0, -0.0, -0.0),
        v(-1.0, -0.0, -0.0),
        v(-0.0, -1.0, -0.0),
        v(-0.0, -0.0, -1.0),
        v(-0.0, 1.0, 1.0),
        v(-1.0, -0.0, -1.0),
    ];
    let hits = check_all(
        &c,
        &lattice_origins(),
        &dirs,
        &[(0.0, Real::INFINITY), (-Real::INFINITY, 3.0)],
    );
    assert!(hits > 100);
    // A −0.0 component must never step its axis.
    let g = c
        .grids
        .iter()
        .find(|g| g.dims() == [8, 8, 8])
        .expect("an 8³ grid");
    for visit in g.cells_along(
        &Ray::new(v(4.0, 2.0, 9.0), v(-0.0, -0.0, -1.0)),
        0.0,
        Real::INFINITY,
    ) {
        assert_eq!(visit.index[0], 4);
        assert_eq!(visit.index[1], 2);
    }
}

#[test]
fn origin_exactly_on_the_grid_max_face() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let mut origins = Vec::new();
    for &a in &COORDS[1..8] {
        for &b in &COORDS[1..8] {
            origins.extend([v(8.0, a, b), v(a, 8.0, b), v(a, b, 8.0)]);
        }
    }
    origins.push(v(8.0, 8.0, 8.0));
    let mut dirs = axis_dirs();
    dirs.extend([v(-1.0, -1.0, -1.0), v(-1.0, -0.5, -0.25), v(1.0, 1.0, 1.0)]);
    check_all(&c, &origins, &dirs, &[(0.0, Real::INFINITY)]);
    // The walk starts in the last cell.
    let g = c
        .grids
        .iter()
        .find(|g| g.dims() == [8, 8, 8])
        .expect("an 8³ grid");
    let first = g
        .cells_along(&Ray::new(v(8.0, 8.0, 8.0), v(-1.0, -1.0, -1.0)), 0.0, 100.0)
        .next();
    assert_eq!(first.map(|c| c.index), Some([7, 7, 7]));
    let along = g.cells_along(&Ray::new(v(8.0, 3.5, 3.5), v(-0.0, 1.0, 0.0)), 0.0, 100.0);
    assert!(along.map(|c| c.index[0]).all(|i| i == 7));
}

#[test]
fn origin_inside_and_outside_with_positive_t_min() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let origins = [
        v(-3.0, 2.5, 2.5),
        v(3.3, 2.5, 2.5),
        v(4.0, 2.0, 2.0),
        v(0.5, 0.5, -4.0),
        v(5.5, 5.5, 5.5),
    ];
    let dirs = [
        v(1.0, 0.0, 0.0),
        v(0.0, 0.0, 1.0),
        v(1.0, 0.25, 0.125),
        v(-0.3, -0.2, -1.0),
    ];
    let mut ranges = vec![(0.0, Real::INFINITY)];
    for t in [0.25, 1.0, 2.0, 3.5, 4.0, 5.0, 6.5, 9.0, 20.0] {
        ranges.push((t, Real::INFINITY));
        ranges.push((t, t + 1.0));
    }
    check_all(&c, &origins, &dirs, &ranges);
}

#[test]
fn primitive_spanning_many_cells_hit_in_a_later_cell() {
    // Primitive 0: a thin slanted triangle that crosses the cell the ray
    // enters first (so it is tested there) but is hit only at x = 6.3.
    let slope = 0.0645;
    let z_at = |x: Real| 2.5 + (6.3 - x) * slope;
    let mut s = vec![
        tri(
            v(0.0, 0.0, z_at(0.0)),
            v(0.0, 8.0, z_at(0.0)),
            v(8.0, 0.0, z_at(8.0)),
        ),
        sph(0.5, 0.5, 0.5, 0.5),
        sph(7.5, 7.5, 7.5, 0.5),
    ];
    // Clutter in the cells after the hit, with higher indices.
    s.extend((0..6).map(|i| sph(7.0, 1.0 + 0.1 * i as Real, 2.5, 0.3)));
    let ray = Ray::new(v(-1.0, 1.0, 2.5), v(1.0, 0.0, 0.0));
    for configs in [all_configs(), lattice_configs()] {
        let c = Checker::new(s.clone(), &configs);
        let h = c.check(&ray, 0.0, Real::INFINITY).expect("hit");
        assert_eq!(h.prim, 0);
        assert!((h.t - 7.3).abs() < 1e-3, "t = {}", h.t);
        // The first cell holds the triangle, so the mailbox stamps it there.
        for g in c.grids.iter().filter(|g| g.dims() == [8, 8, 8]) {
            let first = g
                .cells_along(&ray, 0.0, Real::INFINITY)
                .next()
                .expect("a cell");
            assert!(g.cell_refs(first.index).contains(&0), "{:?}", g.config());
        }
    }
    // A nearer sphere with a higher index wins once it is in front.
    s.push(sph(3.5, 1.0, 2.5, 0.25));
    let c = Checker::new(s, &lattice_configs());
    assert_eq!(c.check(&ray, 0.0, Real::INFINITY).map(|h| h.prim), Some(9));
}

#[test]
fn hit_exactly_on_a_cell_plane() {
    // A fold: two triangles share the edge (4,2,2)–(4,3,3) in the plane x = 4,
    // one on each side of the plane; the higher index lies before the plane.
    let s = vec![
        tri(v(4.0, 2.0, 2.0), v(4.0, 3.0, 3.0), v(4.5, 3.0, 2.0)),
        tri(v(4.0, 2.0, 2.0), v(4.0, 3.0, 3.0), v(3.5, 2.0, 3.0)),
        // The same quad twice, in the plane z = 5: an exact tie.
        tri(v(1.0, 1.0, 5.0), v(3.0, 1.0, 5.0), v(3.0, 3.0, 5.0)),
        tri(v(1.0, 1.0, 5.0), v(3.0, 1.0, 5.0), v(3.0, 3.0, 5.0)),
        sph(0.5, 0.5, 0.5, 0.5),
        sph(7.5, 7.5, 7.5, 0.5),
    ];
    let c = Checker::new(s, &lattice_configs());
    let h = c
        .check(
            &Ray::new(v(-1.0, 2.5, 2.5), v(1.0, 0.0, 0.0)),
            0.0,
            Real::INFINITY,
        )
        .expect("hit");
    assert_eq!(h.t, 5.0);
    for x in [1.5, 2.0, 2.5, 3.0] {
        for y in [1.0, 1.5, 2.0, 2.5] {
            for dz in [1.0, -1.0] {
                let z0 = if dz > 0.0 { -1.0 } else { 9.0 };
                let h = c.check(&Ray::new(v(x, y, z0), v(0.0, 0.0, dz)), 0.0, Real::INFINITY);
                if let Some(h) = h {
                    assert_eq!(h.prim, 2, "the lower index of the duplicated pair");
                }
            }
        }
    }
    // Rays that graze the fold's edge from many directions.
    let mut dirs = Vec::new();
    for k in 0..24 {
        let a = k as Real * 0.26;
        dirs.push(v(a.cos(), 0.1 * a.sin(), a.sin()));
    }
    let origins: Vec<Vec3> = dirs.iter().map(|d| v(4.0, 2.5, 2.5) - *d * 3.0).collect();
    for (o, d) in origins.iter().zip(&dirs) {
        c.check(&Ray::new(*o, *d), 0.0, Real::INFINITY);
    }
}

#[test]
fn all_objects_in_one_cell() {
    let mut rng = crate::support::scenes::Lcg::new(3);
    let s: Vec<Shape> = (0..60)
        .map(|_| {
            sph(
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                0.05,
            )
        })
        .collect();
    let configs: Vec<GridConfig> = all_configs()
        .into_iter()
        .map(|c| GridConfig { max_cells: 1, ..c })
        .collect();
    let c = Checker::new(s.clone(), &configs);
    assert_eq!(c.grids[0].dims(), [1, 1, 1]);
    assert_eq!(c.grids[0].stats().references, 60);
    random_rays(&c, v(0.5, 0.5, 0.5), 1.5, 300);
    // Identical objects: every one in every cell of a normal grid.
    let same = vec![sph(0.2, 0.3, 0.4, 0.1); 40];
    let c = Checker::all(same);
    random_rays(&c, v(0.2, 0.3, 0.4), 0.3, 200);
}

#[test]
fn one_object() {
    let c = Checker::all(vec![sph(1.0, 2.0, 3.0, 0.5)]);
    assert!(c
        .grids
        .iter()
        .all(|g| g.dims() == [2, 2, 2] || g.dims().iter().all(|&n| n >= 1)));
    let h = c.check(
        &Ray::new(v(1.0, 2.0, -5.0), v(0.0, 0.0, 1.0)),
        0.0,
        Real::INFINITY,
    );
    assert_eq!(h.map(|h| h.prim), Some(0));
    random_rays(&c, v(1.0, 2.0, 3.0), 1.0, 300);
    // A single point-sized object: one cell.
    let c = Checker::all(vec![sph(1.0, 2.0, 3.0, 0.0)]);
    assert_eq!(c.grids[0].dims(), [1, 1, 1]);
    random_rays(&c, v(1.0, 2.0, 3.0), 0.5, 100);
}

#[test]
fn empty_scene() {
    for config in all_configs() {
        let g: Grid<Shape> = Grid::build(Vec::new(), &config);
        g.check_invariants().expect("invariants");
        assert_eq!(g.dims(), [0, 0, 0]);
        assert_eq!(g.stats().cells, 0);
        assert!(g.bounds().is_empty());
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let mut s = g.scratch();
        assert_eq!(g.closest_hit(&ray, 0.0, Real::INFINITY, &mut s), None);
        assert!(!g.any_hit(&ray, 0.0, Real::INFINITY, &mut s));
        assert_eq!(g.cells_along(&ray, 0.0, 1.0).count(), 0);
        assert_eq!(g.cell_refs([0, 0, 0]), &[] as &[u32]);
        assert!(g.into_primitives().is_empty());
    }
}

#[test]
fn all_coordinates_negative() {
    let s: Vec<Shape> = lattice_scene()
        .into_iter()
        .map(|p| translate(p, v(-100.0, -50.5, -20.25)))
        .collect();
    let c = Checker::all(s);
    assert!(c.grids[0].bounds().max.max_element() < 0.0);
    random_rays(&c, v(-96.0, -46.5, -16.25), 8.0, 400);
}

#[test]
fn scene_translated_by_1e5() {
    translated_scene(1e5);
}

#[test]
fn scene_translated_by_1e6() {
    translated_scene(1e6);
}

/// Random spheres and triangles around `offset`, large enough that f32 can
/// still tell their surfaces apart there (ulp(1e6) = 1/16).
fn translated_scene(offset: Real) {
    let scale = (offset * 1e-3).max(1.0);
    let mut rng = crate::support::scenes::Lcg::new(11);
    let base = v(offset, -offset, offset * 0.5);
    let s: Vec<Shape> = (0..150)
        .map(|i| {
            let p = base
                + v(
                    rng.range(0.0, 40.0),
                    rng.range(0.0, 40.0),
                    rng.range(0.0, 40.0),
                ) * scale;
            if i % 2 == 0 {
                Shape::Sphere(Sphere::new(p, 3.0 * scale))
            } else {
                let q = p + v(
                    rng.range(-6.0, 6.0),
                    rng.range(-6.0, 6.0),
                    rng.range(-6.0, 6.0),
                ) * scale;
                let r = p + v(
                    rng.range(-6.0, 6.0),
                    rng.range(-6.0, 6.0),
                    rng.range(-6.0, 6.0),
                ) * scale;
                tri(p, q, r)
            }
        })
        .collect();
    let c = Checker::all(s);
    let hits = random_rays(&c, base + Vec3::splat(20.0 * scale), 30.0 * scale, 400);
    assert!(hits > 20, "hits {hits}");
}

#[test]
fn huge_extents() {
    // About a tenth of the largest finite value of the precision.
    let big: Real = Real::MAX / 16.0;
    let s = vec![
        sph(-big, -big, -big, big * 0.1),
        sph(big, big, big, big * 0.1),
        sph(0.0, 0.0, 0.0, big * 0.3),
        sph(big * 0.5, 0.0, -big * 0.5, big * 0.05),
        tri(v(-big, 0.0, big), v(big, 0.0, big), v(0.0, big, -big)),
        // Something tiny in the middle of it all.
        sph(1.0, 1.0, 1.0, 0.5),
    ];
    let c = Checker::all(s);
    random_rays(&c, Vec3::ZERO, big, 300);
    random_rays(&c, v(1.0, 1.0, 1.0), 2.0, 100);
}

#[test]
fn objects_larger_than_the_cells_enclosing_everything() {
    let mut s = vec![
        sph(4.0, 4.0, 4.0, 6.0),
        tri(v(-3.0, -3.0, 4.0), v(11.0, -3.0, 4.0), v(4.0, 11.0, 4.0)),
    ];
    s.extend(lattice_scene());
    let c = Checker::all(s);
    // From inside the enclosing sphere, outwards and through everything.
    random_rays(&c, v(4.0, 4.0, 4.0), 3.0, 400);
}

#[test]
fn denormal_direction_components() {
    // A denormal whose reciprocal overflows to infinity.
    let tiny: Real = Real::MIN_POSITIVE / 1024.0;
    assert!(tiny > 0.0 && !tiny.is_normal());
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let dirs = [
        v(tiny, 0.0, -1.0),
        v(-tiny, tiny, 1.0),
        v(1.0, -tiny, -tiny),
        v(tiny, 1.0, -0.0),
        v(-tiny, -tiny, -1.0),
    ];
    check_all(&c, &lattice_origins(), &dirs, &[(0.0, Real::INFINITY)]);
    // Tiny but normal components whose reciprocals stay finite.
    let small = Real::MIN_POSITIVE * 4.0;
    check_all(
        &c,
        &lattice_origins(),
        &[v(small, 0.0, -1.0), v(1.0, -small, small)],
        &[(0.0, Real::INFINITY)],
    );
}

#[test]
fn t_max_zero_and_t_min_equal_to_t_max() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let mut ranges = vec![
        (0.0, 0.0),
        (-0.0, 0.0),
        (1.0, 1.0),
        (0.5, 0.5),
        (3.0, 3.0),
        (2.0, 1.0),
    ];
    ranges.push((Real::NAN, 1.0));
    ranges.push((0.0, Real::NAN));
    let mut dirs = axis_dirs();
    dirs.push(v(1.0, 1.0, 1.0));
    let hits = check_all(&c, &lattice_origins(), &dirs, &ranges);
    assert!(hits > 0, "point queries on surfaces should hit");
}

#[test]
fn nan_and_infinite_rays_do_not_panic() {
    let c = Checker::new(lattice_scene(), &lattice_configs());
    let bad = [
        Ray::new(v(Real::NAN, 1.0, 1.0), v(1.0, 0.0, 0.0)),
        Ray::new(v(1.0, 1.0, 1.0), v(Real::NAN, 0.0, 1.0)),
        Ray::new(v(Real::INFINITY, 1.0, 1.0), v(-1.0, 0.0, 0.0)),
        Ray::new(v(1.0, 1.0, 1.0), v(Real::INFINITY, 0.0, 0.0)),
        Ray::new(v(1.0, 1.0, 1.0), Vec3::ZERO),
    ];
    for g in &c.grids {
        let mut s = g.scratch();
        for r in &bad {
            let _ = g.closest_hit(r, 0.0, Real::INFINITY, &mut s);
            let _ = g.any_hit(r, 0.0, Real::INFINITY, &mut s);
            assert!(g.cells_along(r, 0.0, Real::INFINITY).count() <= 8 * 3 + 1);
        }
    }
}

/// An infinite plane `y = 0`: its box is infinite, so the grid keeps it aside.
#[derive(Clone, Debug)]
struct Ground;

impl Primitive for Ground {
    type Shared = ();
    type RayData = ();
    type Four = ();
    fn ray_data(_: &Ray) {}
    fn bounds(&self, _: &()) -> Aabb {
        Aabb::new(
            v(-Real::INFINITY, 0.0, -Real::INFINITY),
            v(Real::INFINITY, 0.0, Real::INFINITY),
        )
    }
    fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t_min: Real, t_max: Real) -> Option<PrimHit> {
        let t = -ray.origin.y / ray.dir.y;
        (t >= t_min && t <= t_max).then_some(PrimHit::new(t, 0.0, 0.0))
    }
}

#[derive(Clone, Debug)]
enum WithGround {
    Shape(Shape),
    Ground,
}

impl Primitive for WithGround {
    type Shared = ();
    type RayData = <Shape as Primitive>::RayData;
    type Four = ();
    fn ray_data(ray: &Ray) -> Self::RayData {
        Shape::ray_data(ray)
    }
    fn bounds(&self, _: &()) -> Aabb {
        match self {
            WithGround::Shape(s) => s.bounds(&()),
            WithGround::Ground => Ground.bounds(&()),
        }
    }
    fn closest_hit(
        &self,
        _: &(),
        ray: &Ray,
        data: &Self::RayData,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit> {
        match self {
            WithGround::Shape(s) => s.closest_hit(&(), ray, data, t_min, t_max),
            WithGround::Ground => Ground.closest_hit(&(), ray, &(), t_min, t_max),
        }
    }
}

#[test]
fn unbounded_primitives_are_tested_by_every_query() {
    let mut s: Vec<WithGround> = lattice_scene().into_iter().map(WithGround::Shape).collect();
    s.insert(3, WithGround::Ground);
    let c = Checker::all(s);
    for g in &c.grids {
        assert_eq!(g.unbounded_primitives(), [3]);
        assert_eq!(g.stats().unbounded_prims, 1);
    }
    let mut rng = crate::support::scenes::Lcg::new(5);
    for _ in 0..300 {
        let o = v(
            rng.range(-2.0, 10.0),
            rng.range(-1.0, 10.0),
            rng.range(-2.0, 10.0),
        );
        let d = v(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        c.check(&Ray::new(o, d), 0.0, Real::INFINITY);
    }
}

/// Random rays from points around `center` (within `radius`) in random
/// directions, checked against the exhaustive answer; returns the hits.
fn random_rays<P: Primitive<Shared = ()> + Clone + std::fmt::Debug>(
    c: &Checker<P>,
    center: Vec3,
    radius: Real,
    n: usize,
) -> usize {
    let mut rng = crate::support::scenes::Lcg::new(99);
    let mut hits = 0;
    for i in 0..n {
        let o = center
            + v(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ) * (2.0 * radius);
        let target = center
            + v(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ) * (0.5 * radius);
        let d = target - o;
        let (t0, t1) = if i % 5 == 4 {
            (0.3, 0.9)
        } else {
            (0.0, Real::INFINITY)
        };
        hits += usize::from(c.check(&Ray::new(o, d), t0, t1).is_some());
    }
    hits
}

fn translate(s: Shape, by: Vec3) -> Shape {
    match s {
        Shape::Sphere(p) => Shape::Sphere(Sphere::new(p.center + by, p.radius)),
        Shape::Triangle(t) => {
            let [a, b, c] = t.vertices().map(|p| p + by);
            Shape::Triangle(Triangle::new(a, b, c))
        }
    }
}
