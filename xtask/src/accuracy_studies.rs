//! The studies of `cargo xtask accuracy` that run in this process: samples
//! per pixel, the triangle test, ray offsets, and the settings that change
//! no pixel. Each returns a Markdown section whose numbers come from the
//! runs it made.

use crate::accuracy::{alternated, secs, Opts, Res};
use crate::plot::Series;
use crate::util::{self, sig3};
use gridrt_grid::{Accelerator, CellStorage, Grid, GridConfig, Ray, Real, SlabTest};
use gridrt_tracer::hard_meshes::{self, DirLength};
use gridrt_tracer::offset_scenes::{acne_and_leaks, shadow_scene, table_scene};
use gridrt_tracer::{
    Framebuffer, MtTriangle, RayOffset, RenderOptions, Renderer, Scene, TriangleTest,
};
use plotters::style::RGBColor;
use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// Renders once: the image and the render time (the build excluded).
pub fn render_once(r: &Renderer) -> Res<(Framebuffer, Duration)> {
    let never = AtomicBool::new(false);
    let (fb, stats) = r
        .render(&|_, _| {}, &never)
        .map_err(|_| "a render was cancelled")?;
    Ok((fb, stats.render_time))
}

fn renderer(scene: &Scene, o: &RenderOptions) -> Res<Renderer> {
    Ok(Renderer::new(scene, o)?)
}

fn fixture_scene(name: &str) -> Res<Scene> {
    let path = util::root().join("fixtures/scenes").join(name);
    Ok(util::load_scene(&path)?.scene)
}

/// Root-mean-square difference over every channel of every pixel.
pub fn rmse(a: &Framebuffer, b: &Framebuffer) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| {
            let d = (*p - *q).to_array();
            d.iter().map(|x| f64::from(*x) * f64::from(*x)).sum::<f64>()
        })
        .sum();
    (sum / (3 * a.pixels.len()).max(1) as f64).sqrt()
}

/// Whether two images are bit for bit the same.
pub fn identical(a: &Framebuffer, b: &Framebuffer) -> bool {
    a.width == b.width
        && a.height == b.height
        && a.pixels
            .iter()
            .zip(&b.pixels)
            .all(|(p, q)| p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits))
}

/// Samples per pixel: RMSE against a high-spp reference, and time.
pub fn spp(o: &Opts) -> Res<(String, Vec<Series>)> {
    let mut scene = fixture_scene("soft-shadows.ron")?;
    scene.settings.width = o.size.0;
    scene.settings.height = o.size.1;
    let opts = RenderOptions::default();
    let at = |spp: u32| -> Res<Renderer> {
        let mut s = scene.clone();
        s.settings.spp = spp;
        renderer(&s, &opts)
    };
    eprintln!(
        "accuracy: samples per pixel: reference at {} spp",
        o.ref_spp
    );
    let (reference, ref_time) = render_once(&at(o.ref_spp)?)?;
    let renderers: Vec<(u32, Renderer)> = o
        .spps
        .iter()
        .map(|&n| at(n).map(|r| (n, r)))
        .collect::<Res<_>>()?;
    let mut images: Vec<Option<Framebuffer>> = vec![None; renderers.len()];
    let times = alternated(o.runs, renderers.len(), |i| {
        let (fb, t) = render_once(&renderers[i].1)?;
        images[i] = Some(fb);
        Ok(t)
    })?;
    let mut md = String::new();
    let _ = writeln!(
        md,
        "`fixtures/scenes/soft-shadows.ron` (two spheres and a box on a floor under a \
         rectangle and a disk light, Whitted with one light sample per shading point and \
         pixel sample) at {}×{}: the penumbrae are the noise, and every pixel's samples \
         are jittered in its square, so edges are antialiased too. Reference: the same \
         scene at {} samples per pixel (rendered in {} s). Time: render only, median of \
         {} alternated runs.\n",
        o.size.0,
        o.size.1,
        o.ref_spp,
        sig3(ref_time.as_secs_f64()),
        o.runs
    );
    md += "| samples per pixel | time (s) | RMSE vs reference | RMSE × √spp | time × RMSE² |\n";
    md += "| ---: | ---: | ---: | ---: | ---: |\n";
    let mut points = Vec::new();
    for (((n, _), t), img) in renderers.iter().zip(&times).zip(&images) {
        let img = img.as_ref().ok_or("no image")?;
        let e = rmse(img, &reference);
        let t = t.as_secs_f64();
        points.push((t, e));
        let _ = writeln!(
            md,
            "| {n} | {} | {} | {} | {} |",
            sig3(t),
            sig3(e),
            sig3(e * f64::from(*n).sqrt()),
            sig3(t * e * e)
        );
    }
    let c = crate::plot::fit_scale(&points, |t| 1.0 / t.sqrt());
    let (lo, hi) = (
        points.first().map_or(1.0, |p| p.0),
        points.last().map_or(1.0, |p| p.0),
    );
    let line: Vec<(f64, f64)> = (0..=20)
        .map(|k| {
            let t = lo * (hi / lo).powf(f64::from(k) / 20.0);
            (t, c / t.sqrt())
        })
        .collect();
    let series = vec![
        Series {
            label: "measured RMSE".into(),
            points,
            color: RGBColor(31, 119, 180),
            dashed: false,
        },
        Series {
            label: "∝ 1/√N (time ∝ N)".into(),
            points: line,
            color: RGBColor(110, 110, 110),
            dashed: true,
        },
    ];
    Ok((md, series))
}

