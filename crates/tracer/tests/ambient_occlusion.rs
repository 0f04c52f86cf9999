//! Ambient occlusion (Suffern ch. 17): occluded points get less ambient
//! light, open ones all of it, and scenes without it trace no occlusion
//! rays.

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{
    AccelKind, Geometry, IntegratorChoice, Light, Occlusion, Projection, Rgb, Scene,
};

const SAMPLES: u32 = 16;

fn occluded_ambient(intensity: f32, distance: Real, min_amount: f32) -> Light {
    Light::Ambient {
        color: Rgb::ONE,
        intensity,
        occlusion: Some(Occlusion {
            samples: SAMPLES,
            distance,
            min_amount,
        }),
    }
}

/// A floor lit by ambient light only (`ka = 1`, `kd = 0`), seen from a
/// low camera whose view never rises: a roof above the camera is out of
/// sight, so every pixel shows the floor.
fn floor(light: Light) -> Scene {
    let mut s = empty_scene(32, 24, Vec3::new(0.0, 0.3, 1.5));
    s.camera.projection = Projection::Perspective { vfov_deg: 20.0 };
    let m = material(&mut s, matte(Rgb::splat(0.5), 1.0, 0.0));
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        m,
    );
    s.lights = vec![light];
    s
}

/// `s` with a thin roof at height 0.6 over `x ∈ [x0, x1]`, from far
/// beyond the floor in view to behind the camera.
fn with_roof(mut s: Scene, x0: Real, x1: Real) -> Scene {
    let m = s.objects[0].material;
    object(
        &mut s,
        Geometry::Cuboid {
            min: Vec3::new(x0, 0.6, -50.0),
            max: Vec3::new(x1, 0.7, 5.0),
        },
        m,
    );
    s
}

#[test]
fn a_floor_alone_gets_exactly_the_plain_ambient_light() {
    let (plain, st) = render(&floor(ambient(0.8)));
    assert!(!st.plan.ambient_occlusion);
    assert_eq!(st.rays.ambient_occlusion, 0);
    let (ao, st) = render(&floor(occluded_ambient(0.8, Real::INFINITY, 0.0)));
    assert!(st.plan.ambient_occlusion, "{}", st.plan);
    // Nothing occludes: every ray is free, the share is exactly 1.
    assert_eq!(
        st.rays.ambient_occlusion,
        u64::from(SAMPLES) * st.pixels_hit
    );
    assert_eq!(st.pixels_hit, 32 * 24);
    assert_eq!(ao.pixels, plain.pixels);
}

#[test]
fn a_roof_takes_ambient_light_away_down_to_min_amount() {
    let (plain, _) = render(&floor(ambient(1.0)));
    let roofed = |distance, min_amount| {
        let s = with_roof(
            floor(occluded_ambient(1.0, distance, min_amount)),
            -50.0,
            50.0,
        );
        render(&s)
    };
    let (img, st) = roofed(Real::INFINITY, 0.0);
    assert_eq!(
        st.rays.ambient_occlusion,
        u64::from(SAMPLES) * st.pixels_hit
    );
    for (a, p) in img.pixels.iter().zip(&plain.pixels) {
        assert!(a.x < p.x, "{a} should be darker than {p}");
    }
    // Suffern's floor: a covered point keeps at least `min_amount`.
    let (img, _) = roofed(Real::INFINITY, 0.25);
    for (a, p) in img.pixels.iter().zip(&plain.pixels) {
        assert!(a.x >= 0.25 * p.x * (1.0 - 1e-6) && a.x < p.x, "{a} vs {p}");
    }
    // Occlusion rays shorter than the roof's height see nothing.
    let (img, _) = roofed(0.5, 0.0);
    assert_eq!(img.pixels, plain.pixels);
}

#[test]
fn a_point_under_a_small_roof_gets_less_ambient_than_an_open_point() {
    // The roof covers the left of the view (x < -0.05); the view spans
    // about x ∈ [-0.35, 0.35] on the floor.
    let s = with_roof(
        floor(occluded_ambient(1.0, Real::INFINITY, 0.0)),
        -5.0,
        -0.05,
    );
    let (img, _) = render(&s);
    for y in [4, 12, 20] {
        let (under, open) = (img.get(1, y).x, img.get(30, y).x);
        assert!(under < 0.8 * open, "row {y}: {under} vs {open}");
    }
}

#[test]
fn occlusion_images_do_not_depend_on_threads_or_accelerator() {
    let mut s = with_roof(floor(occluded_ambient(1.0, 2.0, 0.1)), -5.0, -0.05);
    object(&mut s, sphere(Vec3::new(0.1, 0.1, 0.0), 0.1), 0);
    s.settings.spp = 4;
    let (a, sa) = render_with(&s, &opts(AccelKind::Grid, Some(1)));
    let (b, sb) = render_with(&s, &opts(AccelKind::Grid, Some(3)));
    let (c, _) = render_with(&s, &opts(AccelKind::Exhaustive, Some(2)));
    assert_eq!(a.pixels, b.pixels);
    assert_eq!(a.pixels, c.pixels);
    assert_eq!(sa.rays, sb.rays);
}

#[test]
fn occlusion_nobody_can_see_traces_no_rays() {
    // No material with an ambient term: the light lights nothing.
    let mut s = floor(occluded_ambient(1.0, Real::INFINITY, 0.0));
    s.materials[0] = matte(Rgb::splat(0.5), 0.0, 1.0);
    s.lights
        .push(directional(Vec3::new(0.0, 1.0, 1.0), 1.0, true));
    let s = with_roof(s, -5.0, -0.05);
    let (img, st) = render(&s);
    assert!(!st.plan.ambient_occlusion);
    assert_eq!(st.rays.ambient_occlusion, 0);
    let mut plain = s.clone();
    plain.lights[0] = ambient(1.0);
    assert_eq!(render(&plain).0.pixels, img.pixels);
    // A black ambient light.
    let mut s = floor(occluded_ambient(0.0, Real::INFINITY, 0.0));
    s.lights
        .push(directional(Vec3::new(0.0, 1.0, 1.0), 1.0, false));
    let (_, st) = render(&s);
    assert!(!st.plan.ambient_occlusion);
    assert_eq!(st.rays.ambient_occlusion, 0);
    // The path tracer gathers no ambient light.
    let mut s = with_roof(floor(occluded_ambient(1.0, Real::INFINITY, 0.0)), -5.0, 5.0);
    s.materials[0] = matte(Rgb::splat(0.5), 1.0, 0.5);
    s.lights
        .push(directional(Vec3::new(0.0, 1.0, 1.0), 1.0, false));
    s.settings.integrator = IntegratorChoice::Path;
    s.settings.path_max_depth = 1;
    let (_, st) = render(&s);
    assert!(!st.plan.ambient_occlusion);
    assert_eq!(st.rays.ambient_occlusion, 0);
}

#[test]
fn bad_occlusion_settings_are_errors() {
    for (samples, distance, min_amount) in [
        (0, 1.0, 0.0),
        (Occlusion::MAX_SAMPLES + 1, 1.0, 0.0),
        (4, 0.0, 0.0),
        (4, Real::NAN, 0.0),
        (4, 1.0, 1.5),
        (4, 1.0, f32::NAN),
    ] {
        let mut s = floor(occluded_ambient(1.0, distance, min_amount));
        if let Light::Ambient {
            occlusion: Some(o), ..
        } = &mut s.lights[0]
        {
            o.samples = samples;
        }
        let e = gridrt_tracer::render(&s, &Default::default()).unwrap_err();
        assert!(e.to_string().contains("occlusion"), "{e}");
    }
}
