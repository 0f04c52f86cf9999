//! Suffern's benchmark (400 × 400, 1 ray per pixel, no shadows, N random
//! spheres) on one thread: the whole frame, and the camera rays alone
//! (closest hit only, no shading), so the difference is the shading share.
//!
//! Before the criterion runs it prints a one-shot breakdown per N:
//! generate / build / render times, traversal vs shading, rays/s per core
//! and the pixels hit against the reference.
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
    println!("# Suffern benchmark, 400×400, 1 spp, no shadows, 1 thread (best of 5)");
    println!(
        "{:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>9}",
        "N", "gen_s", "build_s", "render_s", "trace_s", "total_s", "shade%", "Mrays/s", "hits", "ref"
    );
    let never = AtomicBool::new(false);
    for n in SIZES {
        let (gen, scene) = best_of(3, || suffern::scene(n));
        let (build, renderer) = best_of(3, || Renderer::new(&scene, &one_thread()).expect("valid scene"));
        let (render, (img, stats)) = best_of(5, || renderer.render(&|_, _| {}, &never).expect("not cancelled"));
        let (trace, hits) = best_of(5, || renderer.count_camera_hits());
        black_box(img);
        let reference = suffern::REFERENCE_PIXELS_HIT
            .iter()
            .find(|r| r.0 == n)
            .map_or(0, |r| r.1);
        let total = gen + build + render;
        let shade = 1.0 - trace.as_secs_f64() / render.as_secs_f64();
        println!(
            "{:>9} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>8.1}% {:>10.2} {:>9} {:>9}",
            n,
            gen.as_secs_f64(),
            build.as_secs_f64(),
            render.as_secs_f64(),
            trace.as_secs_f64(),
            total.as_secs_f64(),
            100.0 * shade.max(0.0),
            stats.rays.total() as f64 / render.as_secs_f64() * 1e-6,
            hits,
            reference
        );
    }
}

fn bench(c: &mut Criterion) {
    let never = AtomicBool::new(false);
    let mut g = c.benchmark_group("suffern");
    g.sample_size(10);
    for n in SIZES {
        let scene = suffern::scene(n);
        let renderer = Renderer::new(&scene, &one_thread()).expect("valid scene");
        g.bench_with_input(BenchmarkId::new("render", n), &renderer, |b, r| {
            b.iter(|| black_box(r.render(&|_, _| {}, &never).expect("not cancelled")));
        });
        g.bench_with_input(BenchmarkId::new("trace_only", n), &renderer, |b, r| {
            b.iter(|| black_box(r.count_camera_hits()));
        });
        g.bench_with_input(BenchmarkId::new("build", n), &scene, |b, s| {
            b.iter(|| black_box(Renderer::new(s, &one_thread()).expect("valid scene")));
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
