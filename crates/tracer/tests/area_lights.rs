//! Rectangle, disk and spot lights: closed-form irradiance under both
//! integrators, soft shadows in the Whitted tracer, one-sided emission,
//! cones, and zero light-sample rays for scenes without area lights.

use crate::common::{empty_scene, material, matte, object, render, sphere};
use gridrt_grid::Vec3;
use gridrt_tracer::{Geometry, IntegratorChoice, Light, Material, Projection, Rgb, Scene};

/// A white diffuse floor (albedo `RHO`) at y = 0 seen from straight above
/// through a tiny orthographic window around the origin, so every pixel
/// shows (almost) the point below the light's centre.
const RHO: f32 = 0.5;

fn floor_scene(integrator: IntegratorChoice, spp: u32) -> Scene {
    // The camera sits between the floor and the lights above it.
    let mut s = empty_scene(4, 4, Vec3::new(0.0, 0.5, 0.0));
    s.camera.up = Vec3::Z;
    s.camera.projection = Projection::Orthographic { height: 1e-3 };
    s.settings.spp = spp;
    s.settings.integrator = integrator;
    let m = material(&mut s, matte(Rgb::ONE, 0.0, RHO));
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

fn mean(img: &gridrt_tracer::Framebuffer) -> f32 {
    img.pixels.iter().map(|p| p.x).sum::<f32>() / img.pixels.len() as f32
}

/// A disk of radius `r` at height `h` facing down lights the point below
/// its centre with E = π·L·r²/(r² + h²): the floor's radiance is ρ/π·E.
fn disk_light(l: f32) -> Light {
    Light::Disk {
        center: Vec3::new(0.0, 1.0, 0.0),
        normal: Vec3::NEG_Y,
        radius: 0.5,
        color: Rgb::ONE,
        intensity: l,
    }
}

#[test]
fn a_disk_light_gives_the_closed_form_radiance_under_both_integrators() {
    let want = RHO * 2.0 * 0.25 / 1.25;
    for integrator in [IntegratorChoice::Whitted, IntegratorChoice::Path] {
        let mut s = floor_scene(integrator, 256);
        s.lights.push(disk_light(2.0));
        let (img, stats) = render(&s);
        let got = mean(&img);
        assert!(
            (got - want).abs() < 0.03 * want,
            "{integrator:?}: {got} vs {want}"
        );
        assert!(stats.rays.light_sample > 0);
        assert_eq!(stats.rays.shadow, 0);
    }
}

#[test]
fn a_rect_light_gives_the_closed_form_radiance() {
    // A square of side 2 at height 1 centred above the point; its
    // irradiance E = ∫ L·cos θ·cos θ_l / r² dA by a fine midpoint sum.
    let (a, h, l) = (1.0f64, 1.0f64, 1.5f64);
    let n = 600;
    let mut e = 0.0;
    for i in 0..n {
        for j in 0..n {
            let x = -a + 2.0 * a * (f64::from(i) + 0.5) / f64::from(n);
            let z = -a + 2.0 * a * (f64::from(j) + 0.5) / f64::from(n);
            let r2 = x * x + z * z + h * h;
            e += l * h * h / (r2 * r2) * (4.0 * a * a) / f64::from(n * n);
        }
    }
    let want = f64::from(RHO) * e / std::f64::consts::PI;
    let mut s = floor_scene(IntegratorChoice::Path, 256);
    // Edges +x then +z: x × z = −y, facing down.
    s.lights.push(Light::Rect {
        corner: Vec3::new(-1.0, 1.0, -1.0),
        edge_u: Vec3::new(2.0, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 2.0),
        color: Rgb::ONE,
        intensity: l as f32,
    });
    let got = f64::from(mean(&render(&s).0));
    assert!((got - want).abs() < 0.03 * want, "{got} vs {want}");
}

#[test]
fn a_light_facing_away_lights_nothing_and_shows_its_black_back() {
    let mut s = floor_scene(IntegratorChoice::Whitted, 4);
    let mut up = disk_light(2.0);
    if let Light::Disk { normal, .. } = &mut up {
        *normal = Vec3::Y;
    }
    s.lights.push(up);
    // The floor is lit by nothing; a camera above the disk sees its front.
    s.camera.eye = Vec3::new(0.0, 5.0, 0.0);
    let (img, _) = render(&s);
    assert!(
        img.pixels.iter().all(|p| (p.x - 2.0).abs() < 1e-4),
        "front seen"
    );
    s.camera.eye = Vec3::new(0.0, 0.5, 0.0);
    s.camera.look_at = Vec3::new(0.0, 5.0, 0.0);
    let (img, _) = render(&s);
    assert!(img.pixels.iter().all(|p| p.x == 0.0), "back is black");
}

#[test]
fn whitted_area_lights_cast_soft_shadows() {
    // A sphere between a rectangle light and the floor: seen from below
    // the light, the shadow has a dark umbra, a lit outside and a penumbra
    // of values between.
    let mut s = empty_scene(48, 48, Vec3::new(0.0, 2.0, 0.0));
    s.camera.projection = Projection::Orthographic { height: 4.0 };
    s.camera.up = Vec3::Z;
    s.settings.spp = 16;
    s.settings.integrator = IntegratorChoice::Whitted;
    let m = material(&mut s, matte(Rgb::ONE, 0.0, 1.0));
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        m,
    );
    // A dark sphere, so that seen from above it does not hide the shadow.
    let black = material(&mut s, matte(Rgb::ZERO, 0.0, 0.0));
    object(&mut s, sphere(Vec3::new(0.0, 0.6, 0.0), 0.4), black);
    s.lights.push(Light::Rect {
        corner: Vec3::new(-0.5, 3.0, -0.5),
        edge_u: Vec3::new(1.0, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 1.0),
        color: Rgb::ONE,
        intensity: 10.0,
    });
    let (img, stats) = render(&s);
    assert!(stats.rays.light_sample > 0, "{stats}");
    let floor: Vec<f32> = img.pixels.iter().map(|p| p.x).collect();
    let lit = floor.iter().cloned().fold(0.0, f32::max);
    let corner = floor[0];
    assert!(
        corner > 0.2 * lit,
        "the floor far away is lit: {corner} of {lit}"
    );
    let between = floor
        .iter()
        .filter(|&&v| v > 0.1 * lit && v < 0.9 * lit)
        .count();
    assert!(between > 40, "a penumbra: {between} pixels between");
}

