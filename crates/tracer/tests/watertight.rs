//! Rays through shared edges and vertices of a mesh never fall through.

use gridrt_grid::{Accelerator, Exhaustive, Grid, GridConfig, Ray, Real, Vec3};
use gridrt_tracer::Triangle;

/// A bumpy height field: an `n × n` grid of quads in [0, 1]², each split in
/// two, with heights on a 1/64 grid so that every sum below is exact.
fn height_field(n: u32) -> (Vec<Vec3>, Vec<Triangle>) {
    let v = |i: u32, j: u32| {
        Vec3::new(
            i as Real / n as Real,
            j as Real / n as Real,
            ((i * 7 + j * 3) % 5) as Real / 64.0,
        )
    };
    let mut tris = Vec::new();
    let mut targets = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            // Alternate the diagonal so that vertices have 4, 6 or 8 triangles.
            if (i + j) % 2 == 0 {
                tris.push(Triangle::new(a, b, c));
                tris.push(Triangle::new(a, c, d));
            } else {
                tris.push(Triangle::new(a, b, d));
                tris.push(Triangle::new(b, c, d));
            }
        }
    }
    // Interior vertices, and midpoints of interior edges (exact: the
    // coordinates are on a 1/128 grid).
    for i in 1..n {
        for j in 1..n {
            let p = v(i, j);
            targets.push(p);
            let mut ends = vec![v(i + 1, j), v(i, j + 1)];
            if (i + j) % 2 == 0 {
                // The diagonals that are edges: of quads (i, j) and (i − 1, j).
                ends.extend([v(i + 1, j + 1), v(i - 1, j + 1)]);
            }
            for q in ends {
                targets.push((p + q) * 0.5);
            }
        }
    }
    (targets, tris)
}

/// A fan of triangles around a centre, rim vertices on a 1/64 grid.
fn fan(k: u32) -> (Vec<Vec3>, Vec<Triangle>) {
    let c = Vec3::new(0.5, 0.5, 0.25);
    let rim: Vec<Vec3> = (0..k)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / f64::from(k);
            let q = |x: f64| ((x * 64.0).round() / 64.0) as Real;
            Vec3::new(
                q(0.5 + 0.4 * a.cos()),
                q(0.5 + 0.4 * a.sin()),
                q(0.25 + 0.1 * (3.0 * a).sin()),
            )
        })
        .collect();
    let tris = (0..k as usize)
        .map(|i| Triangle::new(c, rim[i], rim[(i + 1) % k as usize]))
        .collect();
    let mut targets = vec![c];
    for r in &rim {
        targets.push((c + *r) * 0.5);
        targets.push(c + (*r - c) * 0.25);
    }
    (targets, tris)
}

/// Directions on a 1/8 grid (so `target + d` is exact).
fn directions() -> Vec<Vec3> {
    let mut v = Vec::new();
    for d in [
        [0.0, 0.0, 1.0],
        [0.25, 0.125, 1.0],
        [-0.375, 0.5, 0.75],
        [1.0, -0.25, 0.5],
        [0.5, 1.0, 0.125],
        [-0.125, -1.0, 0.25],
    ] {
        let d = Vec3::new(d[0], d[1], d[2]);
        v.push(d);
        v.push(Vec3::new(d.x, d.y, -d.z));
    }
    v
}

fn check<A: Accelerator>(name: &str, accel: &A, targets: &[Vec3]) {
    let mut scratch = accel.scratch();
    let mut rays = 0;
    for &t in targets {
        for d in directions() {
            // The ray passes exactly through the target at t = 1.
            let ray = Ray::new(t + d, -d);
            assert_eq!(ray.origin - d, t);
            let hit = accel.closest_hit(&ray, 0.0, Real::INFINITY, &mut scratch);
            assert!(
                hit.is_some(),
                "{name}: fell through at {t:?} along {:?}",
                -d
            );
            // The hit at the target is at t = 1 up to rounding; anything nearer
            // is another part of the surface in front of it.
            assert!(
                hit.is_some_and(|h| h.t <= 1.0 + 1e-5 && h.u.is_finite() && h.v.is_finite()),
                "{name}: {hit:?} at {t:?} along {:?}",
                -d
            );
            rays += 1;
        }
    }
    assert!(rays > 100);
}

#[test]
fn height_field_has_no_cracks() {
    let (targets, tris) = height_field(16);
    check("exhaustive", &Exhaustive::new(tris.clone()), &targets);
    check("grid", &Grid::build(tris, &GridConfig::default()), &targets);
}

#[test]
fn fan_has_no_cracks() {
    let (targets, tris) = fan(64);
    check("exhaustive", &Exhaustive::new(tris.clone()), &targets);
    let config = GridConfig {
        exact_insertion: true,
        ..GridConfig::default()
    };
    check("grid", &Grid::build(tris, &config), &targets);
}
