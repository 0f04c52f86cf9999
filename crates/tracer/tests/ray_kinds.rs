//! Every kind of ray is traced when its effect is in the scene, and none
//! of it when that one effect is taken out: the kitchen-sink scene under
//! the Whitted tracer (with ambient occlusion) and under the path tracer.

use crate::common::*;
use gridrt_grid::Real;
use gridrt_tracer::{IntegratorChoice, Light, Material, Occlusion, RayCounts, Rgb, Scene};

// Material indices of `kitchen_sink`.
const RED: usize = 0;
const PHONG: usize = 1;
const MIRROR: usize = 2;
const GLASS: usize = 3;
const LAMP: usize = 4;
const FLOOR: usize = 5;

fn rays(s: &Scene) -> RayCounts {
    render(s).1.rays
}

fn gray() -> Material {
    matte(Rgb::splat(0.5), 0.2, 0.8)
}

fn whitted() -> Scene {
    let mut s = kitchen_sink(12, 9);
    s.lights[0] = Light::Ambient {
        color: Rgb::ONE,
        intensity: 0.5,
        occlusion: Some(Occlusion {
            samples: 4,
            distance: Real::INFINITY,
            min_amount: 0.0,
        }),
    };
    s
}

#[test]
fn whitted_kinds_are_zero_exactly_without_their_effect() {
    let all = rays(&whitted());
    assert!(all.camera > 0 && all.shadow > 0 && all.reflection > 0 && all.refraction > 0);
    assert!(all.light_sample > 0 && all.ambient_occlusion > 0, "{all}");
    // The Whitted tracer gathers no indirect light; nothing here is rough.
    assert_eq!((all.indirect, all.glossy), (0, 0));

    let mut s = whitted();
    for l in &mut s.lights {
        if let Light::Point { shadows, .. } | Light::Directional { shadows, .. } = l {
            *shadows = false;
        }
    }
    let r = rays(&s);
    assert_eq!(r.shadow, 0);
    assert!(r.light_sample > 0 && r.ambient_occlusion > 0 && r.reflection > 0);

    let mut s = whitted();
    s.materials[MIRROR] = gray();
    s.materials[GLASS] = gray();
    let r = rays(&s);
    assert_eq!((r.reflection, r.refraction), (0, 0));
    assert!(r.shadow > 0 && r.light_sample > 0 && r.ambient_occlusion > 0);

    let mut s = whitted();
    s.materials[LAMP] = gray();
    let r = rays(&s);
    assert_eq!(r.light_sample, 0);
    assert!(r.shadow > 0 && r.reflection > 0 && r.ambient_occlusion > 0);

    let r = rays(&kitchen_sink(12, 9));
    assert_eq!(r.ambient_occlusion, 0);
    assert!(r.shadow > 0 && r.reflection > 0 && r.light_sample > 0);
}

#[test]
fn path_kinds_are_zero_exactly_without_their_effect() {
    let path = || {
        let mut s = whitted();
        s.settings.integrator = IntegratorChoice::Path;
        s.settings.path_max_depth = 3;
        s
    };
    let all = rays(&path());
    assert!(
        all.light_sample > 0 && all.glossy > 0 && all.indirect > 0,
        "{all}"
    );
    assert!(all.shadow > 0 && all.reflection > 0 && all.refraction > 0);
    // The path tracer gathers no ambient light.
    assert_eq!(all.ambient_occlusion, 0);

    // No lobe with a highlight: Phong becomes matte, the mirror loses ks.
    let mut s = path();
    s.materials[PHONG] = gray();
    if let Material::Reflective { ks, .. } = &mut s.materials[MIRROR] {
        *ks = 0.0;
    }
    let r = rays(&s);
    assert_eq!(r.glossy, 0);
    assert!(r.indirect > 0 && r.light_sample > 0);

    // No diffuse reflection anywhere: ambient-only mattes, no mirror kd.
    let mut s = path();
    for i in [RED, PHONG, FLOOR] {
        s.materials[i] = matte(Rgb::splat(0.5), 0.5, 0.0);
    }
    if let Material::Reflective { kd, .. } = &mut s.materials[MIRROR] {
        *kd = 0.0;
    }
    let r = rays(&s);
    assert_eq!(r.indirect, 0);
    assert!(r.reflection > 0 && r.refraction > 0);

    // No area light: the lamp becomes matte.
    let mut s = path();
    s.materials[LAMP] = gray();
    let r = rays(&s);
    assert_eq!(r.light_sample, 0);
    assert!(r.indirect > 0 && r.glossy > 0 && r.shadow > 0);
}
