//! Secondary-ray origins at every scale and far from the origin: a small
//! mesh on a floor keeps its shadow (no light leaks) and the lit floor stays
//! lit (no acne), from scale 10⁻⁸ to 10⁸ and offsets up to 10⁶, wherever
//! the precision resolves the scene.

use crate::common::{directional, empty_scene, material, matte, object, render};
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{Framebuffer, Geometry, Light, Mesh, Projection, Rgb, Scene};

/// A floor plane, a unit cube of triangles standing on it and a thin
/// triangle tent, lit by a point light and a directional light that both
/// cast shadows, seen from above; every length times `scale`, every
/// position moved by `offset` on all three axes.
fn shadow_scene(scale: Real, offset: Real) -> Scene {
    let at = |x: Real, y: Real, z: Real| Vec3::new(x, y, z) * scale + Vec3::splat(offset);
    let mut s = empty_scene(48, 36, at(0.0, 6.0, 3.0));
    s.camera.look_at = at(0.0, 0.0, 0.0);
    s.camera.projection = Projection::Perspective { vfov_deg: 60.0 };
    let m = material(&mut s, matte(Rgb::splat(0.8), 0.0, 1.0));
    object(
        &mut s,
        Geometry::Plane {
            point: at(0.0, 0.0, 0.0),
            normal: Vec3::Y,
        },
        m,
    );
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
    // A low tent, 0.01 to 0.08 above the floor: its shadow is lost if an
    // offset lifts shadow rays above it.
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
    object(&mut s, Geometry::Mesh(Box::new(cube)), m);
    s.lights = vec![
        directional(Vec3::new(1.0, 0.7, 0.2), 1.5, true),
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
/// above, seen from a camera between the two. The floor under the top is
/// in shadow, the rest lit; a shadow-ray origin lifted by more than 0.1 (an offset bound
/// of ulps of every coordinate far from the origin) lights it.
fn table_scene(scale: Real, offset: Real) -> Scene {
    let at = |x: Real, y: Real, z: Real| Vec3::new(x, y, z) * scale + Vec3::splat(offset);
    let mut s = empty_scene(48, 36, at(0.0, 0.09, 0.2));
    s.camera.look_at = at(0.0, 0.0, 0.0);
    s.camera.projection = Projection::Perspective { vfov_deg: 60.0 };
    let m = material(&mut s, matte(Rgb::splat(0.8), 0.0, 1.0));
    object(
        &mut s,
        Geometry::Plane {
            point: at(0.0, 0.0, 0.0),
            normal: Vec3::Y,
        },
        m,
    );
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
    object(&mut s, Geometry::Mesh(Box::new(top)), m);
    s.lights = vec![directional(Vec3::new(0.2, 1.0, 0.1), 2.0, true)];
    s
}

/// Pixels that are lit in `reference` and darker in `image` (acne), and
/// the reverse (leaks), counted only where the reference's 5×5
/// neighbourhood is flat, so that silhouettes and shadow edges, which
/// rounding may move by a pixel or two where a pixel is a few ulps wide,
/// do not count.
fn acne_and_leaks(reference: &Framebuffer, image: &Framebuffer) -> (usize, usize) {
    let (w, h) = (reference.width as usize, reference.height as usize);
    let lum = |img: &Framebuffer, x: usize, y: usize| img.pixels[y * w + x].max_element();
    let (mut acne, mut leaks) = (0, 0);
    for y in 2..h - 2 {
        for x in 2..w - 2 {
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

#[test]
fn shadows_hold_at_every_scale_and_offset() {
    let mut failures = Vec::new();
    for (name, scene) in [
        ("cube and tent", shadow_scene as fn(Real, Real) -> Scene),
        ("table", table_scene),
    ] {
        let (reference, stats) = render(&scene(1.0, 0.0));
        assert!(stats.rays.shadow > 0);
        // The scene has shadows to lose: dark and lit floor pixels both.
        let dark = reference
            .pixels
            .iter()
            .filter(|p| p.max_element() < 0.45)
            .count();
        let lit = reference
            .pixels
            .iter()
            .filter(|p| p.max_element() > 0.45)
            .count();
        assert!(
            dark > 40 && lit > 40,
            "{name}: {dark} dark, {lit} lit pixels"
        );
        for scale in [1e-8, 1e-4, 1e-2, 1.0, 1e2, 1e4, 1e8] {
            for offset in [0.0, 1e3, 1e5, 1e6] {
                // The scene (a pixel about 0.1 across) spans at least 64
                // ulps of the offset, so a pixel is a few ulps wide.
                if scale < offset * Real::EPSILON * 64.0 {
                    continue;
                }
                let (img, _) = render(&scene(scale, offset));
                let (acne, leaks) = acne_and_leaks(&reference, &img);
                if acne + leaks > 0 {
                    failures.push(format!(
                        "{name}: scale {scale:e} offset {offset:e}: {acne} acne, {leaks} leaks"
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
