//! A Lambertian sphere under one light matches the analytic radiance
//! `ka·cd·La + kd·cd/π · L · cos θ` pixel by pixel (Suffern's conventions).

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{AccelKind, Light, Projection, Rgb};
use std::f64::consts::PI;

const CD: [f64; 3] = [0.9, 0.5, 0.2];

fn expected(ka: f64, la: f64, kd: f64, l: f64, cos: f64) -> [f64; 3] {
    CD.map(|c| ka * c * la + kd * c / PI * l * cos.max(0.0))
}

fn close(got: Rgb, want: [f64; 3], tol: f64) -> bool {
    (0..3).all(|i| (f64::from(got[i]) - want[i]).abs() <= tol * (1.0 + want[i].abs()))
}

#[test]
fn directional_light_orthographic_camera() {
    let (w, h) = (48u32, 40u32);
    let mut s = empty_scene(w, h, Vec3::new(0.0, 0.0, 5.0));
    s.camera.projection = Projection::Orthographic { height: 2.5 };
    s.settings.background = Rgb::splat(0.1);
    let m = material(&mut s, matte(Rgb::new(0.9, 0.5, 0.2), 0.25, 0.75));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    let dir = [-1.0f64, 2.0, 1.5];
    let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
    let l = dir.map(|d| d / len);
    s.lights = vec![
        ambient(1.0),
        directional(Vec3::new(-1.0, 2.0, 1.5), 3.0, true),
    ];
    for accel in [AccelKind::Grid, AccelKind::Exhaustive] {
        let (img, stats) = render_with(&s, &opts(accel, None));
        // One convex sphere: nothing to shadow, so no shadow rays.
        assert_eq!(stats.rays.shadow, 0);
        let px = 2.5 / f64::from(h);
        let mut checked = 0;
        for y in 0..h {
            for x in 0..w {
                let r = h - 1 - y;
                let ox = px * (f64::from(x) - f64::from(w) / 2.0 + 0.5);
                let oy = px * (f64::from(r) - f64::from(h) / 2.0 + 0.5);
                let d2 = ox * ox + oy * oy;
                let got = img.get(x, y);
                if (d2 - 1.0).abs() < 1e-3 {
                    continue; // the silhouette: hit or miss is a coin toss
                }
                if d2 > 1.0 {
                    assert_eq!(got, Rgb::splat(0.1), "background at ({x}, {y})");
                    continue;
                }
                let n = [ox, oy, (1.0 - d2).sqrt()];
                let cos = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
                let want = expected(0.25, 1.0, 0.75, 3.0, cos);
                assert!(
                    close(got, want, 2e-5),
                    "({x}, {y}): got {got:?}, want {want:?}"
                );
                checked += 1;
            }
        }
        assert!(checked > 600, "{checked} pixels checked");
    }
}

/// Ray/sphere in f64: the nearest t > 0, if the ray is not near grazing.
fn hit_f64(o: [f64; 3], d: [f64; 3], c: [f64; 3], r: f64) -> Option<f64> {
    let f = [o[0] - c[0], o[1] - c[1], o[2] - c[2]];
    let a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    let cc = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;
    let disc = b * b - a * cc;
    if disc < 1e-3 * r * r * a {
        return None;
    }
    let t = (-b - disc.sqrt()) / a;
    (t > 0.0).then_some(t)
}

#[test]
fn point_light_inverse_square_view_plane_camera_with_shadow_rays() {
    let (w, h) = (40u32, 40u32);
    let mut s = empty_scene(w, h, Vec3::new(0.0, 0.0, 6.0));
    s.camera.projection = Projection::ViewPlane {
        distance: 50.0,
        pixel_size: 0.1,
    };
    let m = material(&mut s, matte(Rgb::new(0.9, 0.5, 0.2), 0.0, 0.75));
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    // A second sphere far behind the eye: it shadows nothing in view, but it
    // makes the plan cast shadow rays, so the test also proves that a lit
    // point does not shadow itself (no acne).
    object(&mut s, sphere(Vec3::new(0.0, 0.0, 30.0), 0.1), m);
    let light = [2.0f64, 3.0, 4.0];
    s.lights = vec![Light::Point {
        position: Vec3::new(2.0, 3.0, 4.0),
        color: Rgb::ONE,
        intensity: 30.0,
        inverse_square: true,
        shadows: true,
    }];
    let (img, stats) = render(&s);
    assert!(stats.plan.shadows);
    assert!(stats.rays.shadow > 0);
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let r = h - 1 - y;
            let d = [
                0.1 * (f64::from(x) - 20.0 + 0.5),
                0.1 * (f64::from(r) - 20.0 + 0.5),
                -50.0,
            ];
            let o = [0.0, 0.0, 6.0];
            let got = img.get(x, y);
            let Some(t) = hit_f64(o, d, [0.0; 3], 1.0) else {
                continue;
            };
            let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
            let to = [light[0] - p[0], light[1] - p[1], light[2] - p[2]];
            let dist2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
            let cos = (p[0] * to[0] + p[1] * to[1] + p[2] * to[2]) / dist2.sqrt();
            let want = expected(0.0, 0.0, 0.75, 30.0 / dist2, cos);
            assert!(
                close(got, want, 1e-4),
                "({x}, {y}): got {got:?}, want {want:?}"
            );
            checked += 1;
        }
    }
    assert!(checked > 400, "{checked} pixels checked");
}

