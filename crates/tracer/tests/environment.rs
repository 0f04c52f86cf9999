//! The environment light: a white furnace with an image environment, the
//! closed-form irradiance of a sky above a floor (importance sampling and
//! MIS weighted right) in both integrators, the plan, and Whitted seeing
//! it behind the objects and lighting with it.

use crate::common::{empty_scene, material, matte, object, render, sphere};
use gridrt_grid::Vec3;
use gridrt_tracer::{
    EnvImage, Geometry, IntegratorChoice, IntegratorKind, Light, Projection, Rgb, Scene,
};
use std::sync::Arc;

fn env(w: u32, h: u32, f: impl Fn(u32, u32) -> Rgb) -> Light {
    let mut pixels = Vec::new();
    for r in 0..h {
        for c in 0..w {
            pixels.push(f(c, r));
        }
    }
    Light::Environment {
        color: Rgb::ONE,
        intensity: 1.0,
        image: Some(Arc::new(EnvImage {
            width: w,
            height: h,
            pixels,
        })),
    }
}

fn mean(img: &gridrt_tracer::Framebuffer) -> Rgb {
    img.pixels.iter().copied().sum::<Rgb>() / img.pixels.len() as f32
}

#[test]
fn white_furnace_with_an_image_environment() {
    // An albedo-1 diffuse sphere filling the view inside a uniform image
    // environment of radiance 0.8 renders 0.8 everywhere, within noise.
    let mut s = empty_scene(8, 8, Vec3::new(0.0, 0.0, 3.0));
    s.camera.projection = Projection::Perspective { vfov_deg: 10.0 };
    s.settings.spp = 64;
    let m = material(&mut s, matte(Rgb::ONE, 0.0, 1.0));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    s.lights.push(env(16, 8, |_, _| Rgb::splat(0.8)));
    let (img, stats) = render(&s);
    assert_eq!(stats.plan.integrator, IntegratorKind::Path);
    assert!(stats.plan.env_sampling);
    assert!(stats.rays.light_sample > 0);
    let m = mean(&img);
    assert!((m.x - 0.8).abs() < 0.02 && (m.z - 0.8).abs() < 0.02, "{m}");
}

/// A floor seen from just above through a tiny orthographic window.
fn floor(spp: u32) -> Scene {
    let mut s = empty_scene(4, 4, Vec3::new(0.0, 0.5, 0.0));
    s.camera.up = Vec3::Z;
    s.camera.projection = Projection::Orthographic { height: 1e-3 };
    s.settings.spp = spp;
    let m = material(&mut s, matte(Rgb::ONE, 0.0, 0.5));
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        m,
    );
    s
}

