//! Suffern's benchmark beside the Embree peer: build time and single-thread
//! closest-hit throughput of the grid (and of the exhaustive baseline at
//! small N) on the peer's exact scene and rays, printed as a table.
//!
//! `cargo bench -p gridrt-grid --bench suffern` runs the default set. The
//! environment variable `SUFFERN` selects parts, comma-separated:
//! `spheres` (N = 1e3…1e6), `mesh` (1,024,000 triangles), `bunny`,
//! `sorted`, `sweep` (m and storage sweep), `mailbox`, `meshnest` (nested
//! grids on the mesh), `meshshadow` (any-hit shadow rays on the mesh, with and without nesting),
//! `meshprofile` (only the mesh trace, repeated, for a profiler),
//! `buildprofile` (only the one-thread build, repeated, for a profiler),
//! `exhaustive`. `SUFFERN_N` overrides the list of N, `SUFFERN_M` the grid
//! multiplier, `SUFFERN_NEST` the nesting threshold and `SUFFERN_NEST_M`
//! the nested grids' multiplier of the base configuration; `SUFFERN_MB`
//! (any value) turns its mailbox on. Timings
//! are best of several runs, in one thread (the build also with rayon).

#[path = "../tests/support/prims.rs"]
mod prims;
#[path = "../tests/support/scenes.rs"]
mod scenes;

use gridrt_grid::{
    Accelerator, CellStorage, Exhaustive, Grid, GridConfig, Primitive, QueryCounters, Ray, Real,
    Vec3,
};
use prims::Triangle;
use std::hint::black_box;
use std::time::{Duration, Instant};

#[repr(C)]
struct Timespec {
    sec: i64,
    nsec: i64,
}

extern "C" {
    fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
}

/// CPU time of the calling thread (Linux `CLOCK_THREAD_CPUTIME_ID`), so that
/// other processes on the shared machine do not inflate the numbers; wall
/// time elsewhere.
fn thread_cpu() -> Duration {
    if cfg!(target_os = "linux") {
        let mut ts = Timespec { sec: 0, nsec: 0 };
        // SAFETY: a valid clock id and a valid out-pointer.
        if unsafe { clock_gettime(3, &mut ts) } == 0 {
            return Duration::new(ts.sec as u64, ts.nsec as u32);
        }
    }
    START.with(|s| s.elapsed())
}

thread_local! {
    static START: Instant = Instant::now();
}

/// Best of `n` runs, in thread CPU time (only meaningful for one-thread work).
fn best_of<R>(n: usize, mut f: impl FnMut() -> R) -> (Duration, R) {
    let mut best = Duration::MAX;
    let mut out = None;
    for _ in 0..n {
        let t = thread_cpu();
        let r = black_box(f());
        best = best.min(thread_cpu() - t);
        out = Some(r);
    }
    (best, out.expect("n > 0"))
}

/// Best of `n` runs in wall time (for parallel work).
fn best_wall<R>(n: usize, mut f: impl FnMut() -> R) -> (Duration, R) {
    let mut best = Duration::MAX;
    let mut out = None;
    for _ in 0..n {
        let t = Instant::now();
        let r = black_box(f());
        best = best.min(t.elapsed());
        out = Some(r);
    }
    (best, out.expect("n > 0"))
}

fn trace<A: Accelerator>(acc: &A, rays: &[Ray]) -> Vec<Option<u32>> {
    let mut s = acc.scratch();
    rays.iter()
        .map(|r| {
            acc.closest_hit(r, 0.0, Real::INFINITY, &mut s)
                .map(|h| h.prim)
        })
        .collect()
}

fn counted<P: Primitive>(g: &Grid<P>, rays: &[Ray]) -> QueryCounters {
    let mut s = g.scratch();
    let mut c = QueryCounters::default();
    for r in rays {
        g.closest_hit_counted(r, 0.0, Real::INFINITY, &mut s, &mut c);
    }
    c
}

