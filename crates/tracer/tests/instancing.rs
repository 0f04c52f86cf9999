//! Instances: meshes placed many times share one copy of their arrays and
//! one grid, and render as their world-space copies do.

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{AccelKind, Affine, Geometry, Mesh, RenderOptions, Renderer, Scene};
use std::sync::Arc;

/// A rotation by `deg` about y, scaled by `s`, moved by `t`; mirrored in x
/// when `mirror`.
fn placement(deg: f64, s: Real, t: Vec3, mirror: bool) -> Affine {
    let (sin, cos) = deg.to_radians().sin_cos();
    let (sin, cos) = (sin as Real * s, cos as Real * s);
    let flip = if mirror { -1.0 } else { 1.0 };
    Affine {
        cols: [
            Vec3::new(cos, 0.0, -sin) * flip,
            Vec3::new(0.0, s, 0.0),
            Vec3::new(sin, 0.0, cos),
        ],
        translation: t,
    }
}

/// `m` carried to world space by `a`, as a loader that bakes transforms
/// would: positions, normals by the inverse transpose, winding reversed
/// under a mirror.
fn baked(m: &Mesh, a: &Affine) -> Mesh {
    let inv = a.inverse().expect("invertible");
    let mut out = m.clone();
    for p in &mut out.positions {
        *p = a.point(*p);
    }
    for n in &mut out.normals {
        *n = inv.transpose_vector(*n).normalize();
    }
    if a.determinant() < 0.0 {
        for t in &mut out.triangles {
            t.swap(1, 2);
        }
    }
    out
}

/// A lit scene of `placements` of one mesh: shared instances, or baked
/// copies when `bake`.
fn scene_of(mesh: &Arc<Mesh>, placements: &[Affine], bake: bool) -> Scene {
    let mut s = empty_scene(64, 48, Vec3::new(0.0, 4.0, 9.0));
    let m = material(
        &mut s,
        matte(gridrt_tracer::Rgb::new(0.8, 0.6, 0.4), 0.2, 0.8),
    );
    for a in placements {
        let geometry = if bake {
            Geometry::Mesh(Arc::new(baked(mesh, a)))
        } else {
            Geometry::Instance {
                mesh: Arc::clone(mesh),
                to_world: Box::new(*a),
            }
        };
        object(&mut s, geometry, m);
    }
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            normal: Vec3::Y,
        },
        m,
    );
    s.lights
        .push(directional(Vec3::new(-1.0, 2.0, 1.5), 1.0, true));
    s.lights.push(ambient(0.3));
    s
}

fn nine_placements() -> Vec<Affine> {
    let mut v = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            let t = Vec3::new(2.5 * (i as Real - 1.0), 0.0, 2.5 * (j as Real - 1.0));
            let k = 3 * i + j;
            v.push(placement(
                37.0 * k as f64,
                0.6 + 0.1 * j as Real,
                t,
                k % 4 == 1,
            ));
        }
    }
    v
}

#[test]
fn shared_instances_render_like_their_baked_copies() {
    let mesh = Arc::new(uv_sphere(Vec3::new(0.2, 0.0, 0.0), 1.0, 24, 16));
    let places = nine_placements();
    let shared = scene_of(&mesh, &places, false);
    let r = Renderer::new(&shared, &Default::default()).unwrap();
    assert_eq!(r.instancing().shared_meshes, 1);
    assert_eq!(r.instancing().instances, 9);
    let (a, _) = render(&shared);
    let (b, _) = render(&scene_of(&mesh, &places, true));
    let differ = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (**p - **q).abs().max_element() > 1e-3)
        .count();
    // Only pixels whose ray grazes a silhouette or a shadow edge may differ
    // (the transform rounds the ray differently from the baked vertices).
    assert!(differ * 100 <= a.pixels.len(), "{differ} pixels differ");
    // Instancing switched off bakes every placement: the same picture.
    let off = RenderOptions {
        instancing: false,
        ..RenderOptions::default()
    };
    assert_eq!(
        Renderer::new(&shared, &off).unwrap().instancing().instances,
        0
    );
    let (c, _) = render_with(&shared, &off);
    assert_eq!(c.pixels, b.pixels);
    let lit = a.pixels.iter().filter(|p| p.max_element() > 0.05).count();
    assert!(lit * 2 > a.pixels.len(), "the spheres and floor show");
}

#[test]
fn the_scene_grid_over_instances_equals_exhaustive() {
    let mesh = Arc::new(uv_sphere(Vec3::ZERO, 1.0, 12, 8));
    let shared = scene_of(&mesh, &nine_placements(), false);
    let (g, _) = render_with(&shared, &opts(AccelKind::Grid, Some(1)));
    let (e, _) = render_with(&shared, &opts(AccelKind::Exhaustive, Some(1)));
    assert_eq!(g.pixels, e.pixels);
    let (two, _) = render_with(&shared, &opts(AccelKind::Grid, Some(2)));
    assert_eq!(g.pixels, two.pixels);
}

#[test]
fn a_mesh_placed_once_is_baked_into_the_scene_grid() {
    let mesh = Arc::new(uv_sphere(Vec3::ZERO, 1.0, 12, 8));
    let s = scene_of(&mesh, &nine_placements()[..1], false);
    let r = Renderer::new(&s, &Default::default()).unwrap();
    assert_eq!(r.instancing().instances, 0);
    assert_eq!(r.grid_stats().map(|g| g.references > 100), Some(true));
}

#[test]
fn two_thousand_instances_of_a_100k_triangle_mesh_cost_little_more_than_one() {
    // 2 × 250 × 200 = 100,000 triangles.
    let mesh = Arc::new(uv_sphere(Vec3::ZERO, 1.0, 250, 200));
    assert_eq!(mesh.triangles.len(), 100_000);
    let grid_of = |n: usize| -> Vec<Affine> {
        (0..n)
            .map(|k| {
                let (i, j) = ((k % 50) as Real, (k / 50) as Real);
                placement(k as f64, 0.4, Vec3::new(i - 25.0, 0.0, -j), false)
            })
            .collect()
    };
    let few = scene_of(&mesh, &grid_of(2), false);
    let many = scene_of(&mesh, &grid_of(2000), false);
    let r2 = Renderer::new(&few, &Default::default()).unwrap();
    let r2000 = Renderer::new(&many, &Default::default()).unwrap();
    assert_eq!(r2000.instancing().shared_meshes, 1);
    assert_eq!(r2000.instancing().instances, 2000);
    // The mesh's arrays exist once: the test's handle, the two scenes'
    // placements, and each renderer's shared grid and shading data all
    // point at them.
    assert_eq!(Arc::strong_count(&mesh), 1 + 2 + 2000 + 2 + 2);
    let (one, all) = (r2.instancing().bytes, r2000.instancing().bytes);
    // 100,000 triangles copied 2,000 times would take gigabytes; the
    // shared grid is paid once and each placement costs a few hundred bytes.
    assert!(all <= one + 2000 * 512, "{one} bytes for 2, {all} for 2000");
    let scene_grid = r2000.grid_stats().expect("a grid").bytes;
    assert!(scene_grid < one, "scene grid {scene_grid} bytes");
    let never = std::sync::atomic::AtomicBool::new(false);
    let (img, stats) = r2000.render(&|_, _| {}, &never).unwrap();
    assert_finite(&img);
    assert!(stats.rays.camera > 0);
    assert!(img.pixels.iter().filter(|p| p.max_element() > 0.05).count() > 100);
}
