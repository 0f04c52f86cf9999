//! Shading normals never leak: a light below a surface lights nothing and a
//! mirror never reflects what lies below it, however far the vertex normals
//! tilt (the geometric normal decides the side, as in pbrt).

use crate::common::{directional, empty_scene, material, matte, object, render};
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{Geometry, Material, Mesh, Projection, Rgb, Scene};

/// An 8 × 8 floor of two triangles at y = 0.5, facing up, every vertex
/// normal `n`; the camera at `eye` looks at its centre with a narrow
/// field, so every pixel sees the floor.
fn tilted_floor(n: Vec3, eye: Vec3, floor: Material) -> Scene {
    let mut s = empty_scene(16, 12, eye);
    s.camera.projection = Projection::Perspective { vfov_deg: 10.0 };
    let m = material(&mut s, floor);
    let r: Real = 4.0;
    let lift = Vec3::new(0.0, 0.5, 0.0);
    s.camera.look_at = lift;
    let mesh = Mesh {
        name: "floor".into(),
        positions: vec![
            Vec3::new(-r, 0.0, -r) + lift,
            Vec3::new(-r, 0.0, r) + lift,
            Vec3::new(r, 0.0, r) + lift,
            Vec3::new(r, 0.0, -r) + lift,
        ],
        normals: vec![n.normalize(); 4],
        uvs: vec![],
        uvs1: vec![],
        colors: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    object(&mut s, Geometry::Mesh(std::sync::Arc::new(mesh)), m);
    s
}

#[test]
fn a_light_below_the_surface_lights_nothing_through_a_tilted_normal() {
    // The shading normal leans 79° towards +x; the light comes from +x,
    // 6° below the floor: ns · wi > 0 but ng · wi < 0.
    let floor = matte(Rgb::ONE, 0.0, 1.0);
    let mut s = tilted_floor(Vec3::new(1.0, 0.2, 0.0), Vec3::new(0.0, 5.0, 1.0), floor);
    s.lights
        .push(directional(Vec3::new(1.0, -0.1, 0.0), 3.0, false));
    let (img, _) = render(&s);
    assert!(
        img.pixels.iter().all(|p| *p == Rgb::ZERO),
        "the floor is lit from below"
    );
    // The same light above the floor lights it: the test can fail.
    s.lights[0] = directional(Vec3::new(1.0, 0.1, 0.0), 3.0, false);
    let (img, _) = render(&s);
    assert!(img.pixels.iter().all(|p| p.x > 0.0));
}

#[test]
fn a_mirror_never_reflects_what_lies_below_it() {
    // Seen from (0, 1, 3), a mirror normal leaning almost onto +z reflects
    // the view ray below the floor, where an emissive plane shines; the
    // reflection must stay above (the background, black).
    let mirror = Material::Reflective {
        color: Rgb::ZERO,
        ka: 0.0,
        kd: 0.0,
        ks: 0.0,
        exp: 1.0,
        kr: 1.0,
        reflect: Rgb::ONE,
    };
    let mut s = tilted_floor(Vec3::new(0.0, 0.05, 1.0), Vec3::new(0.0, 1.0, 3.0), mirror);
    let glow = material(
        &mut s,
        Material::Emissive {
            color: Rgb::ONE,
            strength: 1.0,
        },
    );
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            normal: Vec3::Y,
        },
        glow,
    );
    let (img, stats) = render(&s);
    assert!(stats.rays.reflection > 0);
    let lit = img.pixels.iter().filter(|p| **p != Rgb::ZERO).count();
    assert_eq!(lit, 0, "the mirror shows what is below it in {lit} pixels");
    // A glowing plane above the floor, facing it (emission is one-sided),
    // is seen in the mirror.
    if let gridrt_tracer::Geometry::Plane { point, normal } = &mut s.objects[1].geometry {
        *point = Vec3::new(0.0, 50.0, 0.0);
        *normal = Vec3::NEG_Y;
    }
    let (img, _) = render(&s);
    assert!(img.pixels.iter().any(|p| p.x > 0.0));
}
