//! Invalid scenes are errors that say what to fix, never panics.

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::suffern::DrawnColors;
use gridrt_tracer::{
    Geometry, Light, Material, Mesh, Object, Projection, RenderOptions, Renderer, Rgb, Scene,
    SceneError, Sphere, SphereColors, SphereSet,
};
use std::sync::Arc;

fn valid() -> Scene {
    let mut s = empty_scene(4, 4, Vec3::new(0.0, 0.0, 5.0));
    let m = material(&mut s, matte(Rgb::ONE, 0.1, 0.9));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    s.lights = vec![ambient(1.0)];
    s
}

fn err(s: &Scene) -> SceneError {
    let e = Renderer::new(s, &RenderOptions::default()).expect_err("invalid scene");
    assert!(!e.to_string().is_empty());
    e
}

#[test]
fn settings_and_camera() {
    assert!(Renderer::new(&valid(), &RenderOptions::default()).is_ok());
    let mut s = valid();
    s.settings.width = 0;
    assert!(matches!(err(&s), SceneError::EmptyImage { width: 0, .. }));
    let mut s = valid();
    s.settings.width = 100_000;
    s.settings.height = 100_000;
    assert!(matches!(err(&s), SceneError::ImageTooLarge { .. }));
    let mut s = valid();
    s.settings.spp = 0;
    assert_eq!(err(&s), SceneError::ZeroSamples);
    let mut s = valid();
    s.settings.background = Rgb::new(f32::NAN, 0.0, 0.0);
    assert!(matches!(err(&s), SceneError::SettingNotFinite { .. }));
    let mut s = valid();
    s.camera.look_at = s.camera.eye;
    assert_eq!(err(&s), SceneError::CameraEyeAtLookAt);
    assert!(err(&s).to_string().contains("look_at"));
    let mut s = valid();
    s.camera.up = Vec3::new(0.0, 0.0, -3.0);
    assert_eq!(err(&s), SceneError::CameraUpParallel);
    let mut s = valid();
    s.camera.up = Vec3::ZERO;
    assert_eq!(err(&s), SceneError::CameraUpParallel);
    let mut s = valid();
    s.camera.eye.y = Real::INFINITY;
    assert!(matches!(
        err(&s),
        SceneError::CameraNotFinite { what: "eye" }
    ));
    for p in [
        Projection::Perspective { vfov_deg: 0.0 },
        Projection::Perspective {
            vfov_deg: Real::NAN,
        },
        Projection::ViewPlane {
            distance: -1.0,
            pixel_size: 1.0,
        },
        Projection::ViewPlane {
            distance: 1.0,
            pixel_size: 0.0,
        },
        Projection::Orthographic {
            height: Real::INFINITY,
        },
    ] {
        let mut s = valid();
        s.camera.projection = p;
        assert!(
            matches!(err(&s), SceneError::CameraProjection { .. }),
            "{p:?}"
        );
    }
}

#[test]
fn objects() {
    let mut s = valid();
    s.objects[0].material = 7;
    let e = err(&s);
    assert_eq!(
        e,
        SceneError::MaterialOutOfRange {
            object: 0,
            material: 7,
            count: 1
        }
    );
    assert!(e.to_string().contains("object 0") && e.to_string().contains("7"));
    for radius in [0.0, -1.0, Real::NAN, Real::INFINITY] {
        let mut s = valid();
        s.objects[0].geometry = sphere(Vec3::ZERO, radius);
        assert!(
            matches!(err(&s), SceneError::BadRadius { object: 0, .. }),
            "{radius}"
        );
    }
    let mut s = valid();
    s.objects[0].geometry = sphere(Vec3::new(Real::NAN, 0.0, 0.0), 1.0);
    assert!(matches!(err(&s), SceneError::NotFinite { object: 0, .. }));
    let mut s = valid();
    s.objects[0].geometry = Geometry::Cuboid {
        min: Vec3::ONE,
        max: Vec3::ZERO,
    };
    assert_eq!(err(&s), SceneError::InvertedCuboid { object: 0 });
    let mut s = valid();
    s.objects[0].geometry = Geometry::Plane {
        point: Vec3::ZERO,
        normal: Vec3::ZERO,
    };
    assert_eq!(err(&s), SceneError::ZeroNormal { object: 0 });
}

#[test]
fn meshes() {
    let tri = |positions: Vec<Vec3>, triangles: Vec<[u32; 3]>| {
        let mut s = valid();
        s.objects[0].geometry = Geometry::Mesh(Arc::new(Mesh {
            name: "bad.obj".into(),
            positions,
            triangles,
            ..Mesh::default()
        }));
        s
    };
    let e = err(&tri(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 3]]));
    assert!(matches!(
        e,
        SceneError::MeshIndexOutOfRange {
            triangle: 0,
            index: 3,
            vertices: 3,
            ..
        }
    ));
    assert!(e.to_string().contains("bad.obj"));
    let e = err(&tri(
        vec![Vec3::ZERO, Vec3::new(Real::NAN, 0.0, 0.0), Vec3::Y],
        vec![[0, 1, 2]],
    ));
    assert!(matches!(e, SceneError::MeshNotFinite { vertex: 1, .. }));
    let mut s = tri(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
    if let Geometry::Mesh(m) = &mut s.objects[0].geometry {
        std::sync::Arc::make_mut(m).normals = vec![Vec3::Z; 2];
    }
    assert!(matches!(
        err(&s),
        SceneError::MeshAttributeCount {
            attribute: "normals",
            count: 2,
            ..
        }
    ));
    // Degenerate triangles are fine. A collinear one stays (the shear's
    // rounding can make it close a crack); one with two equal vertices
    // can never be hit and is left out.
    let s = tri(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0)],
        vec![[0, 1, 2], [0, 0, 0], [0, 1, 1]],
    );
    let r = Renderer::new(&s, &RenderOptions::default()).unwrap();
    assert_eq!(r.primitive_count(), 1);
}

