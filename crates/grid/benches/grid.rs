//! Criterion benches of the grid: build time, closest-hit throughput, hashed
//! versus dense storage, mailbox on and off, an `m` sweep, a triangle mesh,
//! and the exhaustive baseline (at small N only). Inputs are built before
//! timing from the peer's seeded LCG (Suffern's scene). For the full-size
//! comparison with the Embree peer see `benches/suffern.rs`.
//!
//! `GRIDRT_BENCH_BIG=1` adds N = 1,000,000 (slow).

#[path = "../tests/support/prims.rs"]
mod prims;
#[path = "../tests/support/scenes.rs"]
mod scenes;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use gridrt_grid::{Accelerator, CellStorage, Exhaustive, Grid, GridConfig, Ray, Real};
use std::hint::black_box;
use std::time::Duration;

fn sizes() -> Vec<usize> {
    let mut v = vec![1_000, 10_000, 100_000];
    if std::env::var_os("GRIDRT_BENCH_BIG").is_some() {
        v.push(1_000_000);
    }
    v
}

/// Every 8th ray of the 400×400 image: 20,000 rays spread over the picture.
fn rays() -> Vec<Ray> {
    scenes::suffern_rays().into_iter().step_by(8).collect()
}

fn trace<A: Accelerator>(acc: &A, rays: &[Ray], s: &mut A::Scratch) -> usize {
    rays.iter()
        .filter(|r| acc.closest_hit(r, 0.0, Real::INFINITY, s).is_some())
        .count()
}

fn build(c: &mut Criterion) {
    let mut g = c.benchmark_group("build");
    g.sample_size(10).measurement_time(Duration::from_secs(3));
    for n in sizes() {
        let s = scenes::suffern_spheres(n);
        g.throughput(Throughput::Elements(n as u64));
        for storage in [CellStorage::Dense, CellStorage::Hashed] {
            for parallel_build in [false, true] {
                let cfg = GridConfig {
                    storage,
                    parallel_build,
                    ..GridConfig::default()
                };
                let id = format!(
                    "{storage:?}/{}",
                    if parallel_build { "rayon" } else { "1 thread" }
                );
                g.bench_with_input(BenchmarkId::new(id, n), &s, |b, s| {
                    b.iter_batched(
                        || s.clone(),
                        |p| black_box(Grid::build(p, &cfg)),
                        criterion::BatchSize::LargeInput,
                    )
                });
            }
        }
    }
    g.finish();
}

fn closest_hit(c: &mut Criterion) {
    let rays = rays();
    let mut g = c.benchmark_group("closest_hit");
    g.sample_size(10).measurement_time(Duration::from_secs(3));
    g.throughput(Throughput::Elements(rays.len() as u64));
    for n in sizes() {
        let s = scenes::suffern_spheres(n);
        for storage in [CellStorage::Dense, CellStorage::Hashed] {
            for mailbox in [false, true] {
                let grid = Grid::build(
                    s.clone(),
                    &GridConfig {
                        storage,
                        mailbox,
                        ..GridConfig::default()
                    },
                );
                let id = format!("{storage:?}/mailbox {}", if mailbox { "on" } else { "off" });
                let mut sc = grid.scratch();
                g.bench_function(BenchmarkId::new(id, n), |b| {
                    b.iter(|| black_box(trace(&grid, &rays, &mut sc)))
                });
            }
        }
        if n <= 1_000 {
            let e = Exhaustive::new(s.clone());
            g.bench_function(BenchmarkId::new("exhaustive", n), |b| {
                b.iter(|| black_box(trace(&e, &rays, &mut ())))
            });
        }
    }
    g.finish();
}

fn m_sweep(c: &mut Criterion) {
    let rays = rays();
    let s = scenes::suffern_spheres(100_000);
    let mut g = c.benchmark_group("m_sweep_100k");
    g.sample_size(10).measurement_time(Duration::from_secs(2));
    for m in [0.75, 1.0, 1.25, 1.5, 2.0, 3.0] {
        let cfg = GridConfig {
            m,
            ..GridConfig::default()
        };
        g.bench_function(BenchmarkId::new("build", m), |b| {
            b.iter_batched(
                || s.clone(),
                |p| black_box(Grid::build(p, &cfg)),
                criterion::BatchSize::LargeInput,
            )
        });
        let grid = Grid::build(s.clone(), &cfg);
        let mut sc = grid.scratch();
        g.bench_function(BenchmarkId::new("trace", m), |b| {
            b.iter(|| black_box(trace(&grid, &rays, &mut sc)))
        });
    }
    g.finish();
}

fn mesh(c: &mut Criterion) {
    let rays = rays();
    // 100 of the 1000-sphere scene's spheres as 32×17 UV spheres: 102,400 triangles.
    let tris = scenes::uv_sphere_mesh(&scenes::suffern_spheres(1000)[..100], 32, 17);
    let mut g = c.benchmark_group("mesh_102k");
    g.sample_size(10).measurement_time(Duration::from_secs(3));
    for m in [1.25, 2.0, 3.0] {
        for storage in [CellStorage::Dense, CellStorage::Hashed] {
            let grid = Grid::build(
                tris.clone(),
                &GridConfig {
                    m,
                    storage,
                    ..GridConfig::default()
                },
            );
            let mut sc = grid.scratch();
            g.bench_function(BenchmarkId::new(format!("{storage:?}/trace"), m), |b| {
                b.iter(|| black_box(trace(&grid, &rays, &mut sc)))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, build, closest_hit, m_sweep, mesh);
criterion_main!(benches);
