//! The same image whatever the accelerator and the thread count.

use crate::common::*;
use gridrt_tracer::{suffern, AccelKind, RenderOptions, Renderer};

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
        colors: Vec::new(),
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
