//! Scenes that lose their shadows, or gain acne, when secondary rays leave
//! surfaces badly, and the counter of such pixels. They can be placed at
//! any scale and distance from the origin; the tracer's tests and
//! `cargo xtask accuracy` render them with each [`crate::RayOffset`].
//!
//! ```
//! use gridrt_tracer::offset_scenes::{acne_and_leaks, table_scene};
//! use gridrt_tracer::{render, RenderOptions};
//! let (reference, _) = render(&table_scene(1.0, 0.0), &RenderOptions::default()).unwrap();
//! let (image, _) = render(&table_scene(1e-4, 0.0), &RenderOptions::default()).unwrap();
//! assert_eq!(acne_and_leaks(&reference, &image), (0, 0));
//! ```

use crate::scene::{
    Camera, Geometry, Light, Material, Mesh, Object, Projection, Rgb, Scene, Settings,
};
use crate::Framebuffer;
use gridrt_bbox::{Real, Vec3};

/// A 48 × 36 scene with a matte grey floor plane through `at(0, 0, 0)`,
/// the camera at `eye` looking at `look`.
fn floor_scene(eye: Vec3, look: Vec3, floor: Vec3) -> Scene {
    Scene {
        textures: Default::default(),
        camera: Camera {
            eye,
            look_at: look,
            up: Vec3::Y,
            projection: Projection::Perspective { vfov_deg: 60.0 },
            lens: None,
        },
        settings: Settings {
            width: 48,
            height: 36,
            spp: 1,
            max_depth: 5,
            background: Rgb::ZERO,
            ..Settings::default()
        },
        materials: vec![Material::Matte {
            color: Rgb::splat(0.8),
            ka: 0.0,
            kd: 1.0,
        }],
        lights: Vec::new(),
        objects: vec![Object {
            geometry: Geometry::Plane {
                point: floor,
                normal: Vec3::Y,
            },
            material: 0,
        }],
    }
}

fn sun(direction: Vec3, intensity: f32) -> Light {
    Light::Directional {
        direction,
        color: Rgb::ONE,
        intensity,
        shadows: true,
    }
}

/// A floor plane, a unit cube of triangles standing on it and a thin
/// triangle tent 0.01 to 0.08 above the floor, lit by a point light and a
/// directional light that both cast shadows, seen from above; every length
/// times `scale`, every position moved by `offset` on all three axes.
#[must_use]
pub fn shadow_scene(scale: Real, offset: Real) -> Scene {
    let at = |x: Real, y: Real, z: Real| Vec3::new(x, y, z) * scale + Vec3::splat(offset);
    let mut s = floor_scene(at(0.0, 6.0, 3.0), at(0.0, 0.0, 0.0), at(0.0, 0.0, 0.0));
    let mut cube = Mesh {
        name: "cube".into(),
        ..Mesh::default()
    };
    for i in 0..8u32 {
        let c = |b: u32| if i & b != 0 { 0.5 } else { -0.5 };
        cube.positions.push(at(c(1) - 1.0, c(2) + 0.5, c(4)));
    }
    for f in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        cube.triangles.push([f[0], f[1], f[2]]);
        cube.triangles.push([f[0], f[2], f[3]]);
    }
    // The tent's shadow is lost if an offset lifts shadow rays above it.
    let base = cube.positions.len() as u32;
    for p in [
        at(0.6, 0.01, -1.0),
        at(1.6, 0.01, -1.0),
        at(1.1, 0.08, 1.0),
        at(0.6, 0.01, 1.0),
    ] {
        cube.positions.push(p);
    }
    cube.triangles.push([base, base + 1, base + 2]);
    cube.triangles.push([base, base + 2, base + 3]);
    s.objects.push(Object {
        geometry: Geometry::Mesh(std::sync::Arc::new(cube)),
        material: 0,
    });
    s.lights = vec![
        sun(Vec3::new(1.0, 0.7, 0.2), 1.5),
        Light::Point {
            position: at(-4.0, 3.0, 1.0),
            color: Rgb::ONE,
            intensity: 1.5,
            inverse_square: false,
            shadows: true,
        },
    ];
    s
}