struct Row {
    build_seq: Duration,
    build_par: Duration,
    trace: Duration,
    hits: usize,
    sum: u64,
    counters: QueryCounters,
    mb: f64,
    dims: [u32; 3],
}

fn measure<P: Primitive<Shared = ()> + Clone + Send>(
    prims: &[P],
    rays: &[Ray],
    config: &GridConfig,
    reps: usize,
) -> Row {
    measure_with(prims, rays, config, reps, Grid::build)
}

/// As [`measure`], building every grid with `build`.
fn measure_with<P: Primitive + Clone>(
    prims: &[P],
    rays: &[Ray],
    config: &GridConfig,
    reps: usize,
    build: fn(Vec<P>, &GridConfig) -> Grid<P>,
) -> Row {
    let build_seq = best_seq_build(prims, config, 3, build);
    let mut build_par = Duration::MAX;
    let mut g = build(prims.to_vec(), config);
    for _ in 0..3 {
        let p = prims.to_vec();
        drop(g);
        let t = Instant::now();
        g = black_box(build(p, config));
        build_par = build_par.min(t.elapsed());
    }
    trace(&g, rays);
    let (t, hits) = best_of(reps, || trace(&g, rays));
    let (h, sum) = scenes::checksum(&hits);
    Row {
        build_seq,
        build_par,
        trace: t,
        hits: h,
        sum,
        counters: counted(&g, rays),
        mb: g.stats().bytes as f64 / 1e6,
        dims: g.stats().dims,
    }
}