fn closest<A: Accelerator>(a: &A, r: &Ray, s: &mut A::Scratch) -> bool {
    a.closest_hit(r, 0.0, Real::INFINITY, s).is_some()
}

/// Rays that miss (leak) and the time to trace them all, per accelerator.
struct Probe {
    rays: usize,
    leaks: [usize; 2],
    times: [Duration; 2],
}

/// Watertight vs Möller–Trumbore on the closed meshes, per scale.
pub fn triangle_test(o: &Opts) -> Res<String> {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "Rays from a point inside each closed mesh of `gridrt_tracer::hard_meshes` (a UV \
         sphere with pole fans, a torus, a bicone of 10⁻⁵-radian slivers, a cube whose faces \
         are fans mixing areas 10⁻⁸ and 1) and of four random closed meshes \
         (`hard_meshes::random_star`, 150 splits: slivers and fans over a random \
         triangulation, randomly rotated) through every vertex, edge midpoint and points \
         near both ends of every edge, with unit, 2⁻²⁰ and `target − origin` directions, at \
         offsets {} from the origin where the precision resolves the mesh. Every ray must \
         hit: a miss is a leak. The reference is the geometry itself. Time: tracing all \
         the rays through the grid (build excluded), median of {} alternated runs.\n",
        o.offsets
            .iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(", "),
        o.runs
    );
    md += "| scale | rays | watertight: time (ms) | watertight: leaks | Möller–Trumbore: time (ms) | Möller–Trumbore: leaks | MT leaks per million rays |\n";
    md += "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    let mut total = Probe {
        rays: 0,
        leaks: [0; 2],
        times: [Duration::ZERO; 2],
    };
    for &scale in &o.scales {
        let mut p = Probe {
            rays: 0,
            leaks: [0; 2],
            times: [Duration::ZERO; 2],
        };
        let meshes = hard_meshes::standard_set()
            .into_iter()
            .chain((1..=4).map(|seed| hard_meshes::random_star(seed, 150, 0.3)));
        for mesh in meshes {
            for &offset in &o.offsets {
                if scale < offset * gridrt_bbox::math::to_f64(Real::EPSILON) * 4096.0 {
                    continue;
                }
                let tris = mesh.triangles(scale, offset);
                let mt: Vec<MtTriangle> = tris.iter().copied().map(MtTriangle).collect();
                let config = GridConfig::default();
                let wt = Grid::build(tris, &config);
                let mt = Grid::build(mt, &config);
                let rays: Vec<Ray> = [DirLength::Unit, DirLength::Short, DirLength::ToTarget]
                    .iter()
                    .flat_map(|&len| mesh.probe_rays(scale, offset, len))
                    .collect();
                let mut leaks = [0usize; 2];
                let times = alternated(o.runs, 2, |k| {
                    let start = Instant::now();
                    let hits = if k == 0 {
                        let mut s = wt.scratch();
                        rays.iter().filter(|r| closest(&wt, r, &mut s)).count()
                    } else {
                        let mut s = mt.scratch();
                        rays.iter().filter(|r| closest(&mt, r, &mut s)).count()
                    };
                    let t = start.elapsed();
                    leaks[k] = rays.len() - hits;
                    Ok(t)
                })?;
                p.rays += rays.len();
                for k in 0..2 {
                    p.leaks[k] += leaks[k];
                    p.times[k] += times[k];
                }
            }
        }
        let _ = writeln!(
            md,
            "| {scale:e} | {} | {} | {} | {} | {} | {} |",
            p.rays,
            sig3(p.times[0].as_secs_f64() * 1e3),
            p.leaks[0],
            sig3(p.times[1].as_secs_f64() * 1e3),
            p.leaks[1],
            sig3(p.leaks[1] as f64 * 1e6 / p.rays.max(1) as f64),
        );
        total.rays += p.rays;
        for k in 0..2 {
            total.leaks[k] += p.leaks[k];
            total.times[k] += p.times[k];
        }
    }
    let _ = writeln!(
        md,
        "| **all** | {} | {} | {} | {} | {} | {} |",
        total.rays,
        sig3(total.times[0].as_secs_f64() * 1e3),
        total.leaks[0],
        sig3(total.times[1].as_secs_f64() * 1e3),
        total.leaks[1],
        sig3(total.leaks[1] as f64 * 1e6 / total.rays.max(1) as f64),
    );
    // A real mesh, rendered: the time a user pays, and the pixels it changes.
    let mut scene = fixture_scene("obj_teapot.ron")?;
    scene.settings.width = o.size.0 * 2;
    scene.settings.height = o.size.1 * 2;
    let opts = |t: TriangleTest| RenderOptions {
        triangle_test: t,
        ..RenderOptions::default()
    };
    let rs = [
        renderer(&scene, &opts(TriangleTest::Watertight))?,
        renderer(&scene, &opts(TriangleTest::MollerTrumbore))?,
    ];
    let mut imgs: [Option<Framebuffer>; 2] = [None, None];
    let times = alternated(o.runs, 2, |k| {
        let (fb, t) = render_once(&rs[k])?;
        imgs[k] = Some(fb);
        Ok(t)
    })?;
    let (a, b) = (
        imgs[0].as_ref().ok_or("no image")?,
        imgs[1].as_ref().ok_or("no image")?,
    );
    let differ = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| p != q)
        .count();
    let _ = writeln!(
        md,
        "\nOn a real mesh, `fixtures/scenes/obj_teapot.ron` ({} triangles, {}×{}, shadows): \
         watertight {} s, Möller–Trumbore {} s (render time, median of {} alternated runs; \
         ratio {}); {differ} of {} pixels differ between the two images.",
        rs[0].primitive_count(),
        scene.settings.width,
        scene.settings.height,
        sig3(times[0].as_secs_f64()),
        sig3(times[1].as_secs_f64()),
        o.runs,
        sig3(secs(times[0]) / secs(times[1])),
        a.pixels.len()
    );
    Ok(md)
}