#[test]
fn materials_and_lights() {
    for m in [
        Material::Matte {
            color: Rgb::new(-1.0, 0.0, 0.0),
            ka: 0.0,
            kd: 1.0,
        },
        Material::Matte {
            color: Rgb::ONE,
            ka: f32::NAN,
            kd: 1.0,
        },
        Material::Dielectric {
            ior: 0.0,
            tint: Rgb::ONE,
        },
        Material::Emissive {
            color: Rgb::ONE,
            strength: f32::INFINITY,
        },
    ] {
        let mut s = valid();
        s.materials[0] = m.clone();
        assert!(
            matches!(err(&s), SceneError::BadMaterial { material: 0, .. }),
            "{m:?}"
        );
    }
    for l in [
        Light::Directional {
            direction: Vec3::ZERO,
            color: Rgb::ONE,
            intensity: 1.0,
            shadows: true,
        },
        Light::Point {
            position: Vec3::new(0.0, Real::NAN, 0.0),
            color: Rgb::ONE,
            intensity: 1.0,
            inverse_square: false,
            shadows: true,
        },
        Light::Ambient {
            color: Rgb::ONE,
            intensity: -2.0,
            occlusion: None,
        },
    ] {
        let mut s = valid();
        s.lights.push(l.clone());
        assert!(
            matches!(err(&s), SceneError::BadLight { light: 1, .. }),
            "{l:?}"
        );
    }
}

#[test]
fn sphere_sets() {
    let o = RenderOptions::default();
    // The scene `valid()` plus one sphere-set object.
    let with = |spheres: Vec<Sphere>, colors: Vec<Rgb>, material| {
        let mut s = valid();
        s.objects.push(Object {
            geometry: Geometry::Spheres(Arc::new(SphereSet {
                spheres,
                colors: SphereColors::Each(colors),
            })),
            material,
        });
        Renderer::new(&s, &o)
    };
    let e = with(vec![Sphere::new(Vec3::ZERO, 1.0)], vec![], 3).unwrap_err();
    assert!(matches!(
        e,
        SceneError::MaterialOutOfRange { object: 1, .. }
    ));
    let e = with(vec![Sphere::new(Vec3::ZERO, 1.0)], vec![Rgb::ONE; 2], 0).unwrap_err();
    assert!(matches!(
        e,
        SceneError::SphereSetColors {
            object: 1,
            colors: 2,
            spheres: 1
        }
    ));
    // Drawn colours are counted as given ones.
    let mut s = valid();
    s.objects.push(Object {
        geometry: Geometry::Spheres(Arc::new(SphereSet {
            spheres: vec![Sphere::new(Vec3::ZERO, 1.0); 3],
            colors: SphereColors::Drawn(DrawnColors::new(15, 4)),
        })),
        material: 0,
    });
    assert!(matches!(
        Renderer::new(&s, &o).unwrap_err(),
        SceneError::SphereSetColors {
            object: 1,
            colors: 4,
            spheres: 3
        }
    ));
    let e = with(vec![Sphere::new(Vec3::ZERO, 0.0)], vec![], 0).unwrap_err();
    assert!(matches!(
        e,
        SceneError::BadSetSphere {
            object: 1,
            sphere: 0,
            ..
        }
    ));
    // The first bad sphere of several is the one named.
    let good = Sphere::new(Vec3::ONE, 0.5);
    let mut spheres = vec![good; 5];
    spheres[3] = Sphere::new(Vec3::new(0.0, Real::NAN, 0.0), 0.5);
    spheres[4] = Sphere::new(Vec3::ZERO, Real::INFINITY);
    let e = with(spheres.clone(), vec![], 0).unwrap_err();
    assert!(
        matches!(
            e,
            SceneError::BadSetSphere {
                object: 1,
                sphere: 3,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("centre"), "{e}");
    spheres[3] = good;
    let e = with(spheres, vec![], 0).unwrap_err();
    assert!(
        matches!(
            e,
            SceneError::BadSetSphere {
                object: 1,
                sphere: 4,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("radius"), "{e}");
    let mut colors = vec![Rgb::ONE; 5];
    colors[2] = Rgb::new(0.5, -0.1, 0.5);
    let e = with(vec![good; 5], colors, 0).unwrap_err();
    assert!(
        matches!(
            e,
            SceneError::BadSetSphere {
                object: 1,
                sphere: 2,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(with(vec![good; 5], vec![Rgb::ONE; 5], 0).is_ok());
}

#[test]
fn empty_scene_renders_the_background() {
    let mut s = valid();
    s.objects.clear();
    s.settings.background = Rgb::new(0.1, 0.2, 0.3);
    let (img, stats) = render(&s);
    assert!(img.pixels.iter().all(|p| *p == Rgb::new(0.1, 0.2, 0.3)));
    assert_eq!(stats.pixels_hit, 0);
}
