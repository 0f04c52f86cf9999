//! The public render API: options, the prepared [`Renderer`], the
//! framebuffer and statistics, and the tile loop (parallel with rayon).

use crate::accel_of::{build_accel, grid_config, with_accel, Accel, AccelOf, TriangleStorage};
use crate::camera::CameraModel;
use crate::error::{Cancelled, SceneError};
use crate::framebuffer::{Framebuffer, ImageBuf, LiveImage, PixelFormat, PixelRect, Srgb8Image};
use crate::instancing::InstancingStats;
use crate::integrator::{Found, Integrator, Li, SceneData, Shading, ThreadState, Tracer, Whitted};
use crate::path::PathTracer;
use crate::plan::{EffectPlan, IntegratorKind, RayCounts};
use crate::pool::Pool;
use crate::prepare::{prepare, Prepared, Prims};
use crate::robustness::{with_triangle_test, RayOffset, TriangleTest};
use crate::sampling::{FilterTable, PixelSamples, SampleStream, SamplerKind};
use crate::scene::{Rgb, Scene};
use crate::shapes::Surface;
pub use crate::stats::RenderStats;
use crate::tiles::{tiles, Tile, TILE};
use gridrt_bbox::{Ray, Real, Vec3};
use gridrt_grid::{Accelerator, Exhaustive, Grid, GridConfig, GridStats};
use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Which accelerator answers the ray queries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// The regular grid, configured by [`RenderOptions::grid`] (the
    /// default; its cell storage is `GridConfig::storage`).
    #[default]
    Grid,
    /// The regular grid with a dense cell table, whatever
    /// `GridConfig::storage` says.
    DenseGrid,
    /// No acceleration: every ray tests every primitive (the baseline).
    Exhaustive,
}

/// How to render: accelerator, grid parameters, threads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// The accelerator.
    pub accel: AccelKind,
    /// Grid build parameters. [`AccelKind::Grid`] uses them as given;
    /// [`AccelKind::DenseGrid`] forces `storage` to [`CellStorage::Dense`](gridrt_grid::CellStorage::Dense).
    /// With `threads: Some(1)` the build is sequential whatever
    /// `parallel_build` says.
    pub grid: GridConfig,
    /// Worker threads for building and rendering; `None` = all cores.
    /// The image does not depend on it.
    pub threads: Option<usize>,
    /// The ray–triangle test (default: watertight).
    pub triangle_test: TriangleTest,
    /// How the accelerator stores a mesh scene's triangles (default:
    /// [`TriangleStorage::Auto`]).
    pub triangles: TriangleStorage,
    /// How secondary rays leave surfaces (default: by the error bound).
    pub ray_offset: RayOffset,
    /// Whether a mesh placed by several [`crate::Geometry::Instance`]
    /// objects keeps one grid shared by its placements (default); when
    /// false every placement is baked into world space.
    pub instancing: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            accel: AccelKind::Grid,
            grid: GridConfig::default(),
            threads: None,
            triangle_test: TriangleTest::Watertight,
            triangles: TriangleStorage::Auto,
            ray_offset: RayOffset::ErrorBound,
            instancing: true,
        }
    }
}

/// A scene prepared for rendering: validated, accelerator built, effect
/// plan derived. Render it as often as needed (it is immutable and `Sync`).
pub struct Renderer {
    accel: Accel,
    data: SceneData,
    camera: CameraModel,
    plan: EffectPlan,
    width: u32,
    height: u32,
    spp: u32,
    filter: FilterTable,
    build_time: Duration,
    grid_stats: Option<GridStats>,
    prim_count: usize,
    instancing: InstancingStats,
    pool: Pool,
}

impl fmt::Debug for Renderer {
    /// A summary, not the million primitives.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let accel = self.accel.name();
        f.debug_struct("Renderer")
            .field("accel", &accel)
            .field("primitives", &self.prim_count)
            .field("size", &(self.width, self.height))
            .field("spp", &self.spp)
            .field("plan", &self.plan)
            .field("build_time", &self.build_time)
            .finish_non_exhaustive()
    }
}

/// The grids of shared meshes: like the scene's (the exhaustive
/// accelerator, a reference for the scene's level, keeps them).
fn mesh_grid_config(options: &RenderOptions, parallel: bool) -> GridConfig {
    grid_config(options, parallel).unwrap_or(GridConfig {
        parallel_build: parallel,
        ..options.grid
    })
}