/// Error bound vs fixed offsets at scene scales 1e-4 … 1e4.
pub fn offsets(o: &Opts) -> Res<String> {
    let modes = [
        ("error bound", RayOffset::ErrorBound),
        ("fixed 1e-4", RayOffset::Fixed(1e-4)),
        ("fixed 1e-3", RayOffset::Fixed(1e-3)),
    ];
    let mut md = String::new();
    let _ = writeln!(
        md,
        "Two scenes of `gridrt_tracer::offset_scenes`, scaled about the origin: *cube and \
         tent* (a cube of triangles and a tent 0.01–0.08 above a floor plane, a point and a \
         directional light with shadows, seen from above) and *table* (a table top 0.1 \
         above the floor, seen from between them). Reference: the same scene at scale 1 \
         with the error-bound offset. *Acne*: pixels lit in the reference and darker here; \
         *leaks*: pixels in shadow in the reference and lit here (counted where the \
         reference's 5×5 neighbourhood is flat). Time: render, median of {} alternated \
         runs of the three offsets, {}×{} pixels.\n",
        o.runs, o.size.0, o.size.1
    );
    md += "| scene | scale | offset | time (ms) | acne pixels | leak pixels |\n";
    md += "| --- | ---: | --- | ---: | ---: | ---: |\n";
    for (name, make) in [
        ("cube and tent", shadow_scene as fn(Real, Real) -> Scene),
        ("table", table_scene),
    ] {
        let sized = |mut s: Scene| {
            s.settings.width = o.size.0;
            s.settings.height = o.size.1;
            s
        };
        let (reference, _) = render_once(&renderer(
            &sized(make(1.0, 0.0)),
            &RenderOptions::default(),
        )?)?;
        for &scale in &o.offset_scales {
            let scene = sized(make(scale as Real, 0.0));
            let rs: Vec<Renderer> = modes
                .iter()
                .map(|(_, m)| {
                    renderer(
                        &scene,
                        &RenderOptions {
                            ray_offset: *m,
                            ..RenderOptions::default()
                        },
                    )
                })
                .collect::<Res<_>>()?;
            let mut counts = [(0, 0); 3];
            let times = alternated(o.runs, 3, |k| {
                let (fb, t) = render_once(&rs[k])?;
                counts[k] = acne_and_leaks(&reference, &fb);
                Ok(t)
            })?;
            for (k, (label, _)) in modes.iter().enumerate() {
                let _ = writeln!(
                    md,
                    "| {name} | {scale:e} | {label} | {} | {} | {} |",
                    sig3(times[k].as_secs_f64() * 1e3),
                    counts[k].0,
                    counts[k].1
                );
            }
        }
    }
    Ok(md)
}

