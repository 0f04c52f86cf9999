//! Numerical hard cases: spheres far away or huge, and self-shadowing.

use crate::common::*;
use gridrt_grid::{Primitive, Ray, Real, Vec3};
use gridrt_tracer::{Geometry, Light, Projection, Rgb, Sphere};

/// Distance from the origin to a unit sphere, far beyond what the textbook
/// `b² − 4ac` survives in `f32`.
#[test]
fn unit_sphere_seen_from_far_away() {
    let s = Sphere::new(Vec3::ZERO, 1.0);
    for dist in [1e3 as Real, 1e4, 3e4] {
        let o = Vec3::new(0.0, 0.0, dist);
        for (h, hit) in [
            (0.0 as Real, true),
            (0.5, true),
            (0.9, true),
            (0.99, true),
            (0.999, true),
            (1.002, false),
            (1.01, false),
            (1.5, false),
        ] {
            let ray = Ray::new(o, Vec3::new(h, 0.0, 0.0) - o);
            let got = s.closest_hit(&(), &ray, &Sphere::ray_data(&ray), 0.0, Real::INFINITY);
            assert_eq!(got.is_some(), hit, "distance {dist}, offset {h}");
            if let Some(g) = got {
                // The exact t in f64.
                #[allow(clippy::unnecessary_cast)]
                let (dd, hh) = (dist as f64, h as f64);
                let (a, b, c) = (hh * hh + dd * dd, -dd * dd, dd * dd - 1.0);
                let t = (-b - (b * b - a * c).sqrt()) / a;
                #[allow(clippy::unnecessary_cast)]
                let rel = (g.t as f64 - t).abs() / t;
                assert!(rel < 4e-6, "distance {dist}, offset {h}: t {} vs {t}", g.t);
                let p = ray.at(g.t);
                assert!((p.length() - 1.0).abs() < 0.05, "{p:?}");
            }
        }
    }
}

#[test]
fn huge_sphere_is_hit_where_it_should_be() {
    for big in [1e4 as Real, 1e5] {
        let s = Sphere::new(Vec3::new(0.0, -big, 0.0), big);
        let o = Vec3::new(0.3, 2.0, -0.7);
        let d = Vec3::new(0.3, -1.0, 0.2);
        let ray = Ray::new(o, d);
        let h = s
            .closest_hit(&(), &ray, &Sphere::ray_data(&ray), 0.0, Real::INFINITY)
            .expect("hits the ground");
        // The top of the sphere is flat to first order: y ≈ 0 at t ≈ 2.
        let p = o + d * h.t;
        assert!(p.y.abs() < 2e-2, "big {big}: {p:?}");
        assert!((h.t - 2.0).abs() < 1e-2, "big {big}: t {}", h.t);
        // A ray skimming above the top misses.
        let skim = Ray::new(Vec3::new(-5.0, 0.01, 0.0), Vec3::X);
        assert!(s
            .closest_hit(&(), &skim, &Sphere::ray_data(&skim), 0.0, 10.0)
            .is_none());
    }
}

/// A lit floor (huge sphere or plane) with shadows on: every visible floor
/// pixel is lit. Shadow acne from a bad ray offset would darken some.
#[test]
fn no_shadow_acne_on_huge_sphere_or_plane() {
    assert_no_shadow_acne(Vec3::ZERO);
}

/// The same scene moved 10⁵ (and 10⁵·√2 in x and z) from the origin, where
/// an `f32` coordinate's ulp is about 0.008: a fixed-epsilon offset would
/// put shadow-ray origins below the floor, the error-bound offset does not.
#[test]
fn no_shadow_acne_far_from_the_origin() {
    assert_no_shadow_acne(Vec3::new(1e5, 0.0, 0.0));
    assert_no_shadow_acne(Vec3::new(1e5, 1e5, 1e5));
}

fn assert_no_shadow_acne(shift: Vec3) {
    for floor in [
        Geometry::Sphere {
            center: Vec3::new(0.0, -1e4, 0.0) + shift,
            radius: 1e4,
        },
        Geometry::Plane {
            point: shift,
            normal: Vec3::Y,
        },
    ] {
        let mut s = empty_scene(48, 32, Vec3::new(0.0, 3.0, 8.0) + shift);
        s.camera.look_at = shift;
        s.camera.projection = Projection::Perspective { vfov_deg: 50.0 };
        let m = material(&mut s, matte(Rgb::splat(0.8), 0.0, 1.0));
        object(&mut s, floor.clone(), m);
        // Something far behind the camera, so that the plan casts shadow rays.
        object(&mut s, sphere(Vec3::new(0.0, 3.0, 40.0) + shift, 0.5), m);
        s.lights = vec![
            directional(Vec3::new(0.3, 1.0, 0.2), 1.0, true),
            Light::Point {
                position: Vec3::new(-2.0, 4.0, 1.0) + shift,
                color: Rgb::ONE,
                intensity: 1.0,
                inverse_square: false,
                shadows: true,
            },
        ];
        let (img, stats) = render(&s);
        assert!(stats.rays.shadow > 0);
        // Lower half of the image is floor (the horizon is above it).
        let mut dark = 0;
        for y in 20..32 {
            for x in 0..48 {
                // Both lights lit: the directional light alone gives ≥ 0.8/π·cos.
                if img.get(x, y).min_element() < 0.2 {
                    dark += 1;
                }
            }
        }
        assert_eq!(
            dark, 0,
            "{floor:?}: {dark} shadowed floor pixels (shift {shift:?})"
        );
        assert_eq!(stats.rays.shadow, 2 * stats.pixels_hit, "{floor:?}");
    }
}