impl Renderer {
    /// Validates the scene, derives the effect plan and builds the
    /// accelerator (in parallel when threads allow).
    ///
    /// # Errors
    /// A [`SceneError`] naming the first problem found.
    pub fn new(scene: &Scene, options: &RenderOptions) -> Result<Renderer, SceneError> {
        let start = Instant::now();
        let pool = Pool::new(options.threads);
        let prepared = Self::prepare(scene, options, &pool)?;
        Ok(Self::build(prepared, options, pool, start))
    }

    /// [`Renderer::new`], but `scene.objects` is emptied as soon as the
    /// scene is converted, before the accelerator is built: whatever the
    /// renderer does not share with the scene (with
    /// [`TriangleStorage::Indexed`](crate::TriangleStorage::Indexed), the
    /// meshes' arrays) is freed before the grid takes its memory.
    ///
    /// # Errors
    /// A [`SceneError`] naming the first problem found (`scene` is then
    /// left as it was).
    pub fn new_taking_objects(
        scene: &mut Scene,
        options: &RenderOptions,
    ) -> Result<Renderer, SceneError> {
        let start = Instant::now();
        let pool = Pool::new(options.threads);
        let prepared = Self::prepare(scene, options, &pool)?;
        scene.objects = Vec::new();
        Ok(Self::build(prepared, options, pool, start))
    }

    /// Validation and conversion: everything before the accelerator.
    fn prepare(
        scene: &Scene,
        options: &RenderOptions,
        pool: &Pool,
    ) -> Result<Prepared, SceneError> {
        let mesh_grid = mesh_grid_config(options, pool.is_parallel());
        pool.install(|| {
            prepare(
                scene,
                options.instancing.then_some(&mesh_grid),
                options.triangles.for_test(options.triangle_test),
            )
        })
    }

    /// The accelerator over prepared primitives, and the renderer.
    fn build(prepared: Prepared, options: &RenderOptions, pool: Pool, start: Instant) -> Renderer {
        let parallel = pool.is_parallel();
        let Prepared {
            mut data,
            prims,
            camera,
            plan,
            width,
            height,
            spp,
            instancing,
            ..
        } = prepared.numbered();
        data.ray_offset = options.ray_offset;
        let prims = with_triangle_test(prims, options.triangle_test);
        let prim_count = prims.len() + data.planes.len();
        let (accel, grid_stats) = pool.install(|| match prims {
            Prims::Spheres(v) => {
                let (a, s) = build_accel(v, (), options, parallel);
                (Accel::Spheres(a), s)
            }
            Prims::Set(set) => {
                let (a, s) = match grid_config(options, parallel) {
                    Some(config) => {
                        let grid = Grid::build_from_slice(&set.spheres, &config);
                        let stats = grid.stats().clone();
                        (AccelOf::Grid(grid), Some(stats))
                    }
                    None => (
                        AccelOf::Exhaustive(Exhaustive::new(set.spheres.clone())),
                        None,
                    ),
                };
                (Accel::Spheres(a), s)
            }
            Prims::Triangles(v) => {
                let (a, s) = build_accel(v, (), options, parallel);
                (Accel::Triangles(a), s)
            }
            Prims::Mesh(verts, tris) => {
                let (a, s) = build_accel(tris, verts, options, parallel);
                (Accel::Mesh(a), s)
            }
            Prims::Shapes(v) => {
                let (a, s) = build_accel(v, (), options, parallel);
                (Accel::Shapes(a), s)
            }
        });
        let filter = FilterTable::new(plan.filter);
        Renderer {
            accel,
            data,
            camera,
            filter,
            plan,
            width,
            height,
            spp,
            build_time: start.elapsed(),
            grid_stats,
            prim_count,
            instancing,
            pool,
        }
    }

    /// The effects this renderer simulates.
    #[must_use]
    pub fn plan(&self) -> &EffectPlan {
        &self.plan
    }

    /// What instancing kept shared: meshes with a grid of their own, their
    /// placements, and the memory both take.
    #[must_use]
    pub fn instancing(&self) -> &InstancingStats {
        &self.instancing
    }

    /// The grid's statistics (`None` for the exhaustive accelerator).
    #[must_use]
    pub fn grid_stats(&self) -> Option<&GridStats> {
        self.grid_stats.as_ref()
    }

