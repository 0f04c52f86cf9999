//! Glass: Fresnel reflectance, total internal reflection, Beer's law.

use crate::common::*;
use gridrt_grid::Vec3;
use gridrt_tracer::{Geometry, Material, Projection, Rgb};

fn glass(tint: Rgb) -> Material {
    Material::Dielectric { ior: 1.5, tint }
}

/// A glass slab z ∈ [−1, 0] seen straight on by an orthographic camera.
fn slab_scene(tint: Rgb, max_depth: u32) -> gridrt_tracer::Scene {
    let mut s = empty_scene(8, 8, Vec3::new(0.0, 0.0, 5.0));
    s.camera.projection = Projection::Orthographic { height: 1.0 };
    s.settings.max_depth = max_depth;
    let g = material(&mut s, glass(tint));
    object(
        &mut s,
        Geometry::Cuboid {
            min: Vec3::new(-10.0, -10.0, -1.0),
            max: Vec3::new(10.0, 10.0, 0.0),
        },
        g,
    );
    s
}

#[test]
fn normal_incidence_reflects_f0() {
    // Reflected rays go back up (+z) to a lamp behind the camera; the
    // refracted ray's next hit is at max depth, so it adds nothing.
    let mut s = slab_scene(Rgb::ONE, 1);
    let lamp = material(
        &mut s,
        Material::Emissive {
            color: Rgb::new(1.0, 0.5, 0.25),
            strength: 1.0,
        },
    );
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::new(0.0, 0.0, 10.0),
            normal: -Vec3::Z,
        },
        lamp,
    );
    let (img, stats) = render(&s);
    let f0 = ((1.5f32 - 1.0) / (1.5 + 1.0)).powi(2);
    for p in &img.pixels {
        assert!(
            (*p - Rgb::new(1.0, 0.5, 0.25) * f0).abs().max_element() < 1e-6,
            "{p:?} vs F0 = {f0}"
        );
    }
    assert_eq!(stats.rays.reflection, 64);
    assert_eq!(stats.rays.refraction, 64);
}

#[test]
fn beer_law_through_the_slab() {
    // Lamp below the slab: in through the top, out through the bottom,
    // (1 − F0)² of the light, times the tint for one unit of glass.
    let tint = Rgb::new(0.5, 0.25, 1.0);
    let mut s = slab_scene(tint, 2);
    let lamp = material(
        &mut s,
        Material::Emissive {
            color: Rgb::ONE,
            strength: 1.0,
        },
    );
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::new(0.0, 0.0, -5.0),
            normal: Vec3::Z,
        },
        lamp,
    );
    let (img, _) = render(&s);
    let f0 = ((1.5f32 - 1.0) / (1.5 + 1.0)).powi(2);
    let want = tint * (1.0 - f0) * (1.0 - f0);
    for p in &img.pixels {
        assert!((*p - want).abs().max_element() < 1e-5, "{p:?} vs {want:?}");
    }
}

#[test]
fn total_internal_reflection_inside_a_glass_cube() {
    // The camera sits inside a glass cube and looks along (1, 1, 1): every
    // face is met at cos θ = 1/√3 < √(1 − 1/1.5²), beyond the critical
    // angle, so every bounce is a total internal reflection and no ray ever
    // refracts out.
    let mut s = empty_scene(3, 3, Vec3::new(0.1, 0.05, 0.0));
    s.camera.look_at = s.camera.eye + Vec3::new(1.0, 1.0, 1.0);
    s.camera.projection = Projection::Orthographic { height: 0.01 };
    s.settings.max_depth = 6;
    s.settings.background = Rgb::ONE;
    let g = material(&mut s, glass(Rgb::ONE));
    object(
        &mut s,
        Geometry::Cuboid {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        },
        g,
    );
    let (img, stats) = render(&s);
    assert_eq!(stats.rays.refraction, 0);
    assert_eq!(stats.rays.reflection, 9 * 6);
    // Trapped light: nothing reaches the camera.
    assert!(img.pixels.iter().all(|p| *p == Rgb::ZERO));
}

#[test]
fn glass_sphere_renders_finite_and_uses_both_rays() {
    let mut s = empty_scene(32, 32, Vec3::new(0.0, 0.0, 5.0));
    s.settings.background = Rgb::new(0.3, 0.6, 0.9);
    let g = material(&mut s, glass(Rgb::new(0.9, 1.0, 0.9)));
    object(&mut s, sphere(Vec3::ZERO, 1.0), g);
    let (img, stats) = render(&s);
    assert!(stats.rays.refraction > 0 && stats.rays.reflection > 0);
    // Glass passes most of the sky through: no pixel is black.
    assert!(img.pixels.iter().all(|p| p.max_element() > 0.05));
}