/// The best one-thread build time (thread CPU time) of `reps` builds with
/// `build`; the primitives are copied, and the grid dropped, outside the
/// timed region.
fn best_seq_build<P: Primitive + Clone>(
    prims: &[P],
    config: &GridConfig,
    reps: usize,
    build: fn(Vec<P>, &GridConfig) -> Grid<P>,
) -> Duration {
    let seq = GridConfig {
        parallel_build: false,
        ..*config
    };
    let mut best = Duration::MAX;
    for _ in 0..reps {
        let p = prims.to_vec();
        let t = thread_cpu();
        let g = black_box(build(p, &seq));
        best = best.min(thread_cpu() - t);
        drop(g);
    }
    best
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn header() {
    println!(
        "{:<10} {:<7} {:<6} {:<4} {:>9} {:>9} {:>9} {:>8} {:>7} {:>7} {:>8} {:>15} {:>8} {:>20}",
        "scene",
        "storage",
        "m",
        "mb",
        "build1_ms",
        "buildP_ms",
        "trace_ms",
        "Mrays/s",
        "cells/r",
        "tests/r",
        "hits",
        "dims",
        "MB",
        "checksum"
    );
}

fn print_row(name: &str, c: &GridConfig, r: &Row) {
    println!(
        "{:<10} {:<7} {:<6} {:<4} {:>9.2} {:>9.2} {:>9.2} {:>8.2} {:>7.1} {:>7.1} {:>8} {:>15} {:>8.1} {:>20}",
        name,
        format!("{:?}", c.storage),
        c.m,
        if c.mailbox { "on" } else { "off" },
        ms(r.build_seq),
        ms(r.build_par),
        ms(r.trace),
        (scenes::W * scenes::H) as f64 / r.trace.as_secs_f64() * 1e-6,
        r.counters.cells_per_ray(),
        r.counters.tests_per_ray(),
        r.hits,
        format!("{:?}", r.dims),
        r.mb,
        r.sum
    );
}

fn parts() -> Vec<String> {
    std::env::var("SUFFERN")
        .unwrap_or_else(|_| "spheres,mesh,exhaustive".into())
        .split(',')
        .map(|s| s.trim().to_string())
        .collect()
}

fn ns() -> Vec<usize> {
    std::env::var("SUFFERN_N")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![1000, 10_000, 100_000, 1_000_000])
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` passes nothing: then only smoke-test.
    if !std::env::args().any(|a| a == "--bench") {
        let s = scenes::suffern_spheres(100);
        let r = measure(
            &s,
            &scenes::suffern_rays()[..1000],
            &GridConfig::default(),
            1,
        );
        assert!(r.hits > 0);
        return;
    }
    let parts = parts();
    let has = |p: &str| parts.iter().any(|x| x == p);
    let rays = scenes::suffern_rays();
    let mut base = GridConfig::default();
    if let Some(m) = std::env::var("SUFFERN_M").ok().and_then(|s| s.parse().ok()) {
        base.m = m;
    }
    if let Some(n) = std::env::var("SUFFERN_NEST")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        base.nest_min_refs = n;
    }
    if let Some(m) = std::env::var("SUFFERN_NEST_M")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        base.nest_m = Some(m);
    }
    if std::env::var("SUFFERN_MB").is_ok() {
        base.mailbox = true;
    }
    header();
    if has("spheres") {
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            for storage in [CellStorage::Dense, CellStorage::Hashed] {
                let c = GridConfig { storage, ..base };
                print_row(&format!("sph{n}"), &c, &measure(&s, &rays, &c, 5));
            }
        }
    }
    if has("buildonly") {
        // Builds only (sequential), for a profiler.
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            for _ in 0..3 {
                let g = Grid::build(
                    s.clone(),
                    &GridConfig {
                        parallel_build: false,
                        ..base
                    },
                );
                println!("# build N={n}: {:.2} ms", ms(g.stats().build_time));
            }
        }
    }
    if has("once") {
        // One trace, for cachegrind/callgrind.
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            let g = Grid::build(s, &base);
            let hits = trace(&g, &rays);
            println!("# once N={n}: {:?}", scenes::checksum(&hits));
        }
    }
    if has("buildprofile") {
        // Only the one-thread build, repeated, for a profiler.
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            let best = best_seq_build(&s, &base, 20, Grid::build);
            println!("# build profile N={n}: {:.2} ms (best of 20)", ms(best));
        }
    }
    if has("meshprofile") {
        let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(1000), 32, 17);
        let g = Grid::build(tris, &base);
        let reps = std::env::var("REPS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(10);
        let (t, _) = best_of(reps, || trace(&g, &rays));
        println!("# mesh profile: {:.2} ms per trace (best of {reps})", ms(t));
    }
    if has("profile") {
        // Only the trace, repeated, for a profiler.
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            let g = Grid::build(s, &base);
            let t = Instant::now();
            for _ in 0..20 {
                black_box(trace(&g, &rays));
            }
            println!(
                "# profile N={n}: {:.2} ms per trace",
                ms(t.elapsed()) / 20.0
            );
            let (t, c) = best_of(5, || {
                rays.iter()
                    .map(|r| g.cells_along(r, 0.0, Real::INFINITY).count())
                    .sum::<usize>()
            });
            println!(
                "# walk only (all cells to the far side): {:.2} ms, {:.1} cells/ray",
                ms(t),
                c as f64 / rays.len() as f64
            );
            let (t, c) = best_of(5, || {
                rays.iter()
                    .map(|r| {
                        let mut k = 0usize;
                        let _ = g.visit_cells(r, 0.0, Real::INFINITY, |_, refs| {
                            k += refs.len();
                            std::ops::ControlFlow::<()>::Continue(())
                        });
                        k
                    })
                    .sum::<usize>()
            });
            println!(
                "# walk + lookups: {:.2} ms, {:.1} refs/ray",
                ms(t),
                c as f64 / rays.len() as f64
            );
        }
    }
    if has("sorted") {
        // Experiment: the same spheres, stored in Morton order of their centres.
        for &n in &ns() {
            let s0 = scenes::suffern_spheres(n);
            let s: Vec<prims::Sphere> = gridrt_grid::spatial_order(&s0, &())
                .into_iter()
                .map(|i| s0[i as usize])
                .collect();
            for storage in [CellStorage::Dense, CellStorage::Hashed] {
                let c = GridConfig { storage, ..base };
                print_row(&format!("sorted{n}"), &c, &measure(&s, &rays, &c, 5));
            }
        }
    }
    if has("sweep") {
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            let storages = if has("densesweep") {
                vec![CellStorage::Dense]
            } else {
                vec![CellStorage::Dense, CellStorage::Hashed]
            };
            for &storage in &storages {
                for m in [0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0] {
                    let c = GridConfig { storage, m, ..base };
                    print_row(&format!("sph{n}"), &c, &measure(&s, &rays, &c, 3));
                }
            }
        }
    }
    if has("mailbox") {
        for &n in &ns() {
            let s = scenes::suffern_spheres(n);
            for mailbox in [false, true] {
                let c = GridConfig { mailbox, ..base };
                print_row(&format!("sph{n}"), &c, &measure(&s, &rays, &c, 5));
            }
        }
    }
    if has("mesh") || has("meshsweep") || has("meshmailbox") {
        let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(1000), 32, 17);
        let ms_list: Vec<Real> = if has("meshsweep") {
            vec![0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0]
        } else {
            vec![base.m]
        };
        for m in ms_list {
            for storage in [CellStorage::Dense, CellStorage::Hashed] {
                for mailbox in if has("meshmailbox") {
                    vec![false, true]
                } else {
                    vec![base.mailbox]
                } {
                    let c = GridConfig {
                        storage,
                        m,
                        mailbox,
                        ..base
                    };
                    print_row("mesh", &c, &measure(&tris, &rays, &c, 5));
                }
            }
        }
    }
    if has("meshnest") {
        // Nested grids in crowded cells against the flat grid, over m.
        let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(1000), 32, 17);
        for m in [0.5, 0.75, 1.25] {
            for nest_min_refs in [0, 8, 16] {
                let c = GridConfig {
                    m,
                    nest_min_refs,
                    ..base
                };
                let name = if nest_min_refs == 0 {
                    "mesh".to_string()
                } else {
                    format!("nest{nest_min_refs}")
                };
                print_row(&name, &c, &measure(&tris, &rays, &c, 5));
            }
        }
        // A coarse outer grid with finer nested grids (`nest_m`).
        let c = GridConfig {
            m: 0.3,
            nest_min_refs: 8,
            nest_m: Some(0.7),
            ..base
        };
        print_row("nest8/0.7", &c, &measure(&tris, &rays, &c, 5));
    }
    if has("meshshadow") {
        // Shadow rays (any hit) toward the book's light from every camera
        // hit on the mesh: the flat grid against nested grids.
        let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(1000), 32, 17);
        let light = Vec3::new(-10.0, 20.0, 20.0).normalize();
        let flat = Grid::build(tris.clone(), &base);
        let mut s = flat.scratch();
        let shadow: Vec<Ray> = rays
            .iter()
            .filter_map(|r| {
                let h = flat.closest_hit(r, 0.0, Real::INFINITY, &mut s)?;
                Some(Ray::new(r.origin + r.dir * h.t + light * 1e-3, light))
            })
            .collect();
        for (m, nest_min_refs) in [(1.25, 0), (1.25, 8), (0.5, 0), (0.5, 8)] {
            let c = GridConfig {
                m,
                nest_min_refs,
                ..base
            };
            let g = Grid::build(tris.clone(), &c);
            let mut s = g.scratch();
            let (t, occluded) = best_of(5, || {
                shadow
                    .iter()
                    .filter(|r| g.any_hit(r, 0.0, Real::INFINITY, &mut s))
                    .count()
            });
            println!(
                "# shadow rays m = {m}, nest_min_refs = {nest_min_refs}: {} rays, {occluded} occluded, {:.2} ms",
                shadow.len(),
                ms(t)
            );
        }
    }
    if has("meshexact") {
        let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(1000), 32, 17);
        for m in [1.5, 2.0, 3.0] {
            for exact_insertion in [false, true] {
                let c = GridConfig {
                    m,
                    exact_insertion,
                    ..base
                };
                print_row(
                    if exact_insertion { "meshexact" } else { "mesh" },
                    &c,
                    &measure(&tris, &rays, &c, 3),
                );
            }
        }
    }
    if has("bunny") {
        if let Some(tris) = load_bunny() {
            for storage in [CellStorage::Dense, CellStorage::Hashed] {
                let c = GridConfig { storage, ..base };
                print_row("bunny", &c, &measure(&tris, &bunny_rays(&tris), &c, 5));
            }
        } else {
            println!("# bunny: ../shared/scenes/bunny/stanford-bunny.obj not found, skipped");
        }
    }
    if has("exhaustive") {
        for &n in &[10usize, 100, 1000] {
            let s = scenes::suffern_spheres(n);
            let e = Exhaustive::new(s.clone());
            let (t, hits) = best_wall(if n > 100 { 1 } else { 3 }, || trace(&e, &rays));
            let (h, sum) = scenes::checksum(&hits);
            let r = measure(&s, &rays, &base, 5);
            println!(
                "# exhaustive N={n}: {:.1} ms ({:.2} Mrays/s, {} tests/ray), hits {h}, checksum {sum}; grid {:.2} ms, {:.1} tests/ray; speed-up {:.0}x",
                ms(t),
                (scenes::W * scenes::H) as f64 / t.as_secs_f64() * 1e-6,
                n,
                ms(r.trace),
                r.counters.tests_per_ray(),
                t.as_secs_f64() / r.trace.as_secs_f64()
            );
            assert_eq!((h, sum), (r.hits, r.sum), "grid and exhaustive disagree");
        }
    }
}

/// Loads the Stanford bunny with a minimal OBJ reader (`v` and `f` lines,
/// polygons fanned), if the shared scenes are present.
fn load_bunny() -> Option<Vec<Triangle>> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/bunny/stanford-bunny.obj");
    let text = std::fs::read_to_string(path).ok()?;
    let mut v = Vec::new();
    let mut tris = Vec::new();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<Real> = it.take(3).filter_map(|x| x.parse().ok()).collect();
                if c.len() == 3 {
                    v.push(gridrt_grid::Vec3::new(c[0], c[1], c[2]));
                }
            }
            Some("f") => {
                let idx: Vec<usize> = it
                    .filter_map(|x| x.split('/').next()?.parse::<isize>().ok())
                    .map(|i| {
                        if i < 0 {
                            (v.len() as isize + i) as usize
                        } else {
                            i as usize - 1
                        }
                    })
                    .collect();
                for k in 1..idx.len().saturating_sub(1) {
                    if let (Some(&a), Some(&b), Some(&c)) =
                        (v.get(idx[0]), v.get(idx[k]), v.get(idx[k + 1]))
                    {
                        tris.push(Triangle::new(a, b, c));
                    }
                }
            }
            _ => {}
        }
    }
    (!tris.is_empty()).then_some(tris)
}

/// 400×400 rays at the bunny from in front, framing its box.
fn bunny_rays(tris: &[Triangle]) -> Vec<Ray> {
    let b = tris
        .iter()
        .fold(gridrt_grid::Aabb::EMPTY, |b, t| b.union(t.bounds(&())));
    let c = b.centroid();
    let e = b.extent().max_element();
    let eye = c + gridrt_grid::Vec3::new(0.0, 0.0, 3.0 * e);
    let mut rays = Vec::with_capacity(scenes::W * scenes::H);
    for r in 0..scenes::H {
        for col in 0..scenes::W {
            let x = (col as Real + 0.5) / scenes::W as Real - 0.5;
            let y = (r as Real + 0.5) / scenes::H as Real - 0.5;
            let target = c + gridrt_grid::Vec3::new(x * e * 1.2, y * e * 1.2, 0.0);
            rays.push(Ray::new(eye, (target - eye).normalize()));
        }
    }
    rays
}