    /// Time spent in [`Renderer::new`]: validation, conversion, accelerator
    /// build.
    #[must_use]
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// Primitives: grid primitives (one per sphere, box and non-degenerate
    /// triangle) plus planes.
    #[must_use]
    pub fn primitive_count(&self) -> usize {
        self.prim_count
    }

    /// How the accelerator stores triangles: [`TriangleStorage::Copies`]
    /// or [`TriangleStorage::Indexed`] for a scene of mesh triangles alone,
    /// `None` for other scenes and for the Möller–Trumbore test (whose
    /// primitives are shapes).
    #[must_use]
    pub fn triangle_storage(&self) -> Option<TriangleStorage> {
        match self.accel {
            Accel::Triangles(_) => Some(TriangleStorage::Copies),
            Accel::Mesh(_) => Some(TriangleStorage::Indexed),
            Accel::Spheres(_) | Accel::Shapes(_) => None,
        }
    }

    /// The image size in pixels, `(width, height)`.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Renders the image. `progress(done, total)` is called (from worker
    /// threads) after each tile, in pixels. When `cancel` becomes true the
    /// remaining tiles are skipped and the answer is [`Cancelled`].
    ///
    /// # Errors
    /// [`Cancelled`] when the flag was raised.
    pub fn render(
        &self,
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
    ) -> Result<(Framebuffer, RenderStats), Cancelled> {
        self.render_job(&self.all_rows(), (0, self.width), progress, cancel)
    }

    /// Renders only the pixels of `window` (a crop window or one tile of a
    /// frame split across processes). The answer is an image of the
    /// window's size whose pixels are bit for bit those of the same region
    /// of [`Renderer::render`]'s image: a pixel depends only on its
    /// position in the full image, never on the window or the threads.
    ///
    /// ```
    /// use gridrt_tracer::{suffern, PixelRect, RenderOptions, Renderer};
    /// use std::sync::atomic::AtomicBool;
    /// let r = suffern::renderer(100, suffern::DEFAULT_SEED, &RenderOptions::default()).unwrap();
    /// let never = AtomicBool::new(false);
    /// let (full, _) = r.render(&|_, _| {}, &never).unwrap();
    /// let w = PixelRect { x0: 190, y0: 180, x1: 230, y1: 200 };
    /// let (part, _) = r.render_window(w, &|_, _| {}, &never).unwrap();
    /// assert_eq!((part.width, part.height), (40, 20));
    /// assert_eq!(part.get(3, 5), full.get(193, 185));
    /// ```
    ///
    /// # Errors
    /// [`Cancelled`] when the flag was raised.
    ///
    /// # Panics
    /// When the window is empty or reaches outside the image
    /// ([`Renderer::size`]).
    pub fn render_window(
        &self,
        window: PixelRect,
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
    ) -> Result<(Framebuffer, RenderStats), Cancelled> {
        assert!(
            window.x0 < window.x1
                && window.y0 < window.y1
                && window.x1 <= self.width
                && window.y1 <= self.height,
            "window {window:?} is empty or outside a {} x {} image",
            self.width,
            self.height
        );
        let rows: Vec<u32> = (window.y0..window.y1).collect();
        self.render_job(&rows, (window.x0, window.x1), progress, cancel)
    }

    /// Renders only the image rows listed in `rows` (row 0 at the top; any
    /// order, repeats allowed), for example every k-th row to estimate the
    /// cost of a frame too slow to render whole. The answer is an image
    /// `width × rows.len()` whose row `i` is image row `rows[i]`, bit for bit
    /// as [`Renderer::render`] would give it: a pixel depends only on its
    /// position in the full image, never on which other rows are rendered or
    /// on the threads. The statistics count the rays and hits of these rows;
    /// `progress` reports pixels of these rows.
    ///
    /// ```
    /// use gridrt_tracer::{suffern, RenderOptions, Renderer};
    /// use std::sync::atomic::AtomicBool;
    /// let r = suffern::renderer(100, suffern::DEFAULT_SEED, &RenderOptions::default()).unwrap();
    /// let never = AtomicBool::new(false);
    /// let (full, _) = r.render(&|_, _| {}, &never).unwrap();
    /// let (part, _) = r.render_rows(&[10, 200, 390], &|_, _| {}, &never).unwrap();
    /// assert_eq!((part.width, part.height), (400, 3));
    /// assert_eq!(part.pixels[400..800], full.pixels[200 * 400..201 * 400]);
    /// ```
    ///
    /// # Errors
    /// [`Cancelled`] when the flag was raised.
    ///
    /// # Panics
    /// When a row is not below the image height ([`Renderer::size`]).
    pub fn render_rows(
        &self,
        rows: &[u32],
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
    ) -> Result<(Framebuffer, RenderStats), Cancelled> {
        if let Some(&y) = rows.iter().find(|&&y| y >= self.height) {
            panic!("row {y} outside an image {} rows high", self.height);
        }
        self.render_job(rows, (0, self.width), progress, cancel)
    }

