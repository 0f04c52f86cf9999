//! Glossy materials (GGX conductor, rough dielectric, glTF
//! metallic-roughness) in both integrators: energy in a white furnace and
//! glossy rays only when a rough lobe is in use.

use crate::common::*;
use gridrt_grid::Vec3;
use gridrt_tracer::{ConductorFresnel, IntegratorChoice, IntegratorKind, Light, Material, Rgb};

fn conductor(f0: Rgb, roughness: f32) -> Material {
    Material::Conductor {
        fresnel: ConductorFresnel::Schlick { f0 },
        roughness,
    }
}

/// One sphere filling the middle of a 24×24 image inside a uniform white
/// environment of radiance 1 (the white furnace).
fn furnace(m: Material) -> gridrt_tracer::Scene {
    let mut s = empty_scene(24, 24, Vec3::new(0.0, 0.0, 4.0));
    s.settings.spp = 16;
    let id = material(&mut s, m);
    object(&mut s, sphere(Vec3::ZERO, 1.0), id);
    s.lights = vec![Light::Environment {
        color: Rgb::ONE,
        intensity: 1.0,
        image: None,
    }];
    s
}

/// Mean of the pixels within the sphere's silhouette (radius 8 pixels
/// around the centre, well inside the ~8.6-pixel disk).
fn sphere_mean(img: &gridrt_tracer::Framebuffer) -> f32 {
    let (mut sum, mut n) = (0.0, 0);
    for y in 0..img.height {
        for x in 0..img.width {
            let (dx, dy) = (x as f32 - 11.5, y as f32 - 11.5);
            if dx * dx + dy * dy < 7.0 * 7.0 {
                let p = img.pixels[(y * img.width + x) as usize];
                sum += (p.x + p.y + p.z) / 3.0;
                n += 1;
            }
        }
    }
    sum / n as f32
}

#[test]
fn a_white_rough_conductor_in_a_furnace_creates_no_energy() {
    for roughness in [0.2f32, 0.6, 1.0] {
        let (img, stats) = render(&furnace(conductor(Rgb::ONE, roughness)));
        assert_eq!(stats.plan.integrator, IntegratorKind::Path);
        assert!(stats.plan.glossy && stats.rays.glossy > 0);
        assert_finite(&img);
        let m = sphere_mean(&img);
        // Single scattering loses energy at high roughness (more than half
        // at α = 1), never gains.
        assert!(m <= 1.02, "roughness {roughness}: {m}");
        assert!(m > 0.3, "roughness {roughness}: {m}");
        if roughness <= 0.2 {
            assert!(m > 0.95, "roughness {roughness}: {m}");
        }
    }
}

#[test]
fn rough_glass_in_a_furnace_stays_within_the_environment() {
    let glass = Material::RoughDielectric {
        ior: 1.5,
        tint: Rgb::ONE,
        roughness: 0.3,
    };
    let (img, stats) = render(&furnace(glass));
    assert!(stats.plan.refraction && stats.plan.glossy);
    let m = sphere_mean(&img);
    assert!((0.85..=1.03).contains(&m), "{m}");
}

#[test]
fn gltf_white_dielectric_in_a_furnace_reflects_about_everything() {
    // Base white, metallic 0: a Lambertian base under a 4 % coat.
    let m = Material::MetallicRoughness {
        base: Rgb::ONE,
        metallic: 0.0,
        roughness: 0.5,
    };
    let (img, stats) = render(&furnace(m));
    assert!(stats.plan.indirect && stats.plan.glossy);
    let m = sphere_mean(&img);
    assert!((0.85..=1.05).contains(&m), "{m}");
}

fn whitted_scene(m: Material) -> gridrt_tracer::Scene {
    let mut s = empty_scene(24, 24, Vec3::new(0.0, 1.0, 6.0));
    s.settings.integrator = IntegratorChoice::Whitted;
    s.settings.spp = 4;
    let floor = material(&mut s, matte(Rgb::splat(0.7), 0.2, 0.8));
    let id = material(&mut s, m);
    object(&mut s, sphere(Vec3::new(-0.6, 0.0, 0.0), 0.5), floor);
    object(&mut s, sphere(Vec3::new(0.6, 0.0, 0.0), 0.5), id);
    s.lights = vec![
        ambient(0.5),
        directional(Vec3::new(1.0, 1.0, 0.5), 2.0, true),
    ];
    s
}

