//! The effect plan: effects a scene does not call for cost zero rays.

use crate::common::*;
use gridrt_grid::Vec3;
use gridrt_tracer::{EffectPlan, IntegratorKind, Material, Rgb};

fn two_spheres(shadows: bool) -> gridrt_tracer::Scene {
    let mut s = empty_scene(24, 24, Vec3::new(0.0, 1.0, 6.0));
    let m = material(&mut s, matte(Rgb::splat(0.7), 0.2, 0.8));
    object(&mut s, sphere(Vec3::new(-0.6, 0.0, 0.0), 0.5), m);
    object(&mut s, sphere(Vec3::new(0.6, 0.0, 0.0), 0.5), m);
    s.lights = vec![
        ambient(1.0),
        directional(Vec3::new(1.0, 1.0, 0.5), 2.0, shadows),
    ];
    s
}

#[test]
fn shadows_off_cast_zero_shadow_rays() {
    let (_, stats) = render(&two_spheres(false));
    assert!(!stats.plan.shadows);
    assert_eq!(stats.plan.shadow_lights, 0);
    assert_eq!(stats.rays.shadow, 0);
    let (_, stats) = render(&two_spheres(true));
    assert!(stats.plan.shadows);
    assert_eq!(stats.plan.shadow_lights, 1);
    assert!(stats.rays.shadow > 0);
    // At most one shadow ray per lit hit.
    assert!(stats.rays.shadow <= stats.pixels_hit);
}

#[test]
fn only_lights_with_shadows_cast_shadow_rays() {
    let mut s = two_spheres(true);
    // A second light without shadows: still one shadow ray per lit hit.
    s.lights
        .push(directional(Vec3::new(-1.0, 0.5, 1.0), 1.0, false));
    let (_, stats) = render(&s);
    assert_eq!((stats.plan.direct_lights, stats.plan.shadow_lights), (2, 1));
    assert!(stats.rays.shadow > 0 && stats.rays.shadow <= stats.pixels_hit);
    let mut only_unshadowed = s.clone();
    only_unshadowed.lights.remove(1);
    let (_, stats) = render(&only_unshadowed);
    assert_eq!(stats.rays.shadow, 0);
}

#[test]
fn no_reflective_material_casts_zero_secondary_rays() {
    let mut s = two_spheres(true);
    // A mirror and a glass material that no object uses change nothing.
    material(
        &mut s,
        Material::Reflective {
            color: Rgb::ONE,
            ka: 0.0,
            kd: 0.0,
            ks: 0.0,
            exp: 1.0,
            kr: 1.0,
            reflect: Rgb::ONE,
        },
    );
    material(
        &mut s,
        Material::Dielectric {
            ior: 1.5,
            tint: Rgb::ONE,
        },
    );
    let (_, stats) = render(&s);
    assert_eq!(stats.plan.integrator, IntegratorKind::RayCast);
    assert!(!stats.plan.reflection && !stats.plan.refraction);
    assert_eq!(stats.plan.max_depth, 0);
    assert_eq!((stats.rays.reflection, stats.rays.refraction), (0, 0));
    // Now let an object use the mirror: reflection rays, still no refraction.
    s.objects[1].material = 1;
    let (_, stats) = render(&s);
    assert!(stats.plan.reflection && !stats.plan.refraction);
    assert_eq!(stats.plan.max_depth, s.settings.max_depth);
    assert!(stats.rays.reflection > 0);
    assert_eq!(stats.rays.refraction, 0);
    // A mirror with kr = 0 does not reflect.
    s.materials[1] = Material::Reflective {
        color: Rgb::ONE,
        ka: 0.1,
        kd: 0.5,
        ks: 0.2,
        exp: 10.0,
        kr: 0.0,
        reflect: Rgb::ONE,
    };
    assert!(!EffectPlan::for_scene(&s).reflection);
    // max_depth 0 turns secondary rays off whatever the materials.
    s.objects[1].material = 2;
    s.settings.max_depth = 0;
    let (_, stats) = render(&s);
    assert_eq!(stats.rays.reflection + stats.rays.refraction, 0);
}