#[test]
fn a_sky_lights_a_floor_with_the_closed_form_radiance() {
    // Radiance L over the upper hemisphere only, with one much brighter
    // patch of known solid angle: the floor's radiance is ρ/π·E with
    // E = ∫ L cos θ dω, computed here from the image's own pixels.
    let (w, h) = (32u32, 16u32);
    let sky = |c: u32, r: u32| {
        if r >= h / 2 {
            Rgb::ZERO
        } else if (20..24).contains(&c) && (3..5).contains(&r) {
            Rgb::splat(40.0)
        } else {
            Rgb::splat(1.0)
        }
    };
    // E = Σ L(pixel) ∫ cos θ sin θ dθ dφ over the pixel.
    let mut e = 0.0f64;
    for r in 0..h {
        let (t0, t1) = (
            f64::from(r) / f64::from(h) * std::f64::consts::PI,
            f64::from(r + 1) / f64::from(h) * std::f64::consts::PI,
        );
        // ∫ cos θ sin θ dθ = (sin² t1 − sin² t0)/2, only above the horizon.
        if t1 > std::f64::consts::FRAC_PI_2 + 1e-9 {
            continue;
        }
        let band = (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0;
        for c in 0..w {
            e += f64::from(sky(c, r).x) * band * 2.0 * std::f64::consts::PI / f64::from(w);
        }
    }
    let want = 0.5 / std::f64::consts::PI * e;
    // A floor under a sky takes direct light only: the Whitted tracer owes
    // the same radiance as the path tracer.
    for integrator in [IntegratorChoice::Auto, IntegratorChoice::Whitted] {
        let mut s = floor(256);
        s.settings.integrator = integrator;
        s.lights.push(env(w, h, sky));
        let (img, stats) = render(&s);
        let got = f64::from(mean(&img).x);
        assert!(stats.plan.env_sampling, "{integrator:?}");
        assert!(
            (got - want).abs() < 0.03 * want,
            "{integrator:?}: {got} vs {want}"
        );
    }
}

#[test]
fn whitted_lights_a_convex_surface_by_a_constant_environment_exactly() {
    // An albedo-1 diffuse sphere filling the view inside a constant
    // environment: a direction cosine-weighted about the normal makes every
    // sample exactly the environment's radiance, and nothing occludes it.
    let mut s = empty_scene(8, 8, Vec3::new(0.0, 0.0, 3.0));
    s.camera.projection = Projection::Perspective { vfov_deg: 10.0 };
    s.settings.integrator = IntegratorChoice::Whitted;
    let m = material(&mut s, matte(Rgb::ONE, 0.0, 1.0));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    s.lights.push(Light::Environment {
        color: Rgb::new(0.2, 0.4, 0.7),
        intensity: 1.0,
        image: None,
    });
    let (img, stats) = render(&s);
    assert_eq!(stats.plan.integrator, IntegratorKind::RayCast);
    assert!(stats.plan.env_sampling && stats.plan.light_sampling);
    assert_eq!(stats.rays.light_sample, 64);
    for p in &img.pixels {
        assert!((p.x - 0.2).abs() < 1e-4 && (p.z - 0.7).abs() < 1e-4, "{p}");
    }
}

#[test]
fn a_constant_environment_is_not_light_sampled_and_whitted_sees_images() {
    let mut s = floor(4);
    s.lights.push(Light::Environment {
        color: Rgb::new(0.2, 0.4, 0.6),
        intensity: 1.0,
        image: None,
    });
    let (img, stats) = render(&s);
    assert!(stats.plan.environment && !stats.plan.env_sampling);
    assert_eq!(stats.rays.light_sample, 0);
    // Uniform sky over the upper hemisphere: radiance ρ·L.
    let m = mean(&img);
    assert!((m.y - 0.5 * 0.4).abs() < 0.05 * 0.2, "{m}");

    // Whitted: the camera looking at the sky sees the image's pixel.
    let mut s = empty_scene(2, 2, Vec3::ZERO);
    s.camera.look_at = Vec3::new(0.0, 0.0, -1.0);
    s.camera.projection = Projection::Perspective { vfov_deg: 1.0 };
    s.settings.integrator = IntegratorChoice::Whitted;
    let m = material(&mut s, matte(Rgb::ONE, 0.0, 1.0));
    object(&mut s, sphere(Vec3::new(0.0, 0.0, 50.0), 1.0), m);
    s.lights.push(env(8, 4, |c, _| Rgb::splat(c as f32)));
    let (img, stats) = render(&s);
    assert_eq!(stats.rays.light_sample, 0);
    assert!(
        img.pixels.iter().all(|p| (3.0..=4.0).contains(&p.x)),
        "{:?}",
        img.pixels
    );
}

#[test]
fn two_environments_are_an_error() {
    let mut s = floor(1);
    s.lights.push(env(2, 1, |_, _| Rgb::ONE));
    s.lights.push(env(2, 1, |_, _| Rgb::ONE));
    let e = gridrt_tracer::render(&s, &Default::default()).unwrap_err();
    assert!(e.to_string().contains("at most one"), "{e}");
    let mut s = floor(1);
    s.lights.push(Light::Environment {
        color: Rgb::ONE,
        intensity: 1.0,
        image: Some(Arc::new(EnvImage {
            width: 2,
            height: 2,
            pixels: vec![Rgb::ONE; 3],
        })),
    });
    let e = gridrt_tracer::render(&s, &Default::default()).unwrap_err();
    assert!(e.to_string().contains("width × height"), "{e}");
}
