//! The precision study of `cargo xtask accuracy`: the `f32` and `f64`
//! builds of the `gridrt` binary render the same scene files near and far
//! from the origin.

use crate::accuracy::{alternated, Opts, Res};
use crate::util::{self, sig3};
use gridrt_tracer::offset_scenes::{acne_and_leaks, shadow_scene};
use gridrt_tracer::{Framebuffer, Geometry, Light, Material, Projection, Rgb, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// Builds the `gridrt` binary with and without the `f64` feature and
/// copies each under `dir` (`gridrt-f64`, `gridrt-f32`); the f32 build is
/// built last, so `target/release/gridrt` stays the default one.
pub fn build_binaries(dir: &Path) -> Res<[PathBuf; 2]> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    std::fs::create_dir_all(dir)?;
    let mut out = Vec::new();
    for (features, name) in [(Some("f64"), "gridrt-f64"), (None, "gridrt-f32")] {
        eprintln!("accuracy: building the {name} binary");
        let mut c = Command::new(&cargo);
        c.current_dir(util::root()).args([
            "build",
            "--release",
            "-p",
            "gridrt-io",
            "--bin",
            "gridrt",
        ]);
        if let Some(f) = features {
            c.args(["--features", f]);
        }
        let status = c.status()?;
        if !status.success() {
            return Err(format!("building {name} failed ({status})").into());
        }
        let built = util::target_dir()
            .join("release")
            .join(format!("gridrt{}", std::env::consts::EXE_SUFFIX));
        let to = dir.join(name);
        std::fs::copy(&built, &to)?;
        out.push(to);
    }
    let f32 = out.pop().ok_or("no f32 binary")?;
    let f64 = out.pop().ok_or("no f64 binary")?;
    Ok([f32, f64])
}

fn v3(v: gridrt_bbox::Vec3, shift: f64) -> String {
    let c = |x: gridrt_bbox::Real| gridrt_bbox::math::to_f64(x) + shift;
    format!("({}, {}, {})", c(v.x), c(v.y), c(v.z))
}

fn dir3(v: gridrt_bbox::Vec3) -> String {
    v3(v, 0.0)
}

fn rgb(c: Rgb) -> String {
    format!("({}, {}, {})", c.x, c.y, c.z)
}

/// Writes `scene` as a RON file `stem.ron` (and its meshes as OBJ files)
/// under `dir`, every position moved by `shift` along all three axes,
/// added in `f64` and printed with the digits that read back exactly, so
/// an `f64` build reads the shifted scene exactly and an `f32` build
/// rounds each coordinate once. Only what the study's scenes use is
/// written: a perspective camera, matte materials, ambient, point and
/// directional lights, planes, spheres and meshes.
pub fn write_scene(scene: &Scene, shift: f64, dir: &Path, stem: &str) -> Res<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let cam = &scene.camera;
    let Projection::Perspective { vfov_deg } = cam.projection else {
        return Err("the precision study writes perspective cameras only".into());
    };
    let s = &scene.settings;
    let mut t = String::from("Scene(\n");
    let _ = writeln!(
        t,
        "    camera: Camera(eye: {}, look_at: {}, up: {}, projection: Perspective(vfov: {vfov_deg})),",
        v3(cam.eye, shift),
        v3(cam.look_at, shift),
        dir3(cam.up)
    );
    let _ = writeln!(
        t,
        "    settings: Settings(width: {}, height: {}, spp: {}, max_depth: {}, background: {}),",
        s.width,
        s.height,
        s.spp,
        s.max_depth,
        rgb(s.background)
    );
    t += "    materials: {\n";
    for (i, m) in scene.materials.iter().enumerate() {
        let Material::Matte { color, ka, kd } = *m else {
            return Err("the precision study writes matte materials only".into());
        };
        let _ = writeln!(
            t,
            "        \"m{i}\": Matte(color: {}, ka: {ka}, kd: {kd}),",
            rgb(color)
        );
    }
    t += "    },\n    lights: [\n";
    for l in &scene.lights {
        let _ = match *l {
            Light::Ambient {
                color,
                intensity,
                occlusion: None,
            } => {
                writeln!(t, "        Ambient(color: {}, intensity: {intensity}),", rgb(color))
            }
            Light::Ambient {
                color,
                intensity,
                occlusion: Some(o),
            } => {
                let distance = if o.distance.is_finite() {
                    format!(", distance: {}", o.distance)
                } else {
                    String::new()
                };
                writeln!(
                    t,
                    "        Ambient(color: {}, intensity: {intensity}, occlusion: Occlusion(samples: {}{distance}, min_amount: {})),",
                    rgb(color),
                    o.samples,
                    o.min_amount
                )
            }
            Light::Point {
                position,
                color,
                intensity,
                inverse_square,
                shadows,
            } => writeln!(
                t,
                "        Point(position: {}, color: {}, intensity: {intensity}, inverse_square: {inverse_square}, shadows: {shadows}),",
                v3(position, shift),
                rgb(color)
            ),
            Light::Directional {
                direction,
                color,
                intensity,
                shadows,
            } => writeln!(
                t,
                "        Directional(direction: {}, color: {}, intensity: {intensity}, shadows: {shadows}),",
                dir3(direction),
                rgb(color)
            ),
            Light::Spot { .. }
            | Light::Rect { .. }
            | Light::Disk { .. }
            | Light::Environment { .. } => {
                return Err("the precision study writes ambient, point and directional lights only".into());
            }
        };
    }
    t += "    ],\n    objects: [\n";
    for (i, o) in scene.objects.iter().enumerate() {
        let m = format!("\"m{}\"", o.material);
        let _ = match &o.geometry {
            Geometry::Plane { point, normal } => writeln!(
                t,
                "        Plane(point: {}, normal: {}, material: {m}),",
                v3(*point, shift),
                dir3(*normal)
            ),
            Geometry::Sphere { center, radius } => writeln!(
                t,
                "        Sphere(center: {}, radius: {radius}, material: {m}),",
                v3(*center, shift)
            ),
            Geometry::Mesh(mesh) => {
                let file = format!("{stem}-{i}.obj");
                let mut obj = String::new();
                for p in &mesh.positions {
                    let c = |x: gridrt_bbox::Real| gridrt_bbox::math::to_f64(x) + shift;
                    let _ = writeln!(obj, "v {} {} {}", c(p.x), c(p.y), c(p.z));
                }
                for f in &mesh.triangles {
                    let _ = writeln!(obj, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
                }
                util::write_atomic(&dir.join(&file), obj.as_bytes())?;
                writeln!(t, "        Mesh(file: \"{file}\", material: {m}),")
            }
            Geometry::Cuboid { .. } | Geometry::Spheres(_) | Geometry::Instance { .. } => {
                return Err("the precision study writes no boxes, sphere sets or instances".into());
            }
        };
    }
    t += "    ],\n)\n";
    let path = dir.join(format!("{stem}.ron"));
    util::write_atomic(&path, t.as_bytes())?;
    Ok(path)
}