#[test]
fn lone_convex_object_and_unlit_materials_need_no_shadow_rays() {
    let mut s = two_spheres(true);
    s.objects.pop();
    let plan = EffectPlan::for_scene(&s);
    assert!(!plan.shadows && plan.direct_lights == 1);
    // Only emissive materials: no light loop at all.
    let mut s = two_spheres(true);
    s.materials[0] = Material::Emissive {
        color: Rgb::ONE,
        strength: 1.0,
    };
    let plan = EffectPlan::for_scene(&s);
    assert_eq!((plan.direct_lights, plan.shadow_lights), (0, 0));
    assert!(!plan.ambient);
    let (img, stats) = render(&s);
    assert_eq!(stats.rays.shadow, 0);
    assert!(img.pixels.iter().all(|p| *p == Rgb::ZERO || *p == Rgb::ONE));
}

#[test]
fn jitter_only_above_one_sample() {
    let mut s = two_spheres(false);
    assert!(!EffectPlan::for_scene(&s).jitter);
    s.settings.spp = 4;
    let plan = EffectPlan::for_scene(&s);
    assert!(plan.jitter && plan.spp == 4);
    let (_, stats) = render(&s);
    assert_eq!(stats.rays.camera, 24 * 24 * 4);
}

#[test]
fn plan_and_stats_display_every_effect() {
    let (_, stats) = render(&kitchen_sink(16, 12));
    let p = stats.plan.to_string();
    for word in [
        "Whitted",
        "2 per pixel",
        "shadows     on (2 of 2",
        "reflection  on",
        "refraction  on",
    ] {
        assert!(p.contains(word), "{word:?} missing from:\n{p}");
    }
    let text = stats.to_string();
    println!("{text}");
    assert!(text.contains("camera") && text.contains("shadow") && text.contains("refraction"));
    assert!(text.contains("grid"));
    let plain = EffectPlan::for_scene(&two_spheres(false)).to_string();
    assert!(
        plain.contains("ray casting")
            && plain.contains("no jitter")
            && plain.contains("shadows     off")
    );
}

#[cfg(feature = "serde")]
#[test]
fn stats_serialize_to_json() {
    let (_, stats) = render(&kitchen_sink(8, 8));
    let json = serde_json::to_value(&stats).unwrap();
    assert_eq!(json["rays"]["camera"], 128);
    assert_eq!(json["plan"]["refraction"], true);
    assert!(json["render_time"].is_f64());
    assert!(json["grid"]["dims"].is_array());
}

#[test]
fn a_pinhole_draws_no_lens_sample_and_a_lens_blurs() {
    let mut s = two_spheres(true);
    s.settings.spp = 4;
    let (pinhole, stats) = render(&s);
    assert!(!stats.plan.depth_of_field);
    // A lens of radius 0 is the pinhole: the same image, bit for bit.
    s.camera.lens = Some(gridrt_tracer::ThinLens {
        radius: 0.0,
        focus_distance: 3.0,
    });
    let (same, stats) = render(&s);
    assert!(!stats.plan.depth_of_field);
    assert_eq!(pinhole.pixels, same.pixels);
    // A real aperture focused far behind the spheres blurs them; the
    // camera still casts one ray per sample.
    s.camera.lens = Some(gridrt_tracer::ThinLens {
        radius: 0.3,
        focus_distance: 20.0,
    });
    let (blurred, stats) = render(&s);
    assert!(stats.plan.depth_of_field);
    assert_eq!(stats.rays.camera, u64::from(24 * 24 * 4u32));
    assert_ne!(pinhole.pixels, blurred.pixels);
    assert!(stats.plan.to_string().contains("thin lens"));
}
