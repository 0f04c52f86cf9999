//! Suffern's benchmark (400 × 400, 1 ray per pixel, no shadows, N random
//! spheres) on one thread: the whole frame, and the camera rays alone
//! (closest hit only, no shading), so the difference is the shading share.
//!
//! Before the criterion runs it prints a one-shot breakdown per N (best of a
//! few runs): generate / build / render times, traversal vs shading, rays/s
//! per core, and the pixels hit against the Embree peer's reference. The
//! scene is one object holding a sphere set ([`suffern::scene_of`]);
//! `scene_gen_s` is [`suffern::scene`] (set and scene) on one thread.
//!
//! `cargo bench -p gridrt-tracer --bench suffern`

use criterion::{black_box, criterion_group, BenchmarkId, Criterion};
use gridrt_tracer::{suffern, RenderOptions, Renderer};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

const SIZES: [usize; 2] = [10_000, 1_000_000];

fn one_thread() -> RenderOptions {
    RenderOptions {
        threads: Some(1),
        ..RenderOptions::default()
    }
}

fn best_of<T>(reps: usize, mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut best = Duration::MAX;
    let mut out = None;
    for _ in 0..reps {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed());
        out = Some(r);
    }
    (best, out.expect("reps > 0"))
}

/// The one-shot table printed before criterion runs.
fn breakdown() {
    println!("# Suffern benchmark, 400×400, 1 spp, no shadows, 1 thread, best of 3-5 runs");
    println!(
        "{:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>9} {:>8} {:>8} {:>11}",
        "N",
        "gen_s",
        "prep_s",
        "grid_s",
        "render_s",
        "trace_s",
        "total_s",
        "shade%",
        "Mrays/s",
        "hits",
        "ref",
        "scene_gen_s"
    );
    let never = AtomicBool::new(false);
    for n in SIZES {
        let (gen, _) = best_of(3, || suffern::sphere_set(n, suffern::DEFAULT_SEED));
        // Scene preparation and grid build, without generation.
        let mut build = Duration::MAX;
        let mut grid = Duration::MAX;
        let mut renderer = None;
        for _ in 0..3 {
            let scene = suffern::scene_of(suffern::sphere_set(n, suffern::DEFAULT_SEED));
            let t = Instant::now();
            let r = Renderer::new(&scene, &one_thread()).expect("valid scene");
            build = build.min(t.elapsed());
            grid = grid.min(r.grid_stats().map_or(Duration::ZERO, |g| g.build_time));
            renderer = Some(r);
        }
        let renderer = renderer.expect("built");
        let (render, (img, stats)) = best_of(5, || {
            renderer.render(&|_, _| {}, &never).expect("not cancelled")
        });
        let (trace, hits) = best_of(5, || renderer.count_camera_hits());
        black_box(img);
        let (scene_gen, scene) = best_of(1, || suffern::scene(n));
        drop(scene);
        let reference = suffern::REFERENCE_PIXELS_HIT
            .iter()
            .find(|r| r.0 == n)
            .map_or(0, |r| r.1);
        let total = gen + build + render;
        let shade = 1.0 - trace.as_secs_f64() / render.as_secs_f64();
        println!(
            "{:>9} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>7.1}% {:>9.2} {:>8} {:>8} {:>11.4}",
            n,
            gen.as_secs_f64(),
            build.saturating_sub(grid).as_secs_f64(),
            grid.as_secs_f64(),
            render.as_secs_f64(),
            trace.as_secs_f64(),
            total.as_secs_f64(),
            100.0 * shade.max(0.0),
            stats.rays.total() as f64 / render.as_secs_f64() * 1e-6,
            hits,
            reference,
            scene_gen.as_secs_f64()
        );
    }
}

fn bench(c: &mut Criterion) {
    let never = AtomicBool::new(false);
    let mut g = c.benchmark_group("suffern");
    g.sample_size(10);
    for n in SIZES {
        let renderer =
            suffern::renderer(n, suffern::DEFAULT_SEED, &one_thread()).expect("valid scene");
        g.bench_with_input(BenchmarkId::new("render", n), &renderer, |b, r| {
            b.iter(|| black_box(r.render(&|_, _| {}, &never).expect("not cancelled")));
        });
        g.bench_with_input(BenchmarkId::new("trace_only", n), &renderer, |b, r| {
            b.iter(|| black_box(r.count_camera_hits()));
        });
        g.bench_with_input(BenchmarkId::new("generate_and_build", n), &n, |b, &n| {
            b.iter(|| {
                black_box(
                    suffern::renderer(n, suffern::DEFAULT_SEED, &one_thread()).expect("valid"),
                )
            });
        });
    }
    g.finish();
}

criterion_group!(benches, bench);

fn main() {
    breakdown();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