#[test]
fn suffern_convention_radiance_3_kd_075() {
    // Straight on, light from the camera: cos θ = 1 at the centre pixel.
    let mut s = empty_scene(1, 1, Vec3::new(0.0, 0.0, 5.0));
    s.camera.projection = Projection::Orthographic { height: 0.01 };
    let m = material(&mut s, matte(Rgb::new(0.9, 0.5, 0.2), 0.25, 0.75));
    object(&mut s, sphere(Vec3::ZERO, 1.0 as Real), m);
    s.lights = vec![directional(Vec3::Z, 3.0, false)];
    let (img, _) = render(&s);
    let want = CD.map(|c| 0.75 * c / PI * 3.0);
    assert!(
        close(img.get(0, 0), want, 1e-6),
        "{:?} vs {want:?}",
        img.get(0, 0)
    );
}

#[test]
fn phong_highlight_in_the_mirror_direction() {
    // Light and eye both straight above the top of a sphere: r = wo, so the
    // highlight is ks·cs·L·cos θ with cos θ = 1, on top of kd·cd/π·L.
    let mut s = empty_scene(1, 1, Vec3::new(0.0, 0.0, 5.0));
    s.camera.projection = Projection::Orthographic { height: 1e-3 };
    let m = material(
        &mut s,
        gridrt_tracer::Material::Phong {
            color: Rgb::new(0.9, 0.5, 0.2),
            ka: 0.0,
            kd: 0.5,
            ks: 0.3,
            exp: 40.0,
            specular: Rgb::new(1.0, 1.0, 0.5),
        },
    );
    object(&mut s, sphere(Vec3::ZERO, 1.0), m);
    s.lights = vec![directional(Vec3::Z, 2.0, false)];
    let (img, _) = render(&s);
    let spec = [1.0, 1.0, 0.5];
    let want: Vec<f64> = (0..3)
        .map(|i| (0.5 * CD[i] / PI + 0.3 * spec[i]) * 2.0)
        .collect();
    assert!(
        close(img.get(0, 0), [want[0], want[1], want[2]], 1e-5),
        "{:?} vs {want:?}",
        img.get(0, 0)
    );
}

#[test]
fn smooth_mesh_shades_like_the_sphere_it_approximates() {
    // A finely tessellated sphere with per-vertex normals against the exact
    // sphere: same light, same camera. Interpolated normals must point the
    // right way (barycentric u, v weight vertices 1 and 2).
    let scene = |geometry: gridrt_tracer::Geometry| {
        let mut s = empty_scene(32, 32, Vec3::new(0.0, 0.0, 5.0));
        s.camera.projection = Projection::Orthographic { height: 2.4 };
        let m = material(&mut s, matte(Rgb::ONE, 0.0, 1.0));
        object(&mut s, geometry, m);
        s.lights = vec![directional(Vec3::new(1.0, 1.0, 2.0), 3.0, false)];
        s
    };
    let (exact, _) = render(&scene(sphere(Vec3::ZERO, 1.0)));
    let mesh = uv_sphere(Vec3::ZERO, 1.0, 96, 48);
    let (smooth, _) = render(&scene(gridrt_tracer::Geometry::Mesh(std::sync::Arc::new(
        mesh.clone(),
    ))));
    let mut flat_mesh = mesh;
    flat_mesh.normals.clear();
    let (flat, _) = render(&scene(gridrt_tracer::Geometry::Mesh(std::sync::Arc::new(
        flat_mesh,
    ))));
    let (mut worst_smooth, mut worst_flat) = (0.0f32, 0.0f32);
    for y in 0..32 {
        for x in 0..32 {
            let (a, b, c) = (exact.get(x, y), smooth.get(x, y), flat.get(x, y));
            // Skip the silhouette, where mesh and sphere differ in coverage.
            if a == Rgb::ZERO || b == Rgb::ZERO || a.x < 0.05 {
                continue;
            }
            worst_smooth = worst_smooth.max((a - b).abs().max_element());
            worst_flat = worst_flat.max((a - c).abs().max_element());
        }
    }
    assert!(worst_smooth < 0.01, "smooth normals off by {worst_smooth}");
    // Flat facets are visibly worse: the smooth normals are in use.
    assert!(
        worst_flat > 2.0 * worst_smooth,
        "flat {worst_flat} vs smooth {worst_smooth}"
    );
}