    /// [`Renderer::render`], filling `live` as tiles finish: another
    /// thread can take snapshots of the image while it renders (partial
    /// images), and after a cancellation `live` holds what was done and
    /// which tiles are missing.
    ///
    /// # Errors
    /// [`Cancelled`] when the flag was raised.
    pub fn render_live(
        &self,
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
        live: &LiveImage,
    ) -> Result<(Framebuffer, RenderStats), Cancelled> {
        let (image, stats) = self.render_frame_live(progress, cancel, live, PixelFormat::Linear)?;
        Ok((image.into_linear(), stats))
    }

    /// [`Renderer::render_live`] into 8-bit sRGB, each tile converted as it
    /// finishes: for a PNG, the image takes a quarter of the memory, and
    /// its bytes are those of [`Srgb8Image::from_linear`] of the linear
    /// image.
    ///
    /// # Errors
    /// [`Cancelled`] when the flag was raised.
    pub fn render_srgb8(
        &self,
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
        live: &LiveImage,
    ) -> Result<(Srgb8Image, RenderStats), Cancelled> {
        let (image, stats) = self.render_frame_live(progress, cancel, live, PixelFormat::Srgb8)?;
        Ok((image.into_srgb8(), stats))
    }

    /// Every row of the image: the whole frame's rows for a job.
    fn all_rows(&self) -> Vec<u32> {
        (0..self.height).collect()
    }

    /// Renders the whole frame into an image of `format`, filling `live`.
    fn render_frame_live(
        &self,
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
        live: &LiveImage,
        format: PixelFormat,
    ) -> Result<(ImageBuf, RenderStats), Cancelled> {
        let cols = (0, self.width);
        self.render_job_live(&self.all_rows(), cols, progress, cancel, Some(live), format)
    }

    fn render_job(
        &self,
        rows: &[u32],
        cols: (u32, u32),
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
    ) -> Result<(Framebuffer, RenderStats), Cancelled> {
        let (image, stats) =
            self.render_job_live(rows, cols, progress, cancel, None, PixelFormat::Linear)?;
        Ok((image.into_linear(), stats))
    }

    /// Renders the listed `rows` over the columns `cols` into an image of
    /// `format`.
    fn render_job_live(
        &self,
        rows: &[u32],
        cols: (u32, u32),
        progress: &(dyn Fn(u64, u64) + Sync),
        cancel: &AtomicBool,
        live: Option<&LiveImage>,
        format: PixelFormat,
    ) -> Result<(ImageBuf, RenderStats), Cancelled> {
        let start = Instant::now();
        let job = Job {
            camera: &self.camera,
            width: self.width,
            height: self.height,
            rows,
            cols,
            spp: self.spp,
            sampler: self.plan.sampler,
            filter: &self.filter,
            progress,
            cancel,
            done: AtomicU64::new(0),
            pool: &self.pool,
            live,
            format,
        };
        let out = with_accel!(&self.accel, |a| job.run_plan(a, &self.data, &self.plan))?;
        Ok((
            out.image,
            RenderStats {
                plan: self.plan.clone(),
                build_time: self.build_time,
                render_time: start.elapsed(),
                rays: out.rays,
                pixels_hit: out.pixels_hit,
                grid: self.grid_stats.clone(),
            },
        ))
    }

    /// The render passes of `window`, row by row (see
    /// [`Renderer::render_aovs`]).
    pub(crate) fn aov_rows(&self, aovs: &[crate::Aov], window: PixelRect) -> Vec<Vec<Vec<f32>>> {
        with_accel!(&self.accel, |a| crate::aov::rows(
            a,
            &self.data,
            &self.camera,
            &self.pool,
            self.height,
            aovs,
            window
        ))
    }

