//! Helpers shared by the tests: small scenes and a checked render.

use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{
    AccelKind, Camera, Framebuffer, Geometry, Light, Material, Object, Projection, RenderOptions,
    RenderStats, Rgb, Scene, Settings,
};

/// Options for an accelerator and a thread count.
pub fn opts(accel: AccelKind, threads: Option<usize>) -> RenderOptions {
    RenderOptions {
        accel,
        threads,
        ..RenderOptions::default()
    }
}

/// Panics with the pixel's position when any pixel is NaN or infinite.
pub fn assert_finite(img: &Framebuffer) {
    assert_eq!(img.pixels.len(), img.width as usize * img.height as usize);
    if let Some(i) = img.pixels.iter().position(|p| !p.is_finite()) {
        panic!(
            "pixel ({}, {}) is {:?}",
            i % img.width as usize,
            i / img.width as usize,
            img.pixels[i]
        );
    }
}

/// Renders with the options and checks every pixel is finite.
pub fn render_with(scene: &Scene, options: &RenderOptions) -> (Framebuffer, RenderStats) {
    let (img, stats) = gridrt_tracer::render(scene, options).expect("valid scene");
    assert_finite(&img);
    assert_eq!(
        stats.rays.camera,
        u64::from(img.width * img.height * scene.settings.spp)
    );
    (img, stats)
}

/// Renders with the default options (grid, all threads), checked.
pub fn render(scene: &Scene) -> (Framebuffer, RenderStats) {
    render_with(scene, &RenderOptions::default())
}

/// A scene with no objects: `w × h`, 1 spp, max depth 5, black background,
/// the camera at `eye` looking at the origin (up +y) with a 40° field.
pub fn empty_scene(w: u32, h: u32, eye: Vec3) -> Scene {
    Scene {
        textures: Default::default(),
        camera: Camera {
            eye,
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Perspective { vfov_deg: 40.0 },
            lens: None,
        },
        settings: Settings {
            width: w,
            height: h,
            spp: 1,
            max_depth: 5,
            background: Rgb::ZERO,
            ..Settings::default()
        },
        materials: Vec::new(),
        lights: Vec::new(),
        objects: Vec::new(),
    }
}

/// Adds a material and returns its index.
pub fn material(scene: &mut Scene, m: Material) -> u32 {
    scene.materials.push(m);
    (scene.materials.len() - 1) as u32
}

/// Adds an object.
pub fn object(scene: &mut Scene, geometry: Geometry, material: u32) {
    scene.objects.push(Object { geometry, material });
}

pub fn sphere(center: Vec3, radius: Real) -> Geometry {
    Geometry::Sphere { center, radius }
}

pub fn matte(color: Rgb, ka: f32, kd: f32) -> Material {
    Material::Matte { color, ka, kd }
}

pub fn directional(direction: Vec3, intensity: f32, shadows: bool) -> Light {
    Light::Directional {
        direction,
        color: Rgb::ONE,
        intensity,
        shadows,
    }
}

pub fn ambient(intensity: f32) -> Light {
    Light::Ambient {
        color: Rgb::ONE,
        intensity,
        occlusion: None,
    }
}

/// A UV sphere mesh (`slices × stacks`), with per-vertex normals.
pub fn uv_sphere(center: Vec3, r: Real, slices: u32, stacks: u32) -> gridrt_tracer::Mesh {
    let mut m = gridrt_tracer::Mesh {
        name: "uv sphere".into(),
        ..Default::default()
    };
    for k in 0..=stacks {
        for j in 0..slices {
            let th = std::f64::consts::PI * f64::from(k) / f64::from(stacks);
            let ph = 2.0 * std::f64::consts::PI * f64::from(j) / f64::from(slices);
            let n = Vec3::new(
                (th.sin() * ph.sin()) as Real,
                th.cos() as Real,
                (th.sin() * ph.cos()) as Real,
            );
            m.positions.push(center + n * r);
            m.normals.push(n);
        }
    }
    let idx = |k: u32, j: u32| k * slices + j % slices;
    for k in 0..stacks {
        for j in 0..slices {
            m.triangles
                .push([idx(k, j), idx(k + 1, j), idx(k + 1, j + 1)]);
            m.triangles
                .push([idx(k, j), idx(k + 1, j + 1), idx(k, j + 1)]);
        }
    }
    m
}

/// A scene with one of everything: spheres, a box, a smooth mesh, a plane;
/// matte, Phong, mirror, glass and emissive materials; ambient, point and
/// directional lights with shadows; 2 spp.
pub fn kitchen_sink(w: u32, h: u32) -> Scene {
    let mut s = empty_scene(w, h, Vec3::new(1.0, 2.5, 7.0));
    s.settings.spp = 2;
    s.settings.max_depth = 4;
    s.settings.background = Rgb::new(0.1, 0.2, 0.3);
    // Its emissive sphere would make `Auto` path trace; these tests are
    // about the Whitted tracer (tests/path.rs path traces it).
    s.settings.integrator = gridrt_tracer::IntegratorChoice::Whitted;
    let red = material(&mut s, matte(Rgb::new(0.8, 0.2, 0.1), 0.2, 0.8));
    let phong = material(
        &mut s,
        Material::Phong {
            color: Rgb::new(0.2, 0.6, 0.3),
            ka: 0.1,
            kd: 0.6,
            ks: 0.4,
            exp: 20.0,
            specular: Rgb::ONE,
        },
    );
    let mirror = material(
        &mut s,
        Material::Reflective {
            color: Rgb::splat(0.5),
            ka: 0.0,
            kd: 0.1,
            ks: 0.2,
            exp: 50.0,
            kr: 0.8,
            reflect: Rgb::ONE,
        },
    );
    let glass = material(
        &mut s,
        Material::Dielectric {
            ior: 1.5,
            tint: Rgb::new(0.9, 0.95, 1.0),
        },
    );
    let lamp = material(
        &mut s,
        Material::Emissive {
            color: Rgb::new(1.0, 0.9, 0.7),
            strength: 2.0,
        },
    );
    let floor = material(&mut s, matte(Rgb::splat(0.7), 0.1, 0.9));
    object(&mut s, sphere(Vec3::new(-1.2, 0.0, 0.0), 0.7), red);
    object(&mut s, sphere(Vec3::new(0.3, 0.0, -0.8), 0.6), glass);
    object(&mut s, sphere(Vec3::new(1.5, 1.5, -2.0), 0.3), lamp);
    object(
        &mut s,
        Geometry::Cuboid {
            min: Vec3::new(0.8, -0.7, 0.2),
            max: Vec3::new(1.6, 0.1, 1.0),
        },
        mirror,
    );
    object(
        &mut s,
        Geometry::Mesh(std::sync::Arc::new(uv_sphere(
            Vec3::new(-0.2, 0.9, -1.5),
            0.6,
            12,
            7,
        ))),
        phong,
    );
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::new(0.0, -0.7, 0.0),
            normal: Vec3::Y,
        },
        floor,
    );
    s.lights = vec![
        ambient(0.5),
        directional(Vec3::new(-1.0, 2.0, 1.5), 2.0, true),
        Light::Point {
            position: Vec3::new(2.0, 3.0, 2.0),
            color: Rgb::new(1.0, 0.8, 0.6),
            intensity: 20.0,
            inverse_square: true,
            shadows: true,
        },
    ];
    s
}
