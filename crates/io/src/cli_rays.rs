//! `gridrt rays`: batch closest-hit queries against a mesh, with the
//! build and the query loop timed apart and, with `--stats`, the work per
//! ray counted in a pass of its own.

use crate::cli::{accel_label, check_outputs, warn, Accel, RaysArgs};
use crate::cli_stats::{self, speed_text, Perf, RaysJson};
use crate::error::{Error, Result};
use crate::image_out::{check_output_dir, stage, write_atomic};
use crate::model::{load_model_in, Model};
use crate::rays::{format_hits, parse_rays, trace_rays_into};
use crate::RayQuery;
use gridrt_grid::{Exhaustive, Grid, GridStats, Primitive, QueryCounters};
use gridrt_tracer::{
    MeshTriangle, MeshVertices, MtTriangle, Triangle, TriangleStorage, TriangleTest,
};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Runs `f(true)` in a thread pool of its own (`threads` workers, or one
/// per core), or `f(false)` on this thread when no pool can be started (a
/// container's process limit): rayon's global pool would panic there.
fn in_pool<R: Send>(threads: Option<u32>, f: impl FnOnce(bool) -> R + Send) -> R {
    #[cfg(feature = "rayon")]
    if let Ok(pool) = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.map_or(0, |t| t as usize))
        .build()
    {
        return pool.install(|| f(true));
    }
    #[cfg(not(feature = "rayon"))]
    let _ = threads;
    f(false)
}

/// Runs `gridrt rays`.
///
/// # Errors
/// Any [`Error`] of loading, parsing or writing.
pub(crate) fn rays(a: &RaysArgs, out: &mut dyn Write) -> Result<()> {
    a.intersect.check()?;
    let mut outputs = Vec::new();
    if let Some(o) = &a.output {
        check_output_dir(o)?;
        outputs.push(("-o", o.as_path()));
    }
    if let Some(s) = &a.stats {
        check_output_dir(s)?;
        outputs.push(("--stats", s.as_path()));
    }
    check_outputs(&outputs, &[a.mesh.clone(), a.rays.clone()])?;
    let sandbox = a.access.sandbox(Some(&a.mesh))?;
    let model = load_model_in(&a.mesh, &sandbox)?;
    warn(&model.warnings);
    let bytes = sandbox.read(&a.rays)?;
    check_outputs(&outputs, &sandbox.files_read())?;
    let queries = parse_rays(&String::from_utf8_lossy(&bytes), &a.rays)?;
    let n_tris = model.triangle_count();
    let storage = (a.intersect.triangle_storage())
        .for_test(a.intersect.triangle_test())
        .resolve(n_tris);
    let indexed = storage == TriangleStorage::Indexed;
    // The triangles in the form asked for; the model goes (the grid
    // keeps what it needs).
    let prims = match (indexed, a.intersect.triangle_test()) {
        (true, _) => {
            let (verts, tris) = mesh_triangles(model, &a.mesh)?;
            RaysPrims::Indexed(verts, tris)
        }
        (false, test) => {
            let copies = model
                .triangles()
                .map(|[p0, p1, p2]| Triangle::new(p0, p1, p2));
            match test {
                TriangleTest::Watertight => RaysPrims::Copies(copies.collect()),
                TriangleTest::MollerTrumbore => RaysPrims::Mt(copies.map(MtTriangle).collect()),
            }
        }
    };
    let want_counts = a.stats.is_some();
    let (run, threads) = in_pool(a.threads, |parallel| {
        let threads = if parallel { rayon_threads() } else { 1 };
        let run = match prims {
            RaysPrims::Copies(v) => run_on(a, v, (), &queries, parallel, want_counts),
            RaysPrims::Mt(v) => run_on(a, v, (), &queries, parallel, want_counts),
            RaysPrims::Indexed(verts, v) => run_on(a, v, verts, &queries, parallel, want_counts),
        };
        (run, threads)
    });
    let n_hit = run.hits.iter().filter(|h| h.is_some()).count() as u64;
    let text = format_hits(&run.hits);
    let stats_file = match &a.stats {
        Some(p) => {
            let c = run.counters.unwrap_or_default();
            let n = queries.len() as u64;
            let json = RaysJson {
                mesh: a.mesh.display().to_string(),
                rays_file: a.rays.display().to_string(),
                triangles: n_tris,
                triangle_storage: cli_stats::storage_name(storage),
                threads,
                perf: Perf {
                    accel: cli_stats::chosen(a.accel.accel, run.grid.as_ref()),
                    accel_requested: a.accel.accel.name(),
                    build_s: run.build.as_secs_f64(),
                    trace_s: run.trace.as_secs_f64(),
                    rays: n,
                    hits: n_hit,
                    mrays_per_s: cli_stats::mrays(n, run.trace.as_secs_f64()),
                    cells_per_ray: c.cells_per_ray(),
                    tests_per_ray: c.tests_per_ray(),
                    bytes: run.grid.as_ref().map_or(0, |g| g.bytes),
                },
                grid: run.grid.as_ref().map(cli_stats::GridJson::new),
            };
            let json = serde_json::to_string_pretty(&json)
                .map_err(|e| Error::output(p, format!("cannot encode statistics: {e}")))?;
            Some(stage(p, |f| {
                f.write_all(json.as_bytes())?;
                f.write_all(b"\n")
            })?)
        }
        None => None,
    };
    match &a.output {
        Some(p) => write_atomic(p, |f| f.write_all(text.as_bytes()))?,
        None => out
            .write_all(text.as_bytes())
            .and_then(|()| out.flush())
            .map_err(|e| Error::Write {
                path: PathBuf::from("<standard output>"),
                source: e,
            })?,
    }
    if let Some(f) = stats_file {
        f.commit()?;
    }
    if std::io::stderr().is_terminal() {
        eprintln!(
            "{} rays, {n_hit} hits, {n_tris} triangles, {} on {threads} threads: build {:.3} s, trace {:.3} s ({})",
            queries.len(),
            accel_label(&a.accel, run.grid.as_ref()),
            run.build.as_secs_f64(),
            run.trace.as_secs_f64(),
            speed_text(queries.len() as u64, run.trace.as_secs_f64())
        );
    }
    Ok(())
}