/// Settings that must change no pixel: verified identical, and timed.
pub fn no_change(o: &Opts) -> Res<String> {
    let base = GridConfig::default();
    let variants: Vec<(&str, GridConfig)> = vec![
        ("default (dense cells, m = 0.75, auto hierarchy)", base),
        (
            "mailbox",
            GridConfig {
                mailbox: true,
                ..base
            },
        ),
        (
            "exact insertion",
            GridConfig {
                exact_insertion: true,
                ..base
            },
        ),
        (
            "hashed cells (`--accel hashed-grid`)",
            GridConfig {
                storage: CellStorage::Hashed,
                ..base
            },
        ),
        ("m = 0.5", GridConfig { m: 0.5, ..base }),
        ("m = 1", GridConfig { m: 1.0, ..base }),
        ("m = 2 (the lecture's)", GridConfig { m: 2.0, ..base }),
        (
            "flat grid (no hierarchy)",
            GridConfig {
                auto: false,
                ..base
            },
        ),
        (
            "nested grids: m 0.3, nest 8, nest m 0.7",
            GridConfig {
                m: 0.3,
                nest_min_refs: 8,
                nest_m: Some(0.7),
                ..base
            },
        ),
        (
            "textbook slab test",
            GridConfig {
                slab: SlabTest::Textbook,
                ..base
            },
        ),
    ];
    let mut md = String::new();
    let _ = writeln!(
        md,
        "Each setting renders the scene; the image must be bit for bit the default's \
         (every pixel's three `f32` values compared). Time: build and render, medians of \
         {} alternated runs of all the settings, {}×{} pixels.\n",
        o.runs,
        o.size.0 * 2,
        o.size.1 * 2
    );
    md += "| scene | setting | build (ms) | render (ms) | render / default | error vs default |\n";
    md += "| --- | --- | ---: | ---: | ---: | --- |\n";
    let mut all_same = true;
    for name in ["obj_teapot.ron", "random_spheres.ron", "mirror_glass.ron"] {
        let mut scene = fixture_scene(name)?;
        scene.settings.width = o.size.0 * 2;
        scene.settings.height = o.size.1 * 2;
        let n = variants.len();
        let mut imgs: Vec<Option<Framebuffer>> = vec![None; n];
        let mut builds = vec![Vec::new(); n];
        let renders = alternated(o.runs, n, |k| {
            let start = Instant::now();
            let r = renderer(
                &scene,
                &RenderOptions {
                    grid: variants[k].1,
                    ..RenderOptions::default()
                },
            )?;
            builds[k].push(start.elapsed());
            let (fb, t) = render_once(&r)?;
            imgs[k] = Some(fb);
            Ok(t)
        })?;
        let reference = imgs[0].clone().ok_or("no image")?;
        for (k, (label, _)) in variants.iter().enumerate() {
            let img = imgs[k].as_ref().ok_or("no image")?;
            let same = identical(img, &reference);
            all_same &= same;
            let error = if same {
                "0 (identical)".to_string()
            } else {
                let d = img
                    .pixels
                    .iter()
                    .zip(&reference.pixels)
                    .filter(|(p, q)| p != q)
                    .count();
                format!("**{d} pixels differ**")
            };
            let _ = writeln!(
                md,
                "| `{name}` | {label} | {} | {} | {} | {error} |",
                sig3(util::median(builds[k].clone()).as_secs_f64() * 1e3),
                sig3(renders[k].as_secs_f64() * 1e3),
                sig3(secs(renders[k]) / secs(renders[0])),
            );
        }
    }
    if !all_same {
        md += "\n**Some setting changed pixels: a bug to fix.**\n";
    }
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rmse_and_identity() {
        let mut a = Framebuffer::new(2, 1);
        let b = a.clone();
        assert!(identical(&a, &b));
        assert_eq!(rmse(&a, &b), 0.0);
        a.pixels[0] = gridrt_tracer::Rgb::new(0.3, 0.0, 0.0);
        assert!(!identical(&a, &b));
        assert!((rmse(&a, &b) - (0.09f64 / 6.0).sqrt()).abs() < 1e-6);
    }
}