    /// Traces only the camera rays (closest hit, one per pixel through its
    /// centre, no shading) and counts the pixels that hit something. This is
    /// the benchmark's "pixels hit", and timing it against
    /// [`Renderer::render`] splits frame time into traversal and shading.
    #[must_use]
    pub fn count_camera_hits(&self) -> u64 {
        let all = self.all_rows();
        let job = Job {
            camera: &self.camera,
            width: self.width,
            height: self.height,
            rows: &all,
            cols: (0, self.width),
            spp: 1,
            sampler: self.plan.sampler,
            filter: &self.filter,
            progress: &|_, _| {},
            cancel: &AtomicBool::new(false),
            done: AtomicU64::new(0),
            pool: &self.pool,
            live: None,
            format: PixelFormat::Linear,
        };
        let res = with_accel!(&self.accel, |a| job.run::<_, HitOnly, false>(a, &self.data));
        res.map_or(0, |o| o.pixels_hit)
    }
}

/// Renders a scene with the given options: [`Renderer::new`] then
/// [`Renderer::render`] with no progress report and no cancellation.
///
/// # Errors
/// A [`SceneError`] when the scene is invalid.
pub fn render(
    scene: &Scene,
    options: &RenderOptions,
) -> Result<(Framebuffer, RenderStats), SceneError> {
    let r = Renderer::new(scene, options)?;
    let never = AtomicBool::new(false);
    // The flag is never raised, so the render cannot be cancelled.
    let out = r.render(&|_, _| {}, &never);
    Ok(out.unwrap_or_else(|Cancelled| unreachable!("nothing raises the cancel flag")))
}

/// An integrator that only finds the closest hit (for
/// [`Renderer::count_camera_hits`]).
struct HitOnly;

impl Integrator for HitOnly {
    const BATCH: bool = false;

    #[inline]
    fn li<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        _: u32,
        _: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let hit = tr.closest(ray, Real::INFINITY, &mut ts.scratch).is_some();
        Li {
            color: Rgb::ZERO,
            t: 0.0,
            hit,
        }
    }

    fn shade<A>(
        _: &Tracer<'_, A>,
        _: &Ray,
        hit: Option<&Shading>,
        _: u32,
        _: &mut SampleStream,
        _: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        Li {
            color: Rgb::ZERO,
            t: 0.0,
            hit: hit.is_some(),
        }
    }
}

struct TileOut {
    pixels: Vec<Rgb>,
    rays: RayCounts,
    hits: u64,
}

struct Output {
    image: ImageBuf,
    rays: RayCounts,
    pixels_hit: u64,
}

/// One render: what every tile needs to know.
struct Job<'a> {
    camera: &'a CameraModel,
    width: u32,
    height: u32,
    /// The image rows to render (row 0 at the top), in output order.
    rows: &'a [u32],
    /// The image columns to render, `x0..x1`.
    cols: (u32, u32),
    spp: u32,
    sampler: SamplerKind,
    filter: &'a FilterTable,
    progress: &'a (dyn Fn(u64, u64) + Sync),
    cancel: &'a AtomicBool,
    done: AtomicU64,
    pool: &'a Pool,
    /// Filled as tiles finish, when the caller watches the render.
    live: Option<&'a LiveImage>,
    /// How the image keeps its pixels.
    format: PixelFormat,
}

