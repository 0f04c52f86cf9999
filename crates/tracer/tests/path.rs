//! The path tracer: a white furnace, an energy check of light sampling with
//! MIS against BSDF sampling alone, determinism, the plan's choices and the
//! rays it does not spend.

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{
    AccelKind, Geometry, IntegratorChoice, IntegratorKind, Material, Mesh, Rgb, Scene, SceneError,
};

fn path_scene(w: u32, h: u32, eye: Vec3) -> Scene {
    let mut s = empty_scene(w, h, eye);
    s.settings.integrator = IntegratorChoice::Path;
    s
}

fn emissive(radiance: f32) -> Material {
    Material::Emissive {
        color: Rgb::ONE,
        strength: radiance,
    }
}

/// Two triangles of the quad `a b c d` (counter-clockwise = front).
fn quad(name: &str, a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Geometry {
    Geometry::Mesh(std::sync::Arc::new(Mesh {
        name: name.into(),
        positions: vec![a, b, c, d],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    }))
}

fn mean(img: &gridrt_tracer::Framebuffer) -> Rgb {
    img.pixels.iter().copied().sum::<Rgb>() / img.pixels.len() as f32
}

#[test]
fn white_furnace_a_white_sphere_in_a_uniform_environment_vanishes() {
    // Albedo 1 (kd = 1, white): every path escapes with its weight intact,
    // so every pixel is the environment's radiance, sphere or not.
    for sampler in [
        gridrt_tracer::SamplerKind::MultiJittered,
        gridrt_tracer::SamplerKind::Sobol,
        gridrt_tracer::SamplerKind::Random,
    ] {
        let mut s = path_scene(12, 12, Vec3::new(0.0, 0.0, 4.0));
        s.settings.background = Rgb::splat(0.5);
        s.settings.spp = 4;
        s.settings.sampler = sampler;
        let m = material(&mut s, matte(Rgb::ONE, 0.0, 1.0));
        object(&mut s, sphere(Vec3::ZERO, 1.0), m);
        let (img, stats) = render(&s);
        assert!(stats.pixels_hit > 40);
        for p in &img.pixels {
            assert!(
                (*p - Rgb::splat(0.5)).abs().max_element() < 1e-3,
                "{sampler}: {p}"
            );
        }
        assert!(stats.rays.indirect > 0);
    }
}

/// A closed 2 × 2 × 2 box of white diffuse walls (the floor and walls as
/// meshes) with the camera inside it, and a square lamp under the ceiling.
fn closed_box(lamp: Geometry, lamp_material: Material) -> Scene {
    let mut s = path_scene(24, 24, Vec3::new(0.0, 1.0, 0.9));
    s.camera.look_at = Vec3::new(0.0, 0.9, 0.0);
    s.settings.spp = 64;
    let white = material(&mut s, matte(Rgb::splat(0.7), 0.0, 1.0));
    let p = |x: Real, y: Real, z: Real| Vec3::new(x, y, z);
    // Walls (diffuse surfaces reflect on both sides, so winding is free).
    let walls = [
        [
            p(-1., 0., -1.),
            p(1., 0., -1.),
            p(1., 0., 1.),
            p(-1., 0., 1.),
        ],
        [
            p(-1., 2., -1.),
            p(-1., 2., 1.),
            p(1., 2., 1.),
            p(1., 2., -1.),
        ],
        [
            p(-1., 0., -1.),
            p(-1., 2., -1.),
            p(1., 2., -1.),
            p(1., 0., -1.),
        ],
        [p(-1., 0., 1.), p(1., 0., 1.), p(1., 2., 1.), p(-1., 2., 1.)],
        [
            p(-1., 0., -1.),
            p(-1., 0., 1.),
            p(-1., 2., 1.),
            p(-1., 2., -1.),
        ],
        [p(1., 0., -1.), p(1., 2., -1.), p(1., 2., 1.), p(1., 0., 1.)],
    ];
    for (i, w) in walls.iter().enumerate() {
        object(
            &mut s,
            quad(&format!("wall {i}"), w[0], w[1], w[2], w[3]),
            white,
        );
    }
    let l = material(&mut s, lamp_material);
    object(&mut s, lamp, l);
    s
}

/// The 12 triangles of the box `[lo, hi]`, wound counter-clockwise seen
/// from outside (the front faces out, as a `Cuboid`'s normals do).
fn box_mesh(lo: Vec3, hi: Vec3) -> Geometry {
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let (f, t) = (false, true);
    let faces = [
        [c(f, f, f), c(t, f, f), c(t, f, t), c(f, f, t)],
        [c(f, t, f), c(f, t, t), c(t, t, t), c(t, t, f)],
        [c(f, f, f), c(f, t, f), c(t, t, f), c(t, f, f)],
        [c(f, f, t), c(t, f, t), c(t, t, t), c(f, t, t)],
        [c(f, f, f), c(f, f, t), c(f, t, t), c(f, t, f)],
        [c(t, f, f), c(t, t, f), c(t, t, t), c(t, f, t)],
    ];
    let mut m = Mesh {
        name: "lamp box".into(),
        ..Mesh::default()
    };
    for q in faces {
        let k = m.positions.len() as u32;
        m.positions.extend_from_slice(&q);
        m.triangles.push([k, k + 1, k + 2]);
        m.triangles.push([k, k + 2, k + 3]);
    }
    Geometry::Mesh(std::sync::Arc::new(m))
}

#[test]
fn energy_light_sampling_with_mis_agrees_with_bsdf_sampling_alone() {
    // The same emitting box twice: as a mesh (12 area lights, sampled with
    // MIS against BSDF sampling) and as a `Cuboid` (boxes are not sampled:
    // only BSDF sampling finds it). Both estimators are unbiased, so their
    // image means agree within noise.
    let (lo, hi) = (Vec3::new(-0.4, 1.85, -0.4), Vec3::new(0.4, 1.9, 0.4));
    let (img_mis, st_mis) = render(&closed_box(box_mesh(lo, hi), emissive(4.0)));
    assert_eq!(st_mis.plan.area_lights, 12);
    assert!(st_mis.plan.light_sampling);
    assert!(st_mis.rays.light_sample > 0);
    let cuboid = Geometry::Cuboid { min: lo, max: hi };
    let (img_bsdf, st_bsdf) = render(&closed_box(cuboid, emissive(4.0)));
    assert_eq!(st_bsdf.plan.area_lights, 0);
    assert!(!st_bsdf.plan.light_sampling);
    assert_eq!(st_bsdf.rays.light_sample, 0);
    let (m1, m2) = (mean(&img_mis), mean(&img_bsdf));
    let rel = ((m1 - m2) / m2).abs().max_element();
    assert!(rel < 0.04, "MIS {m1} vs BSDF only {m2}");
    // Grey walls and a white lamp: a grey image, brighter than the lamp's
    // direct light alone would make it (interreflection).
    assert!(
        m1.x > 0.1 && (m1.x - m1.z).abs() < 1e-3 * m1.x.max(1.0),
        "{m1}"
    );
}

#[test]
fn emission_is_one_sided() {
    // A lamp facing up (counter-clockwise seen from above) under a camera
    // looking down sees it lit; flipped, it is black and lights nothing.
    let up = [
        Vec3::new(-3.0, 0.0, -3.0),
        Vec3::new(-3.0, 0.0, 3.0),
        Vec3::new(3.0, 0.0, 3.0),
        Vec3::new(3.0, 0.0, -3.0),
    ];
    for (flip, want) in [(false, 2.0f32), (true, 0.0)] {
        let mut s = path_scene(4, 4, Vec3::new(0.0, 3.0, 0.5));
        let mut v = up;
        if flip {
            v.reverse();
        }
        let m = material(&mut s, emissive(2.0));
        object(&mut s, quad("lamp", v[0], v[1], v[2], v[3]), m);
        s.settings.background = Rgb::splat(0.25);
        let (img, _) = render(&s);
        for p in &img.pixels {
            assert!((p.x - want).abs() < 1e-6, "flip {flip}: {p}");
        }
    }
}

#[test]
fn path_images_do_not_depend_on_threads_or_the_accelerator() {
    let mut s = kitchen_sink(20, 16);
    s.settings.integrator = IntegratorChoice::Path;
    s.settings.sampler = gridrt_tracer::SamplerKind::Sobol;
    let (a, sa) = render_with(&s, &opts(AccelKind::Grid, Some(1)));
    let (b, sb) = render_with(&s, &opts(AccelKind::Grid, Some(3)));
    let (c, _) = render_with(&s, &opts(AccelKind::Exhaustive, Some(2)));
    assert_eq!(sa.plan.integrator, IntegratorKind::Path);
    assert_eq!(a.pixels, b.pixels);
    assert_eq!(a.pixels, c.pixels);
    assert_eq!(sa.rays, sb.rays);
    // Glass, mirror, Phong, diffuse, area light and point lights are all
    // there, so every kind of ray is traced.
    let r = sa.rays;
    assert!(r.light_sample > 0 && r.indirect > 0 && r.glossy > 0);
    assert!(r.reflection > 0 && r.refraction > 0 && r.shadow > 0);
}

#[test]
fn auto_path_traces_only_when_some_object_emits() {
    let mut s = empty_scene(8, 8, Vec3::new(0.0, 0.0, 4.0));
    let m = material(&mut s, matte(Rgb::splat(0.5), 0.2, 0.8));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    s.lights = vec![directional(Vec3::ONE, 1.0, true)];
    assert_eq!(s.settings.integrator, IntegratorChoice::Auto);
    let (_, st) = render(&s);
    assert_eq!(st.plan.integrator, IntegratorKind::RayCast);
    let r = st.rays;
    assert_eq!((r.light_sample, r.glossy, r.indirect), (0, 0, 0));
    // An emissive sphere: path tracing, with the sphere as an area light.
    let e = material(&mut s, emissive(3.0));
    object(&mut s, sphere(Vec3::new(0.0, 2.5, 0.0), 0.5), e);
    let (_, st) = render(&s);
    assert_eq!(st.plan.integrator, IntegratorKind::Path);
    assert_eq!(st.plan.area_lights, 1);
    assert!(st.rays.light_sample > 0 && st.rays.indirect > 0);
    // No glossy material, no glass, no mirror: none of those rays.
    assert!(!st.plan.glossy);
    assert_eq!(
        (st.rays.glossy, st.rays.reflection, st.rays.refraction),
        (0, 0, 0)
    );
    // 1 spp: the pixel centre, no filter.
    assert!(!st.plan.jitter);
    // The directional light casts shadow rays; without it, none.
    assert!(st.rays.shadow > 0);
    s.lights.clear();
    let (_, st) = render(&s);
    assert_eq!(st.rays.shadow, 0);
    assert_eq!(st.plan.direct_lights, 0);
}

#[test]
fn path_tracing_a_scene_where_nothing_emits_is_an_error() {
    let mut s = path_scene(8, 8, Vec3::new(0.0, 0.0, 4.0));
    let m = material(&mut s, matte(Rgb::splat(0.5), 0.2, 0.8));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    let e = gridrt_tracer::render(&s, &Default::default()).unwrap_err();
    assert_eq!(e, SceneError::NothingEmits);
    assert!(e.to_string().contains("nothing emits light"));
    // A background is an environment light: fine.
    s.settings.background = Rgb::splat(0.2);
    assert!(gridrt_tracer::render(&s, &Default::default()).is_ok());
}

#[test]
fn the_path_depth_bounds_paths() {
    // Depth 0: only what the camera sees directly (the lamp), no bounce.
    let lamp = box_mesh(Vec3::new(-0.4, 1.85, -0.4), Vec3::new(0.4, 1.9, 0.4));
    let mut s = closed_box(lamp, emissive(4.0));
    s.settings.spp = 2;
    s.settings.path_max_depth = 0;
    let (_, st) = render(&s);
    assert_eq!(st.rays.total(), st.rays.camera);
    s.settings.path_max_depth = 1;
    let (_, st1) = render(&s);
    assert!(st1.rays.indirect > 0 && st1.rays.indirect <= st1.rays.camera);
}