#[test]
fn whitted_casts_glossy_rays_only_for_rough_lobes() {
    // A matte scene: no glossy rays, and the compiled loop has none.
    let (_, stats) = render(&whitted_scene(matte(Rgb::ONE, 0.2, 0.8)));
    assert!(!stats.plan.glossy);
    assert_eq!(stats.rays.glossy, 0);
    // A rough metal: one glossy ray per hit on it (depth allowing).
    let (img, stats) = render(&whitted_scene(conductor(Rgb::new(0.9, 0.6, 0.3), 0.4)));
    assert_eq!(stats.plan.integrator, IntegratorKind::Whitted);
    assert!(stats.plan.glossy && stats.rays.glossy > 0);
    assert_finite(&img);
    // A polished metal (roughness 0) is a Fresnel mirror: reflection rays,
    // no glossy ones.
    let (_, stats) = render(&whitted_scene(conductor(Rgb::new(0.9, 0.6, 0.3), 0.0)));
    assert!(stats.plan.reflection && !stats.plan.glossy);
    assert!(stats.rays.reflection > 0);
    assert_eq!(stats.rays.glossy, 0);
    // glTF's material and rough glass sample their lobes too.
    for m in [
        Material::MetallicRoughness {
            base: Rgb::new(0.8, 0.2, 0.1),
            metallic: 0.5,
            roughness: 0.4,
        },
        Material::RoughDielectric {
            ior: 1.5,
            tint: Rgb::ONE,
            roughness: 0.3,
        },
    ] {
        let (img, stats) = render(&whitted_scene(m.clone()));
        assert!(stats.plan.glossy && stats.rays.glossy > 0, "{m:?}");
        assert_finite(&img);
    }
}

#[test]
fn a_rough_conductor_lit_by_a_light_shows_a_highlight() {
    // The direct light goes through the GGX lobe: the rough metal is lit,
    // brightest where the light's mirror direction meets the camera.
    let mut s = whitted_scene(conductor(Rgb::ONE, 0.3));
    s.lights = vec![directional(Vec3::new(0.0, 1.0, 2.0), 2.0, false)];
    s.settings.max_depth = 0;
    let (img, stats) = render(&s);
    assert_eq!(stats.rays.glossy, 0);
    let max = img
        .pixels
        .iter()
        .map(|p| p.max_element())
        .fold(0.0f32, f32::max);
    assert!(max > 0.5, "{max}");
}

#[test]
fn whitted_counts_an_area_light_on_a_rough_lobe_once() {
    // A rough conductor under a rectangle light, nothing else: the light
    // reaches the sphere directly, by light sampling and by the glossy ray
    // alike. Whitted must count it once, as the path tracer does with one
    // bounce (both see direct light only here).
    let scene = |integrator| {
        let mut s = empty_scene(24, 24, Vec3::new(0.0, 0.0, 4.0));
        s.camera.projection = gridrt_tracer::Projection::Perspective { vfov_deg: 20.0 };
        s.settings.spp = 64;
        s.settings.integrator = integrator;
        s.settings.max_depth = 1;
        s.settings.path_max_depth = 1;
        let m = material(&mut s, conductor(Rgb::new(1.0, 0.78, 0.34), 0.35));
        object(&mut s, sphere(Vec3::ZERO, 0.6), m);
        s.lights.push(Light::Rect {
            corner: Vec3::new(-1.0, 2.4, -1.0),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 2.0),
            color: Rgb::ONE,
            intensity: 3.0,
        });
        s
    };
    let (whitted, stats) = render(&scene(IntegratorChoice::Whitted));
    assert_eq!(stats.plan.integrator, IntegratorKind::Whitted);
    assert!(
        stats.rays.glossy > 0 && stats.rays.light_sample > 0,
        "{stats}"
    );
    let (path, stats) = render(&scene(IntegratorChoice::Path));
    assert_eq!(stats.plan.integrator, IntegratorKind::Path);
    let mean = |img: &gridrt_tracer::Framebuffer| {
        img.pixels.iter().map(|p| f64::from(p.x)).sum::<f64>() / img.pixels.len() as f64
    };
    let (w, p) = (mean(&whitted), mean(&path));
    assert!((w - p).abs() < 0.04 * p, "Whitted {w} vs path {p}");
}