impl Job<'_> {
    /// Picks the specialised render loop for the plan, once: each effect is a
    /// const parameter, so the loop of a scene without shadows contains no
    /// shadow code at all. A new effect adds one more `pick` step.
    fn run_plan<A>(
        &self,
        accel: &A,
        data: &SceneData,
        plan: &EffectPlan,
    ) -> Result<Output, Cancelled>
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        if plan.integrator == IntegratorKind::Path {
            return self.pick_jitter::<A, PathTracer>(accel, data, plan);
        }
        match (plan.shadows, plan.light_sampling) {
            (false, false) => self.pick_occlusion::<A, false, false>(accel, data, plan),
            (true, false) => self.pick_occlusion::<A, true, false>(accel, data, plan),
            (false, true) => self.pick_occlusion::<A, false, true>(accel, data, plan),
            (true, true) => self.pick_occlusion::<A, true, true>(accel, data, plan),
        }
    }

    fn pick_occlusion<A, const SHADOWS: bool, const AREA: bool>(
        &self,
        accel: &A,
        data: &SceneData,
        plan: &EffectPlan,
    ) -> Result<Output, Cancelled>
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        if plan.ambient_occlusion {
            self.pick_secondary::<A, SHADOWS, AREA, true>(accel, data, plan)
        } else {
            self.pick_secondary::<A, SHADOWS, AREA, false>(accel, data, plan)
        }
    }

    fn pick_secondary<A, const SHADOWS: bool, const AREA: bool, const AO: bool>(
        &self,
        accel: &A,
        data: &SceneData,
        plan: &EffectPlan,
    ) -> Result<Output, Cancelled>
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        // Refraction always comes with (Fresnel) reflection, and glossy
        // rays only come with reflection.
        match (plan.reflection, plan.refraction, plan.glossy) {
            (false, false, _) => self
                .pick_jitter::<A, Whitted<SHADOWS, false, false, AREA, false, AO>>(
                    accel, data, plan,
                ),
            (true, false, false) => self
                .pick_jitter::<A, Whitted<SHADOWS, true, false, AREA, false, AO>>(
                    accel, data, plan,
                ),
            (true, false, true) => self
                .pick_jitter::<A, Whitted<SHADOWS, true, false, AREA, true, AO>>(accel, data, plan),
            (_, true, false) => self
                .pick_jitter::<A, Whitted<SHADOWS, true, true, AREA, false, AO>>(accel, data, plan),
            (_, true, true) => self
                .pick_jitter::<A, Whitted<SHADOWS, true, true, AREA, true, AO>>(accel, data, plan),
        }
    }

    fn pick_jitter<A, I>(
        &self,
        accel: &A,
        data: &SceneData,
        plan: &EffectPlan,
    ) -> Result<Output, Cancelled>
    where
        A: Accelerator,
        A::Prim: Surface,
        I: Integrator,
    {
        if plan.jitter {
            self.run::<A, I, true>(accel, data)
        } else {
            self.run::<A, I, false>(accel, data)
        }
    }

    /// Renders every tile (in parallel when the pool has threads) and
    /// assembles the image of the listed rows. Per-tile ray counts are
    /// summed in tile order.
    fn run<A, I, const JITTER: bool>(
        &self,
        accel: &A,
        data: &SceneData,
    ) -> Result<Output, Cancelled>
    where
        A: Accelerator,
        A::Prim: Surface,
        I: Integrator,
    {
        let tr = Tracer { accel, data };
        let tiles = tiles(self.rows.len(), self.cols);
        let out_width = self.cols.1 - self.cols.0;
        let total = u64::from(out_width) * self.rows.len() as u64;
        let height = u32::try_from(self.rows.len()).expect("rows fit an image");
        let rect = |t: &Tile| PixelRect {
            x0: t.x0 - self.cols.0,
            y0: t.k0 as u32,
            x1: t.x1 - self.cols.0,
            y1: t.k1 as u32,
        };
        if let Some(live) = self.live {
            live.start(out_width, height, tiles.iter().map(rect).collect());
        }
        let indexed: Vec<(usize, Tile)> = tiles.into_iter().enumerate().collect();
        // Each tile goes into the image as soon as it is done, so the
        // finished tiles never all wait beside the image.
        let image = Mutex::new(ImageBuf::new(out_width, height, self.format));
        let one = |ts: &mut ThreadState<A::Scratch>, &(index, tile): &(usize, Tile)| {
            if self.cancel.load(Ordering::Relaxed) {
                return None;
            }
            let out = self.tile::<A, I, JITTER>(&tr, tile, ts);
            if let Some(live) = self.live {
                live.finish_tile(index, &out.pixels, out.rays.total());
            }
            let w = (tile.x1 - tile.x0) as usize;
            let mut img = image.lock().unwrap_or_else(PoisonError::into_inner);
            for (row, k) in (tile.k0..tile.k1).enumerate() {
                let start = k * out_width as usize + (tile.x0 - self.cols.0) as usize;
                img.put(start, &out.pixels[row * w..(row + 1) * w]);
            }
            drop(img);
            let n = out.pixels.len() as u64;
            let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
            (self.progress)(done, total);
            Some((out.rays, out.hits))
        };
        let new_state = || ThreadState {
            scratch: accel.scratch(),
            counts: RayCounts::default(),
        };
        let outs = self.pool.map_init(&indexed, new_state, one);
        if self.cancel.load(Ordering::Relaxed) || outs.iter().any(Option::is_none) {
            return Err(Cancelled);
        }
        let mut rays = RayCounts::default();
        let mut pixels_hit = 0;
        for (r, hits) in outs.into_iter().flatten() {
            rays += r;
            pixels_hit += hits;
        }
        Ok(Output {
            image: image.into_inner().unwrap_or_else(PoisonError::into_inner),
            rays,
            pixels_hit,
        })
    }

    /// One tile. Pixel `(x, y)` of the image (row 0 at the top) is Suffern's
    /// pixel `(c, r) = (x, height − 1 − y)` (row 0 at the bottom).
    #[inline(never)]
    fn tile<A, I, const JITTER: bool>(
        &self,
        tr: &Tracer<'_, A>,
        tile: Tile,
        ts: &mut ThreadState<A::Scratch>,
    ) -> TileOut
    where
        A: Accelerator,
        A::Prim: Surface,
        I: Integrator,
    {
        ts.counts = RayCounts::default();
        let mut pixels = Vec::with_capacity((tile.x1 - tile.x0) as usize * (tile.k1 - tile.k0));
        let mut hits = 0;
        // A thin lens draws a point of the aperture from each sample's
        // stream; pinhole cameras (the plan's `depth_of_field` off) keep
        // the batched loop and draw nothing.
        let lens = self.camera.has_lens();
        let samples = PixelSamples::new(self.sampler, self.spp);
        // The stream of the unsampled loops (one sample at the pixel centre).
        let one_sample = PixelSamples::new(self.sampler, 1);
        for &y in &self.rows[tile.k0..tile.k1] {
            debug_assert!(y < self.height);
            let r = self.height - 1 - y;
            if JITTER || I::SAMPLED || lens {
                for x in tile.x0..tile.x1 {
                    let index = u64::from(y) * u64::from(self.width) + u64::from(x);
                    let px = samples.at(index);
                    let mut sum = Rgb::ZERO;
                    let mut weights = 0.0f32;
                    let mut hit = false;
                    for s in 0..self.spp {
                        let mut stream = px.stream(s);
                        let u = stream.next_2d();
                        // At 1 spp the sample goes through the pixel centre.
                        let (jx, jy, w) = if JITTER {
                            self.filter.sample(u)
                        } else {
                            (0.5, 0.5, 1.0)
                        };
                        let ray = if lens {
                            self.camera.lens_ray(x, r, jx, jy, stream.next_2d())
                        } else {
                            self.camera.ray(x, r, jx, jy)
                        };
                        ts.counts.camera += 1;
                        let li = I::li(tr, &ray, 0, &mut stream, ts);
                        sum += li.color * w;
                        weights += w;
                        hit |= li.hit;
                    }
                    pixels.push(if weights > 0.0 {
                        sum / weights
                    } else {
                        Rgb::ZERO
                    });
                    hits += u64::from(hit);
                }
            } else if I::BATCH {
                // One row of the tile in three passes: trace every camera
                // ray, gather the hits' shading data, shade. Gathering in a
                // tight loop lets the cache misses on per-primitive data
                // (colours of a million spheres) overlap instead of queueing.
                const N: usize = TILE as usize;
                let n = (tile.x1 - tile.x0) as usize;
                let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); N];
                let mut found: [Option<Found>; N] = [None; N];
                for k in 0..n {
                    rays[k] = self.camera.ray(tile.x0 + k as u32, r, 0.5, 0.5);
                    found[k] = tr.closest(&rays[k], Real::INFINITY, &mut ts.scratch);
                    tr.prefetch(found[k]);
                }
                ts.counts.camera += n as u64;
                let shading: [Option<Shading>; N] =
                    std::array::from_fn(|k| found[k].map(|f| tr.shading(&rays[k], f)));
                let mut stream = one_sample.stream(0);
                for k in 0..n {
                    let li = I::shade(tr, &rays[k], shading[k].as_ref(), 0, &mut stream, ts);
                    pixels.push(li.color);
                    hits += u64::from(li.hit);
                }
            } else {
                let mut stream = one_sample.stream(0);
                for x in tile.x0..tile.x1 {
                    let ray = self.camera.ray(x, r, 0.5, 0.5);
                    ts.counts.camera += 1;
                    let li = I::li(tr, &ray, 0, &mut stream, ts);
                    pixels.push(li.color);
                    hits += u64::from(li.hit);
                }
            }
        }
        TileOut {
            pixels,
            rays: ts.counts,
            hits,
        }
    }
}
