//! Property tests: on random and adversarial scenes the grid returns exactly
//! the exhaustive answer (same primitive, bitwise-equal t, u, v) for every
//! ray — hashed and dense, mailbox on and off, exact insertion on and off,
//! for closest hit and any hit (and each hit's slot holds the primitive hit). Case counts are modest so the suite stays fast.

use crate::support::prims::{Shape, Sphere, Triangle};
use crate::support::{all_configs, same, Checker};
use gridrt_grid::{GridConfig, Ray, Real, Vec3};
use proptest::prelude::*;

/// `cases` cases, or `PROPTEST_CASES` when set (for a long soak run).
/// A failing case is kept (proptest's default persistence) in
/// `proptest-regressions/equivalence.txt` beside `tests/` and run first
/// from then on, so that a rare failure is never lost with a run's output.
fn cfg(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        ..ProptestConfig::default()
    }
}

fn vec3(c: impl Strategy<Value = Real> + Clone) -> impl Strategy<Value = Vec3> {
    (c.clone(), c.clone(), c).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn cont() -> impl Strategy<Value = Real> + Clone {
    -4.0 as Real..4.0
}

/// Integers and half-integers in `[−4, 4]`: on the cell planes of 8³ and 16³ grids over `[−4, 4]³`.
fn lattice() -> impl Strategy<Value = Real> + Clone {
    (-8i32..=8).prop_map(|i| i as Real * 0.5)
}

/// A direction component that is often exactly zero (of either sign).
fn dir_comp() -> impl Strategy<Value = Real> + Clone {
    prop_oneof![
        3 => -1.0 as Real..1.0,
        1 => Just(0.0 as Real),
        1 => Just(-0.0 as Real),
        1 => prop::sample::select(vec![1.0 as Real, -1.0, 2.0, -0.5]),
    ]
}

fn direction() -> impl Strategy<Value = Vec3> {
    vec3(dir_comp()).prop_filter("non-zero direction", |d| d.length_squared() > 1e-6)
}

fn sphere(
    c: impl Strategy<Value = Real> + Clone,
    radii: impl Strategy<Value = Real>,
) -> impl Strategy<Value = Shape> {
    (vec3(c), radii).prop_map(|(p, r)| Shape::Sphere(Sphere::new(p, r)))
}

fn triangle(c: impl Strategy<Value = Real> + Clone) -> impl Strategy<Value = Shape> {
    (vec3(c.clone()), vec3(c.clone()), vec3(c))
        .prop_map(|(a, b, c)| Shape::Triangle(Triangle::new(a, b, c)))
}

/// Triangles over a small pool of lattice points: many shared edges and vertices.
fn fan(pool: Vec<Vec3>, n: usize) -> impl Strategy<Value = Vec<Shape>> {
    let k = pool.len();
    prop::collection::vec((0..k, 0..k, 0..k), 1..n).prop_map(move |ix| {
        ix.into_iter()
            .filter(|(a, b, c)| a != b && b != c && a != c)
            .map(|(a, b, c)| Shape::Triangle(Triangle::new(pool[a], pool[b], pool[c])))
            .collect()
    })
}

/// Rays: an origin, a direction and a range.
fn rays(
    origin: impl Strategy<Value = Real> + Clone,
    n: usize,
) -> impl Strategy<Value = Vec<(Vec3, Vec3, Real, Real)>> {
    let range = prop_oneof![
        3 => Just((0.0 as Real, Real::INFINITY)),
        1 => (0.0 as Real..3.0, 0.0 as Real..6.0).prop_map(|(a, b)| (a, a + b)),
        1 => (0.0 as Real..4.0).prop_map(|a| (a, a)),
    ];
    prop::collection::vec((vec3(origin), direction(), range), n)
        .prop_map(|v| v.into_iter().map(|(o, d, (a, b))| (o, d, a, b)).collect())
}

/// Checks every ray on the scene. A scene of spheres only, or of triangles
/// only, is checked as `Sphere`s or `Triangle`s too, which test four at a
/// time (`Primitive::closest_hits`), against the `Shape`s' answers, which
/// test one at a time.
fn run(scene: Vec<Shape>, configs: &[GridConfig], rays: &[(Vec3, Vec3, Real, Real)]) {
    /// The scene as `T`s, when every shape is one.
    fn all<T>(scene: &[Shape], f: impl Fn(&Shape) -> Option<T>) -> Option<Vec<T>> {
        scene.iter().map(f).collect()
    }
    let as_sphere = |s: &Shape| match s {
        Shape::Sphere(s) => Some(*s),
        Shape::Triangle(_) => None,
    };
    let as_triangle = |s: &Shape| match s {
        Shape::Triangle(t) => Some(*t),
        Shape::Sphere(_) => None,
    };
    let sphere_lanes = all(&scene, as_sphere).map(|v| Checker::new(v, configs));
    let tri_lanes = all(&scene, as_triangle)
        .filter(|v| !v.is_empty())
        .map(|v| Checker::new(v, configs));
    let c = Checker::new(scene, configs);
    for &(o, d, t0, t1) in rays {
        // The ray, and the same line from far away, through the scene.
        for (ray, t0, t1) in [
            (Ray::new(o, d), t0, t1),
            (Ray::new(o - d * 7.0, d), 0.0, Real::INFINITY),
        ] {
            let want = c.check(&ray, t0, t1);
            let got = [
                sphere_lanes.as_ref().map(|l| l.check(&ray, t0, t1)),
                tri_lanes.as_ref().map(|l| l.check(&ray, t0, t1)),
            ];
            for got in got.into_iter().flatten() {
                assert!(
                    same(&got, &want),
                    "four at a time: {got:?}, one at a time: {want:?}"
                );
            }
        }
    }
}

/// Two small triangles that pin the grid box to exactly `[−4, 4]³`.
fn pins() -> Vec<Shape> {
    let t = |a: Real, b: Real| {
        Shape::Triangle(Triangle::new(
            Vec3::splat(a),
            Vec3::new(a, a, b),
            Vec3::new(b, a, a),
        ))
    };
    vec![t(-4.0, -3.5), t(4.0, 3.5)]
}

/// All configs, over the automatic resolution and 8³ and 16³ grids whose
/// cell planes are the (half-)integers of `[−4, 4]`.
fn aligned_configs() -> Vec<GridConfig> {
    let mut v = all_configs();
    for d in [8, 16] {
        v.extend(all_configs().into_iter().map(|c| GridConfig {
            dims: Some([d, d, d]),
            ..c
        }));
    }
    v
}

proptest! {
    #![proptest_config(cfg(40))]

    #[test]
    fn random_spheres_and_triangles(
        spheres in prop::collection::vec(sphere(cont(), 0.01 as Real..1.5), 0..30),
        tris in prop::collection::vec(triangle(cont()), 0..30),
        rays in rays(-6.0 as Real..6.0, 30),
    ) {
        let mut scene = spheres;
        scene.extend(tris);
        run(scene, &all_configs(), &rays);
    }

    #[test]
    fn spheres_only_tested_four_at_a_time(
        random in prop::collection::vec(sphere(cont(), 0.01 as Real..1.5), 1..30),
        lattice in prop::collection::vec(sphere(lattice(), prop::sample::select(vec![0.5 as Real, 1.0, 0.0])), 0..20),
        rays in rays(-6.0 as Real..6.0, 30),
    ) {
        let mut scene = random;
        scene.extend(lattice);
        run(scene, &all_configs(), &rays);
    }

    #[test]
    fn integer_coordinates_hits_on_cell_planes(
        spheres in prop::collection::vec(sphere(lattice(), prop::sample::select(vec![0.5 as Real, 1.0, 0.0])), 0..20),
        tris in prop::collection::vec(triangle(lattice()), 0..25),
        rays in rays(lattice(), 30),
    ) {
        // Keep everything inside [−4, 4]³ so the pins fix the grid box.
        let mut scene = pins();
        scene.extend(spheres.into_iter().filter(|s| match s {
            Shape::Sphere(s) => (s.center.abs() + Vec3::splat(s.radius)).max_element() <= 4.0,
            Shape::Triangle(_) => true,
        }));
        scene.extend(tris);
        run(scene, &aligned_configs(), &rays);
    }

    #[test]
    fn shared_edges_and_vertices(
        tris in fan(
            (0..27).map(|i| Vec3::new((i % 3) as Real * 4.0 - 4.0, ((i / 3) % 3) as Real * 4.0 - 4.0, (i / 9) as Real * 4.0 - 4.0)).collect(),
            40,
        ),
        rays in rays(lattice(), 40),
    ) {
        let mut scene = pins();
        scene.extend(tris);
        run(scene, &aligned_configs(), &rays);
    }

    #[test]
    fn meshes_of_quads_on_cell_planes(
        cells in prop::collection::vec((-4i32..4, -4i32..4, -4i32..=4, 0usize..3), 1..30),
        rays in rays(lattice(), 40),
    ) {
        // Unit quads (two triangles sharing a diagonal) lying in the planes x, y or z = integer.
        let mut scene = pins();
        for (a, b, c, axis) in cells {
            let p = |u: i32, w: i32| {
                let mut q = [u as Real, w as Real, c as Real];
                q.rotate_right(axis);
                Vec3::from_array(q.map(|x| x as _))
            };
            scene.push(Shape::Triangle(Triangle::new(p(a, b), p(a + 1, b), p(a + 1, b + 1))));
            scene.push(Shape::Triangle(Triangle::new(p(a, b), p(a + 1, b + 1), p(a, b + 1))));
        }
        run(scene, &aligned_configs(), &rays);
    }
}

proptest! {
    #![proptest_config(cfg(12))]

    #[test]
    fn clustered_scenes_teapot_in_a_stadium(
        small in prop::collection::vec(sphere(-0.05 as Real..0.05, 0.001 as Real..0.01), 1..60),
        big in prop::collection::vec(triangle(-40.0 as Real..40.0), 1..6),
        rays in rays(-0.1 as Real..0.1, 30),
    ) {
        let mut scene = big;
        scene.extend(small);
        run(scene, &all_configs(), &rays);
    }
}

/// A zero-area triangle (three collinear lattice points) that a ray
/// crosses, found by `shared_edges_and_vertices` in `f64`: two of its
/// edge functions round to zero, and only their exact signs put the hit
/// where the ray crosses it (t = 7) rather than at a vertex's depth.
#[test]
#[allow(clippy::excessive_precision)] // the f64 ray of the case (rounded in f32)
fn a_ray_through_a_zero_area_triangle() {
    let v = |x: Real, y: Real, z: Real| Vec3::new(x, y, z);
    let mut scene = pins();
    scene.push(Shape::Triangle(Triangle::new(
        v(0.0, 0.0, 0.0),
        v(0.0, 4.0, -4.0),
        v(0.0, -4.0, 4.0),
    )));
    scene.push(Shape::Triangle(Triangle::new(
        v(-4.0, -4.0, 0.0),
        v(-4.0, -4.0, -4.0),
        v(4.0, 0.0, 4.0),
    )));
    let rays = [(
        v(5.601734542429038, -6.978210308029009, -2.0286462409218466),
        v(-0.8002477917755769, 0.8540300440041442, 0.43266374870312097),
        0.0,
        Real::INFINITY,
    )];
    run(scene, &aligned_configs(), &rays);
}
