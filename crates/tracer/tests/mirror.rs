//! Perfect mirrors reflect a known colour.

use crate::common::*;
use gridrt_grid::Vec3;
use gridrt_tracer::{Geometry, Material, Projection, Rgb};

fn mirror(kr: f32, reflect: Rgb) -> Material {
    Material::Reflective {
        color: Rgb::ZERO,
        ka: 0.0,
        kd: 0.0,
        ks: 0.0,
        exp: 1.0,
        kr,
        reflect,
    }
}

#[test]
fn mirror_plane_shows_the_emitter_above() {
    // Looking straight down at a mirror floor; the reflected rays go up and
    // hit a lamp that the camera rays (going down) never meet.
    let mut s = empty_scene(16, 16, Vec3::new(0.0, 5.0, 0.0));
    s.camera.up = Vec3::Z;
    s.camera.projection = Projection::Orthographic { height: 2.0 };
    let m = material(&mut s, mirror(0.8, Rgb::new(1.0, 0.5, 0.25)));
    let lamp = material(
        &mut s,
        Material::Emissive {
            color: Rgb::new(0.5, 1.0, 1.0),
            strength: 2.0,
        },
    );
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        m,
    );
    object(&mut s, sphere(Vec3::new(0.0, 9.0, 0.0), 3.0), lamp);
    let (img, stats) = render(&s);
    assert!(stats.plan.reflection && !stats.plan.refraction);
    assert_eq!(stats.rays.reflection, 256);
    let want = Rgb::new(1.0, 0.5, 0.25) * 0.8 * (Rgb::new(0.5, 1.0, 1.0) * 2.0);
    for p in &img.pixels {
        assert!((*p - want).abs().max_element() < 1e-6, "{p:?} vs {want:?}");
    }
}

#[test]
fn mirror_sphere_reflects_the_background_and_its_neighbour() {
    let mut s = empty_scene(32, 32, Vec3::new(0.0, 0.0, 6.0));
    s.settings.background = Rgb::new(0.2, 0.4, 0.6);
    s.settings.max_depth = 1;
    let m = material(&mut s, mirror(1.0, Rgb::ONE));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    let (img, stats) = render(&s);
    // A lone mirror ball in a uniform sky is the sky colour everywhere.
    for p in &img.pixels {
        assert!(
            (*p - Rgb::new(0.2, 0.4, 0.6)).abs().max_element() < 1e-6,
            "{p:?}"
        );
    }
    assert_eq!(stats.rays.reflection, stats.pixels_hit);
    assert!(stats.pixels_hit > 50);
    // Two mirrors facing each other: depth is capped by max_depth.
    object(&mut s, sphere(Vec3::new(0.0, 0.0, 3.0), 0.5), m);
    s.settings.max_depth = 3;
    let (_, stats) = render(&s);
    assert!(stats.rays.reflection <= 3 * stats.pixels_hit);
}
