//! The same image whatever the accelerator and the thread count.

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{suffern, AccelKind, RenderOptions, Renderer, Rgb};

#[test]
fn grid_dense_grid_and_exhaustive_are_bit_identical() {
    let scene = kitchen_sink(40, 30);
    let (want, ws) = render_with(&scene, &opts(AccelKind::Exhaustive, Some(2)));
    for accel in [AccelKind::Grid, AccelKind::DenseGrid] {
        let (img, stats) = render_with(&scene, &opts(accel, Some(2)));
        assert!(img == want, "{accel:?} differs from exhaustive");
        assert_eq!(stats.rays, ws.rays);
        assert_eq!(stats.pixels_hit, ws.pixels_hit);
        assert!(stats.grid.is_some());
    }
    assert!(ws.grid.is_none());
    // With mailboxing and exact insertion too.
    let mut o = opts(AccelKind::Grid, Some(2));
    o.grid.mailbox = true;
    o.grid.exact_insertion = true;
    o.grid.m = 3.0;
    let (img, _) = render_with(&scene, &o);
    assert!(img == want, "mailbox + exact insertion differs");
}

#[test]
fn thread_count_does_not_change_the_image() {
    let scene = kitchen_sink(37, 23);
    let (want, ws) = render_with(&scene, &opts(AccelKind::Grid, Some(1)));
    for threads in [Some(2), Some(3), None] {
        let (img, stats) = render_with(&scene, &opts(AccelKind::Grid, threads));
        assert!(img == want, "{threads:?} threads differ from 1");
        assert_eq!(stats.rays, ws.rays);
    }
}

#[test]
fn sphere_set_renders_like_objects() {
    let opts = RenderOptions::default();
    let (a, sa) = render_with(&suffern::scene(300), &opts);
    let r = suffern::renderer(300, suffern::DEFAULT_SEED, &opts).unwrap();
    let (b, sb) = r.render(&|_, _| {}, &Default::default()).unwrap();
    assert!(a == b);
    assert_eq!((sa.rays, sa.pixels_hit), (sb.rays, sb.pixels_hit));
    assert_eq!(r.primitive_count(), 300);
    // Mixed: a sphere set added to a scene with other shapes.
    let mut scene = kitchen_sink(24, 24);
    let base = Renderer::new(&scene, &opts).unwrap();
    let set = gridrt_tracer::SphereSet {
        spheres: suffern::sphere_set(50, 3).spheres,
        colors: gridrt_tracer::SphereColors::None,
    };
    let mut mixed = scene.clone();
    mixed.objects.push(gridrt_tracer::Object {
        geometry: gridrt_tracer::Geometry::Spheres(std::sync::Arc::new(set.clone())),
        material: 0,
    });
    let mixed = Renderer::new(&mixed, &opts).unwrap();
    assert_eq!(mixed.primitive_count(), base.primitive_count() + 50);
    let (img, _) = mixed.render(&|_, _| {}, &Default::default()).unwrap();
    assert_finite(&img);
    for s in &set.spheres {
        object(&mut scene, sphere(s.center, s.radius), 0);
    }
    let (want, _) = render_with(&scene, &opts);
    assert!(img == want);
}

/// A scene of meshes alone: two smooth UV spheres (their poles hold
/// zero-area triangles), one of them glowing (an
/// area light made of triangles), a flat mesh placed twice, a floor plane
/// and a point light with shadows.
fn meshes_only(integrator: gridrt_tracer::IntegratorChoice) -> gridrt_tracer::Scene {
    use gridrt_tracer::{Affine, Geometry, Material, Mesh};
    use std::sync::Arc;
    let mut s = empty_scene(36, 28, Vec3::new(0.5, 1.5, 6.0));
    s.settings.spp = 2;
    s.settings.max_depth = 3;
    s.settings.integrator = integrator;
    let red = material(&mut s, matte(Rgb::new(0.8, 0.2, 0.1), 0.2, 0.8));
    let lamp = material(
        &mut s,
        Material::Emissive {
            color: Rgb::new(1.0, 0.9, 0.7),
            strength: 3.0,
        },
    );
    let ball = |c: Vec3, r: Real| Geometry::Mesh(Arc::new(uv_sphere(c, r, 10, 6)));
    object(&mut s, ball(Vec3::new(-0.8, 0.2, 0.0), 0.7), red);
    object(&mut s, ball(Vec3::new(1.2, 1.6, -1.0), 0.3), lamp);
    let quad = Arc::new(Mesh {
        name: "quad".into(),
        positions: vec![
            Vec3::new(0.0, -0.5, 0.0),
            Vec3::new(1.0, -0.5, 0.0),
            Vec3::new(1.0, 0.5, 0.0),
            Vec3::new(0.0, 0.5, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    });
    for x in [0.3, 1.5] {
        let geometry = Geometry::Instance {
            mesh: Arc::clone(&quad),
            to_world: Box::new(Affine::translation(Vec3::new(x, 0.0, -0.5))),
        };
        object(&mut s, geometry, red);
    }
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::new(0.0, -0.5, 0.0),
            normal: Vec3::Y,
        },
        red,
    );
    s.lights = vec![gridrt_tracer::Light::Point {
        position: Vec3::new(2.0, 4.0, 3.0),
        color: Rgb::ONE,
        intensity: 30.0,
        inverse_square: true,
        shadows: true,
    }];
    s
}

