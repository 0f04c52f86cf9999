//! Timed runs of the benchmark through the tracer's public API, and the
//! counting pass for primitive tests per ray. Nothing here is an algorithm
//! of its own: scene generation is `gridrt_tracer::suffern`, rendering is
//! `Renderer`, counting uses the grid's and the exhaustive accelerator's
//! `closest_hit_counted`.

use gridrt_grid::{
    Accelerator, Exhaustive, Grid, GridConfig, GridStats, QueryCounters, Ray, Real, Vec3,
};
use gridrt_tracer::suffern::{self, DEFAULT_SEED};
use gridrt_tracer::{AccelKind, Framebuffer, RenderOptions, Renderer, Sphere};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// Wall time of a closure and its result.
pub fn timed<R>(f: impl FnOnce() -> R) -> (R, Duration) {
    let start = Instant::now();
    let r = f();
    (r, start.elapsed())
}

/// One grid run: generate the spheres, build, render.
#[derive(Debug)]
pub struct GridRun {
    /// `suffern::sphere_set`.
    pub generate: Duration,
    /// `Renderer::new` (validation, conversion, grid build).
    pub build: Duration,
    /// `Renderer::render` (trace and shade every pixel).
    pub render: Duration,
    /// The image.
    pub image: Framebuffer,
    /// Pixels hit.
    pub pixels_hit: u64,
    /// The grid's statistics.
    pub stats: GridStats,
}

fn options(accel: AccelKind, grid: GridConfig, threads: usize) -> RenderOptions {
    RenderOptions {
        accel,
        grid,
        threads: Some(threads),
        ..RenderOptions::default()
    }
}

/// Generates, builds and renders the benchmark with `n` spheres and a grid.
///
/// # Errors
/// The renderer's error as text (none expected for this scene).
pub fn grid_run(n: usize, config: GridConfig, threads: usize) -> Result<GridRun, String> {
    let (scene, generate) =
        timed(|| suffern::scene_of(suffern::sphere_set_threads(n, DEFAULT_SEED, threads)));
    let (renderer, build) =
        timed(|| Renderer::new(&scene, &options(AccelKind::Grid, config, threads)));
    drop(scene);
    let renderer = renderer.map_err(|e| e.to_string())?;
    let never = AtomicBool::new(false);
    let (out, render) = timed(|| renderer.render(&|_, _| {}, &never));
    let (image, stats) = out.map_err(|e| e.to_string())?;
    let grid = renderer
        .grid_stats()
        .cloned()
        .ok_or("the grid renderer has no grid statistics")?;
    // Free the grid outside the timed region (a million spheres take a while).
    drop(renderer);
    Ok(GridRun {
        generate,
        build,
        render,
        image,
        pixels_hit: stats.pixels_hit,
        stats: grid,
    })
}

/// Times `runs` closest-hit-only passes over the camera rays
/// (`Renderer::count_camera_hits`, one thread), after one warm-up.
///
/// # Errors
/// The renderer's error as text.
pub fn trace_only(
    n: usize,
    config: GridConfig,
    runs: usize,
) -> Result<(Vec<Duration>, u64), String> {
    let renderer = suffern::renderer(n, DEFAULT_SEED, &options(AccelKind::Grid, config, 1))
        .map_err(|e| e.to_string())?;
    let hits = renderer.count_camera_hits();
    let times = (0..runs)
        .map(|_| timed(|| renderer.count_camera_hits()).1)
        .collect();
    Ok((times, hits))
}

/// One exhaustive run over all rows or some of them.
#[derive(Debug)]
pub struct ExhaustiveRun {
    /// `Renderer::new` with `AccelKind::Exhaustive`.
    pub build: Duration,
    /// Rendering the rows.
    pub render: Duration,
    /// The full-size image; rows not rendered stay black.
    pub image: Framebuffer,
}

/// Builds the exhaustive renderer and renders the whole image, or only the
/// image rows listed in `rows` (`Renderer::render_rows`: each row bit for
/// bit as in the whole frame), copied into a black full-size image for
/// comparison.
///
/// # Errors
/// The renderer's error as text, or a row outside the image.
pub fn exhaustive_run(
    n: usize,
    threads: usize,
    rows: Option<&[u32]>,
) -> Result<ExhaustiveRun, String> {
    let scene = suffern::scene(n);
    let (width, height) = (scene.settings.width, scene.settings.height);
    if let Some(&y) = rows.and_then(|r| r.iter().find(|&&y| y >= height)) {
        return Err(format!("row {y} is outside an image {height} rows high"));
    }
    let opts = options(AccelKind::Exhaustive, GridConfig::default(), threads);
    let (renderer, build) = timed(|| Renderer::new(&scene, &opts));
    drop(scene);
    let renderer = renderer.map_err(|e| e.to_string())?;
    let never = AtomicBool::new(false);
    let (out, render) = timed(|| match rows {
        None => renderer.render(&|_, _| {}, &never),
        Some(r) => renderer.render_rows(r, &|_, _| {}, &never),
    });
    let (part, _) = out.map_err(|e| e.to_string())?;
    let image = match rows {
        None => part,
        Some(rows) => {
            let mut full = Framebuffer::new(width, height);
            let w = width as usize;
            for (i, &y) in rows.iter().enumerate() {
                let y = y as usize;
                full.pixels[y * w..(y + 1) * w].copy_from_slice(&part.pixels[i * w..(i + 1) * w]);
            }
            full
        }
    };
    Ok(ExhaustiveRun {
        build,
        render,
        image,
    })
}