/// The triangles `gridrt rays` tests, in the form `--triangle-test` and
/// `--triangles` ask for.
enum RaysPrims {
    Copies(Vec<Triangle>),
    Mt(Vec<MtTriangle>),
    Indexed(MeshVertices, Vec<MeshTriangle>),
}

/// The model's triangles as [`MeshTriangle`]s over one vertex array, the
/// vertices renumbered in the triangles' spatial order.
fn mesh_triangles(model: Model, path: &Path) -> Result<(MeshVertices, Vec<MeshTriangle>)> {
    let (positions, indices) = model.indexed();
    drop(model);
    let verts = MeshVertices::new(positions);
    let mut tris = MeshTriangle::from_indices(&verts, &indices).ok_or_else(|| Error::Limit {
        path: path.to_path_buf(),
        place: String::new(),
        msg: format!(
            "more than {} vertices: too many for --triangles indexed",
            MeshTriangle::MAX_VERTICES
        ),
    })?;
    drop(indices);
    Ok((verts.in_spatial_order(&mut tris), tris))
}

/// Builds the accelerator `a` asks for over `prims` (with the grid switches
/// of `--mailbox`, `--exact-insertion` and `--slab`) and answers `queries`,
/// timing the build and the query loop apart.
fn run_on<P: Primitive + Clone + Send + Sync>(
    a: &RaysArgs,
    prims: Vec<P>,
    shared: P::Shared,
    queries: &[RayQuery],
    parallel: bool,
    want_counts: bool,
) -> RaysRun {
    match a.accel.accel {
        Accel::Exhaustive => {
            let (e, build) = timed(|| Exhaustive::with_shared(prims, shared));
            let (hits, trace) = answers(queries, |out| trace_rays_into(&e, queries, out, parallel));
            let counters = want_counts.then(|| cli_stats::count_exhaustive(&e, queries));
            RaysRun {
                hits,
                build,
                trace,
                counters,
                grid: None,
            }
        }
        _ => {
            let mut config = a.intersect.grid(a.accel.grid_config());
            config.parallel_build &= parallel;
            let (g, build) = timed(|| Grid::build_shared(prims, shared, &config));
            let (hits, trace) = answers(queries, |out| trace_rays_into(&g, queries, out, parallel));
            let counters = want_counts.then(|| cli_stats::count_grid(&g, queries));
            let grid = Some(g.stats().clone());
            RaysRun {
                hits,
                build,
                trace,
                counters,
                grid,
            }
        }
    }
}

/// What `gridrt rays` measured.
struct RaysRun {
    hits: Vec<Option<gridrt_grid::Hit>>,
    build: std::time::Duration,
    trace: std::time::Duration,
    counters: Option<QueryCounters>,
    grid: Option<GridStats>,
}

/// The answers `trace` writes for `queries`, and the time it took: the
/// answers' memory is allocated and written once before the clock starts,
/// so that the time is the query loop's alone (`trace_s`), not the page
/// faults of a fresh array.
fn answers(
    queries: &[RayQuery],
    trace: impl FnOnce(&mut [Option<gridrt_grid::Hit>]),
) -> (Vec<Option<gridrt_grid::Hit>>, std::time::Duration) {
    let mut out = Vec::with_capacity(queries.len());
    out.resize(queries.len(), None);
    let ((), t) = timed(|| trace(&mut out));
    (out, t)
}

fn timed<R>(f: impl FnOnce() -> R) -> (R, std::time::Duration) {
    let start = Instant::now();
    let r = f();
    (r, start.elapsed())
}

/// The current pool's worker count.
fn rayon_threads() -> usize {
    #[cfg(feature = "rayon")]
    return rayon::current_num_threads();
    #[cfg(not(feature = "rayon"))]
    1
}