/// Under a low table: a floor and a top 0.1 above it over x < 0, lit from
/// above, seen from a camera between the two (every length times `scale`,
/// moved by `offset`). The floor under the top is in shadow, the rest lit;
/// a shadow-ray origin lifted by more than 0.1·`scale` lights it.
#[must_use]
pub fn table_scene(scale: Real, offset: Real) -> Scene {
    let at = |x: Real, y: Real, z: Real| Vec3::new(x, y, z) * scale + Vec3::splat(offset);
    let mut s = floor_scene(at(0.0, 0.09, 0.2), at(0.0, 0.0, 0.0), at(0.0, 0.0, 0.0));
    let top = Mesh {
        name: "table top".into(),
        positions: vec![
            at(-2.0, 0.1, -3.0),
            at(0.0, 0.1, -3.0),
            at(0.0, 0.1, 3.0),
            at(-2.0, 0.1, 3.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    };
    s.objects.push(Object {
        geometry: Geometry::Mesh(std::sync::Arc::new(top)),
        material: 0,
    });
    s.lights = vec![sun(Vec3::new(0.2, 1.0, 0.1), 2.0)];
    s
}

/// [`shadow_scene`] with mirrors: a mirror of two triangles leaning over
/// the back of the floor and a mirror sphere beside the cube, so reflected
/// rays leave triangles and a sphere towards lit and shadowed floor. A
/// reflected ray that hits its own mirror again darkens the pixel (acne).
#[must_use]
pub fn mirror_scene(scale: Real, offset: Real) -> Scene {
    let at = |x: Real, y: Real, z: Real| Vec3::new(x, y, z) * scale + Vec3::splat(offset);
    let mut s = shadow_scene(scale, offset);
    s.settings.background = Rgb::new(0.3, 0.5, 0.8);
    s.materials.push(Material::Reflective {
        color: Rgb::splat(0.2),
        ka: 0.0,
        kd: 0.3,
        ks: 0.0,
        exp: 1.0,
        kr: 0.7,
        reflect: Rgb::ONE,
    });
    let mirror = (s.materials.len() - 1) as u32;
    let quad = Mesh {
        name: "mirror".into(),
        positions: vec![
            at(-3.0, 0.0, -1.5),
            at(3.0, 0.0, -1.5),
            at(3.0, 2.5, -2.8),
            at(-3.0, 2.5, -2.8),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    };
    s.objects.push(Object {
        geometry: Geometry::Mesh(std::sync::Arc::new(quad)),
        material: mirror,
    });
    s.objects.push(Object {
        geometry: Geometry::Sphere {
            center: at(1.2, 0.6, 1.3),
            radius: 0.6 * scale,
        },
        material: mirror,
    });
    s
}

/// [`shadow_scene`] with glass: the cube and a sphere beside it are clear
/// glass (index 1.5), so refracted rays leave triangles and a sphere from
/// inside and outside. A ray that re-enters the surface it left shows as
/// dark speckle (acne) inside the glass.
#[must_use]
pub fn glass_scene(scale: Real, offset: Real) -> Scene {
    let at = |x: Real, y: Real, z: Real| Vec3::new(x, y, z) * scale + Vec3::splat(offset);
    let mut s = shadow_scene(scale, offset);
    s.settings.background = Rgb::new(0.3, 0.5, 0.8);
    s.materials.push(Material::Dielectric {
        ior: 1.5,
        tint: Rgb::ONE,
    });
    let glass = (s.materials.len() - 1) as u32;
    for o in &mut s.objects {
        if matches!(o.geometry, Geometry::Mesh(_)) {
            o.material = glass;
        }
    }
    s.objects.push(Object {
        geometry: Geometry::Sphere {
            center: at(1.2, 0.6, 1.3),
            radius: 0.6 * scale,
        },
        material: glass,
    });
    s
}

/// Pixels that are lit in `reference` and darker in `image` (acne), and
/// the reverse (leaks), counted only where the reference's 5×5
/// neighbourhood is flat, so that silhouettes and shadow edges, which
/// rounding may move by a pixel or two where a pixel is a few ulps wide,
/// do not count. Both images must have the same size.
///
/// # Panics
/// When the sizes differ.
#[must_use]
pub fn acne_and_leaks(reference: &Framebuffer, image: &Framebuffer) -> (usize, usize) {
    assert_eq!(
        (reference.width, reference.height),
        (image.width, image.height),
        "images of different sizes"
    );
    let (w, h) = (reference.width as usize, reference.height as usize);
    let lum = |img: &Framebuffer, x: usize, y: usize| img.pixels[y * w + x].max_element();
    let (mut acne, mut leaks) = (0, 0);
    for y in 2..h.saturating_sub(2) {
        for x in 2..w.saturating_sub(2) {
            let around = (0..25).map(|k| lum(reference, x + k % 5 - 2, y + k / 5 - 2));
            let (lo, hi) = around.fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(v), b.max(v)));
            if hi - lo > 0.02 {
                continue;
            }
            let (r, t) = (lum(reference, x, y), lum(image, x, y));
            acne += usize::from(t < r - 0.1);
            leaks += usize::from(t > r + 0.1);
        }
    }
    (acne, leaks)
}