#[test]
fn indexed_triangles_render_like_copies() {
    use gridrt_tracer::{IntegratorChoice, TriangleStorage};
    for integrator in [IntegratorChoice::Whitted, IntegratorChoice::Path] {
        let scene = meshes_only(integrator);
        for accel in [AccelKind::Grid, AccelKind::Exhaustive] {
            // Shared instances make a scene of shapes; baked ones keep it
            // one of triangles alone.
            for instancing in [false, true] {
                let mut o = opts(accel, Some(2));
                o.instancing = instancing;
                let (want, ws) = render_with(&scene, &o);
                o.triangles = TriangleStorage::Indexed;
                // Taking the objects away changes nothing in the image,
                // nor do the mesh arrays it then frees (a scene of its own,
                // so that the renderer holds the only copies).
                let mut taken = meshes_only(integrator);
                let r = Renderer::new_taking_objects(&mut taken, &o).unwrap();
                assert!(taken.objects.is_empty());
                let indexed = format!("{r:?}").contains("indexed triangles");
                assert_eq!(indexed, !instancing, "{accel:?}, instancing {instancing}");
                let (img, stats) = r.render(&|_, _| {}, &Default::default()).unwrap();
                assert!(
                    img == want,
                    "{integrator:?}, {accel:?}, instancing {instancing}"
                );
                assert_eq!(stats.rays, ws.rays);
                assert_eq!(stats.plan.area_lights, ws.plan.area_lights);
            }
        }
    }
}

/// `TriangleStorage::Auto`, the default, stores a mesh scene's triangles
/// indexed from `INDEXED_FROM` triangles on, as copies below it and with
/// the Möller–Trumbore test (as shapes); other scenes keep shapes.
#[test]
fn auto_storage_indexes_large_meshes() {
    use gridrt_tracer::{Geometry, Mesh, Scene, TriangleStorage, TriangleTest, INDEXED_FROM};
    use std::sync::Arc;
    // A flat sheet of `2·k²` triangles facing the camera.
    let sheet = |k: u32| {
        let n = k + 1;
        let positions = (0..n * n)
            .map(|i| {
                Vec3::new(
                    (i % n) as Real / k as Real,
                    (i / n) as Real / k as Real,
                    -1.0,
                )
            })
            .collect();
        let mut triangles = Vec::new();
        for y in 0..k {
            for x in 0..k {
                let v = y * n + x;
                triangles.push([v, v + 1, v + n + 1]);
                triangles.push([v, v + n + 1, v + n]);
            }
        }
        let mut s = empty_scene(4, 4, Vec3::new(0.5, 0.5, 2.0));
        let grey = material(&mut s, matte(Rgb::ONE, 0.2, 0.8));
        let mesh = Mesh {
            name: "sheet".into(),
            positions,
            triangles,
            ..Default::default()
        };
        object(&mut s, Geometry::Mesh(Arc::new(mesh)), grey);
        s
    };
    let storage = |s: &Scene, test: TriangleTest| {
        let mut o = opts(AccelKind::Grid, Some(1));
        o.triangle_test = test;
        assert_eq!(o.triangles, TriangleStorage::Auto);
        Renderer::new(s, &o).unwrap().triangle_storage()
    };
    let k = ((INDEXED_FROM / 2) as f64).sqrt().ceil() as u32;
    let triangles = |k: u32| 2 * (k as usize).pow(2);
    assert!(triangles(k) >= INDEXED_FROM && triangles(k - 1) < INDEXED_FROM);
    let large = sheet(k);
    assert_eq!(
        storage(&large, TriangleTest::Watertight),
        Some(TriangleStorage::Indexed)
    );
    // Möller–Trumbore triangles are copies, held as shapes.
    assert_eq!(storage(&large, TriangleTest::MollerTrumbore), None);
    assert_eq!(
        storage(&sheet(k - 1), TriangleTest::Watertight),
        Some(TriangleStorage::Copies)
    );
    let spheres = suffern::scene_of(suffern::sphere_set(10, suffern::DEFAULT_SEED));
    assert_eq!(storage(&spheres, TriangleTest::Watertight), None);
}