#[test]
fn a_spot_lights_its_cone_only() {
    let mut s = floor_scene(IntegratorChoice::Whitted, 1);
    s.camera.projection = Projection::Orthographic { height: 8.0 };
    s.settings.width = 64;
    s.settings.height = 64;
    s.lights.push(Light::Spot {
        position: Vec3::new(0.0, 2.0, 0.0),
        direction: Vec3::NEG_Y,
        color: Rgb::ONE,
        intensity: 1.0,
        inner_deg: 20.0,
        outer_deg: 30.0,
        inverse_square: false,
        shadows: true,
    });
    let (img, stats) = render(&s);
    // Radius on the floor: 2·tan 20° = 0.73 (full), 2·tan 30° = 1.15 (end).
    // Pixel (c, r) shows the floor point at distance `dist` from the axis.
    let full = RHO / std::f32::consts::PI;
    let (mut inner, mut band, mut outer) = (0, 0, 0);
    for r in 0..64 {
        for c in 0..64 {
            let x = (c as f32 + 0.5) / 64.0 * 8.0 - 4.0;
            let z = (r as f32 + 0.5) / 64.0 * 8.0 - 4.0;
            let dist = x.hypot(z);
            let v = img.pixels[r * 64 + c].x;
            let cos = 2.0 / dist.hypot(2.0);
            if dist < 0.7 {
                assert!((v - full * cos).abs() < 1e-4, "({c}, {r}): {v}");
                inner += 1;
            } else if dist > 1.2 {
                assert_eq!(v, 0.0, "({c}, {r})");
                outer += 1;
            } else if dist > 0.78 && dist < 1.1 {
                assert!(v > 0.0 && v < full * cos, "({c}, {r}): {v}");
                band += 1;
            }
        }
    }
    assert!(inner > 50 && band > 50 && outer > 50);
    // One plane cannot shadow itself: no shadow rays.
    assert_eq!(stats.rays.shadow, 0);
    assert_eq!(stats.rays.light_sample, 0);
}

#[test]
fn an_area_light_makes_auto_path_trace_and_counts_as_a_light() {
    let mut s = floor_scene(IntegratorChoice::Auto, 1);
    s.lights.push(disk_light(1.0));
    let (_, stats) = render(&s);
    assert_eq!(stats.plan.integrator, gridrt_tracer::IntegratorKind::Path);
    assert_eq!(stats.plan.area_lights, 1);
    // Without it, no light sampling at all.
    let mut s = floor_scene(IntegratorChoice::Whitted, 4);
    s.lights
        .push(crate::common::directional(Vec3::Y, 1.0, true));
    let (_, stats) = render(&s);
    assert_eq!(stats.rays.light_sample, 0);
    assert!(!stats.plan.light_sampling);
}

#[test]
fn an_emissive_material_lights_a_whitted_scene_as_an_area_light() {
    // An emissive sphere above the floor: Whitted samples it.
    let mut s = floor_scene(IntegratorChoice::Whitted, 64);
    let e = material(
        &mut s,
        Material::Emissive {
            color: Rgb::ONE,
            strength: 1.0,
        },
    );
    object(&mut s, sphere(Vec3::new(0.0, 2.0, 0.0), 0.5), e);
    let (img, stats) = render(&s);
    // A sphere of radius r at distance d lights like a point of intensity
    // L·π·r² straight below (the disk it subtends): E = π·L·r²/d².
    let want = RHO * 0.25 / 4.0;
    let got = mean(&img);
    assert!(stats.plan.light_sampling);
    assert!((got - want).abs() < 0.05 * want, "{got} vs {want}");
}