/// The benchmark's camera ray through the centre of pixel (c, r), r = 0 at
/// the bottom: Suffern's view plane at distance 3600 with pixel size 1, as
/// the Embree peer writes it (`normalize(c − 200 + 0.5, r − 200 + 0.5,
/// −3600)` from (0, 0, 20)); the tracer's camera gives the same bits.
pub fn camera_ray(c: u32, r: u32, resolution: u32) -> Ray {
    let half = f64::from(resolution) * 0.5;
    let dx = (f64::from(c) - half + 0.5) as Real;
    let dy = (f64::from(r) - half + 0.5) as Real;
    let dz: Real = -3600.0;
    let inv = 1.0 / (dx * dx + dy * dy + dz * dz).sqrt();
    Ray::new(
        Vec3::new(0.0, 0.0, 20.0),
        Vec3::new(dx * inv, dy * inv, dz * inv),
    )
}

/// What the counting pass found.
#[derive(Debug, Default)]
pub struct Counted {
    /// Queries, cells visited, primitive tests.
    pub counters: QueryCounters,
    /// Per pixel (index `r · resolution + c`, r = 0 at the bottom, as the
    /// Embree peer), the index of the sphere hit, or `u32::MAX`.
    pub prims: Vec<u32>,
}

impl Counted {
    /// Pixels whose ray hit a sphere.
    pub fn pixels_hit(&self) -> u64 {
        self.prims.iter().filter(|&&p| p != u32::MAX).count() as u64
    }
}

/// Builds a grid over the spheres and traces every camera ray, counting
/// cells visited and sphere tests.
pub fn count_grid(spheres: Vec<Sphere>, config: &GridConfig, resolution: u32) -> Counted {
    let grid = Grid::build(spheres, config);
    let mut scratch = grid.scratch();
    let mut out = Counted {
        prims: Vec::with_capacity((resolution * resolution) as usize),
        ..Counted::default()
    };
    for r in 0..resolution {
        for c in 0..resolution {
            let ray = camera_ray(c, r, resolution);
            let hit = grid.closest_hit_counted(
                &ray,
                0.0,
                Real::INFINITY,
                &mut scratch,
                &mut out.counters,
            );
            out.prims.push(hit.map_or(u32::MAX, |h| h.prim));
        }
    }
    out
}

/// Exhaustive tests per ray, counted on `samples` camera rays spread over
/// the image (every ray tests every sphere, so a sample is exact).
pub fn count_exhaustive(spheres: Vec<Sphere>, resolution: u32, samples: u32) -> QueryCounters {
    let acc = Exhaustive::new(spheres);
    let mut counters = QueryCounters::default();
    let pixels = resolution * resolution;
    let samples = samples.clamp(1, pixels);
    for i in 0..samples {
        let p = (u64::from(2 * i + 1) * u64::from(pixels) / u64::from(2 * samples)) as u32;
        let ray = camera_ray(p % resolution, p / resolution, resolution);
        acc.closest_hit_counted(&ray, 0.0, Real::INFINITY, &mut counters);
    }
    counters
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counting_agrees_with_the_renderer_and_the_peer() {
        let set = suffern::sphere_set(100, DEFAULT_SEED);
        let counted = count_grid(set.spheres.clone(), &GridConfig::default(), 400);
        assert_eq!(counted.pixels_hit(), 35_175);
        assert_eq!(counted.counters.rays, 160_000);
        assert!(counted.counters.tests_per_ray() > 0.0);
        let ex = count_exhaustive(set.spheres, 400, 7);
        assert_eq!((ex.rays, ex.tests), (7, 700));
    }

    #[test]
    fn grid_and_exhaustive_runs_render_the_same_image() {
        assert_eq!(
            grid_run(10, GridConfig::default(), 1).unwrap().pixels_hit,
            16_972
        );
        let rows = crate::table::spread_rows(6, 400);
        let e = exhaustive_run(100, 2, Some(&rows)).unwrap();
        let g = grid_run(100, GridConfig::default(), 2).unwrap();
        assert_eq!(
            crate::bitdiff::bitwise_diff(&g.image, &e.image, Some(&rows)),
            Ok(None)
        );
        // The rows have spheres in them, and the other rows stay black.
        assert!(rows
            .iter()
            .any(|&y| g.image.pixels[y as usize * 400..][..400]
                .iter()
                .any(|p| p.x > 0.0)));
        let black = |y: usize| {
            e.image.pixels[y * 400..][..400]
                .iter()
                .all(|p| p.to_array() == [0.0; 3])
        };
        assert!((0..400).filter(|&y| !rows.contains(&(y as u32))).all(black));
        assert!(!rows.iter().all(|&y| black(y as usize)));
        let full = exhaustive_run(10, 1, None).unwrap();
        let g10 = grid_run(10, GridConfig::default(), 1).unwrap();
        assert_eq!(
            crate::bitdiff::bitwise_diff(&g10.image, &full.image, None),
            Ok(None)
        );
        assert!(exhaustive_run(10, 1, Some(&[400])).is_err());
    }
}