/// Runs `bin render scene -o out.exr --stats out.json` with `extra`
/// arguments: the image and the render time the binary measured.
fn run(bin: &Path, scene: &Path, out: &Path, extra: &[&str]) -> Res<(Framebuffer, Duration)> {
    let json = out.with_extension("json");
    let o = Command::new(bin)
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("--stats")
        .arg(&json)
        .arg("-q")
        .args(extra)
        .output()?;
    if !o.status.success() {
        return Err(format!(
            "{} failed: {}",
            util::show(bin),
            String::from_utf8_lossy(&o.stderr).trim()
        )
        .into());
    }
    let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&json)?)?;
    let t = stats["render_time"]
        .as_f64()
        .ok_or("no render_time in the statistics")?;
    let img = gridrt_io::read_image(out)?;
    let pixels = img
        .values
        .chunks_exact(3)
        .map(|c| Rgb::new(c[0], c[1], c[2]))
        .collect();
    Ok((
        Framebuffer {
            width: img.width,
            height: img.height,
            pixels,
        },
        Duration::from_secs_f64(t),
    ))
}

/// Pixels whose largest channel differs by more than 1/255 (linear).
fn differing(a: &Framebuffer, b: &Framebuffer) -> usize {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (**p - **q).abs().max_element() > 1.0 / 255.0)
        .count()
}

/// The study: f32 and f64, grid, at each offset; reference the `f64`
/// exhaustive render at the same offset (pixels that differ) and at the
/// origin (acne and leaks).
pub fn precision(o: &Opts, bins: &[PathBuf; 2]) -> Res<String> {
    let dir = util::target_dir().join("accuracy/precision");
    let mut base = shadow_scene(1.0, 0.0);
    base.settings.width = o.size.0 * 2;
    base.settings.height = o.size.1 * 2;
    let origin = write_scene(&base, 0.0, &dir, "at-0")?;
    let (home, _) = run(
        &bins[1],
        &origin,
        &dir.join("home.exr"),
        &["--accel", "exhaustive"],
    )?;
    let mut md = String::new();
    let _ = writeln!(
        md,
        "The *cube and tent* scene ({}×{}), written as RON and OBJ files moved by the \
         offset along all three axes (added in `f64`, printed exactly), rendered by \
         the `gridrt` binary built without and with `--features f64` (the xtask builds \
         both). *Differ*: pixels whose largest channel differs by more than 1/255 from the \
         `f64` exhaustive render of the same file. *Acne*, *leaks*: against the `f64` \
         exhaustive render at the origin, as in the ray-offset study. In `f32` an ulp at \
         10⁶ is 0.0625, coarser than the tent's height above the floor (0.01 to 0.08): its \
         vertices round onto or next to the floor, so its shadow changes where the \
         precision cannot hold the scene's shape. Time: the render time each binary \
         reports, median of {} alternated runs.\n",
        o.size.0 * 2,
        o.size.1 * 2,
        o.runs
    );
    md += "| offset | build | time (ms) | time f64 / f32 | pixels that differ | acne pixels | leak pixels |\n";
    md += "| ---: | --- | ---: | ---: | ---: | ---: | ---: |\n";
    for &offset in &o.far {
        let stem = format!("at-{offset:e}");
        let scene = write_scene(&base, offset, &dir, &stem)?;
        let (reference, _) = run(
            &bins[1],
            &scene,
            &dir.join(format!("{stem}-ref.exr")),
            &["--accel", "exhaustive"],
        )?;
        let mut imgs: [Option<Framebuffer>; 2] = [None, None];
        let times = alternated(o.runs, 2, |k| {
            let (img, t) = run(&bins[k], &scene, &dir.join(format!("{stem}-{k}.exr")), &[])?;
            imgs[k] = Some(img);
            Ok(t)
        })?;
        for (k, name) in ["f32", "f64"].iter().enumerate() {
            let img = imgs[k].as_ref().ok_or("no image")?;
            let (acne, leaks) = acne_and_leaks(&home, img);
            let ratio = if k == 1 {
                sig3(times[1].as_secs_f64() / times[0].as_secs_f64())
            } else {
                String::new()
            };
            let _ = writeln!(
                md,
                "| {offset:e} | {name} | {} | {ratio} | {} | {acne} | {leaks} |",
                sig3(times[k].as_secs_f64() * 1e3),
                differing(img, &reference),
            );
        }
    }
    Ok(md)
}
