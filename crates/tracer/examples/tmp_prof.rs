#![allow(clippy::unwrap_used)]
use gridrt_tracer::*;
use std::time::{Duration, Instant};
use std::sync::atomic::AtomicBool;
fn main() {
    if let Ok(k) = std::env::var("RENDERS") {
        let k: usize = k.parse().unwrap();
        let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(1_000_000);
        let opts = RenderOptions { threads: Some(1), ..Default::default() };
        let mut set = suffern::sphere_set(n, 15);
        if std::env::var("NOCOLOR").is_ok() { set.colors.clear(); }
        let r = Renderer::with_spheres(&suffern::base_scene(), set, &opts).unwrap();
        let never = AtomicBool::new(false);
        let trace = std::env::var("TRACE").is_ok();
        for _ in 0..k { if trace { std::hint::black_box(r.count_camera_hits()); } else { std::hint::black_box(r.render(&|_, _| {}, &never).unwrap()); } }
        return;
    }
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(1_000_000);
    let opts = RenderOptions { threads: Some(1), ..Default::default() };
    let never = AtomicBool::new(false);
    for _ in 0..3 {
        let t = Instant::now();
        let set = suffern::sphere_set(n, 15);
        let a = t.elapsed();
        let t = Instant::now();
        let r = Renderer::with_spheres(&suffern::base_scene(), set, &RenderOptions { accel: AccelKind::Exhaustive, threads: Some(1), ..Default::default() }).unwrap();
        println!("sphere_set {:?} prepare(exhaustive) {:?}", a, t.elapsed());
        let t = Instant::now();
        drop(r);
        println!("drop {:?}", t.elapsed());
    }
    let t0 = Instant::now();
    let mut set = suffern::sphere_set(n, 15);
    if std::env::var("NOCOLOR").is_ok() { set.colors.clear(); }
    let r = Renderer::with_spheres(&suffern::base_scene(), set, &opts).unwrap();
    let tb = t0.elapsed();
    let (_img, st) = r.render(&|_, _| {}, &never).unwrap();
    let total = t0.elapsed();
    println!("lean: gen+build {:?} (grid {:?}) render {:?} total {:?} hits {}", tb, r.grid_stats().unwrap().build_time, st.render_time, total, st.pixels_hit);
    let (mut br, mut bt) = (Duration::MAX, Duration::MAX);
    for _ in 0..7 {
        let t = Instant::now();
        let _ = r.render(&|_, _| {}, &never).unwrap();
        br = br.min(t.elapsed());
        let t = Instant::now();
        let _ = r.count_camera_hits();
        bt = bt.min(t.elapsed());
    }
    println!("best render {:?} trace {:?}", br, bt);
    let set = suffern::sphere_set(n, 15);
    let g = gridrt_grid::Grid::build(set.spheres, &gridrt_grid::GridConfig { parallel_build: false, ..Default::default() });
    let mut sc = gridrt_grid::Accelerator::scratch(&g);
    let mut qc = gridrt_grid::QueryCounters::default();
    for r in 0..400 { for c in 0..400 {
        let d = gridrt_grid::Vec3::new(c as f32 - 200.0 + 0.5, r as f32 - 200.0 + 0.5, -3600.0).normalize();
        let ray = gridrt_grid::Ray::new(gridrt_grid::Vec3::new(0.0, 0.0, 20.0), d);
        let _ = g.closest_hit_counted(&ray, 0.0, f32::INFINITY, &mut sc, &mut qc);
    }}
    println!("cells/ray {:.1} tests/ray {:.1}", qc.cells_per_ray(), qc.tests_per_ray());
}
#[allow(dead_code)]
fn counters() {}
