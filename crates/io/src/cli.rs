//! The `gridrt` command line: argument definitions (clap) and the commands.
//! `src/main.rs` only parses, calls [`run`] and turns an error into one line.

pub use crate::cli_access::AccessArgs;
use crate::cli_counts::SceneCounts;
pub use crate::cli_effects::{EffectArgs, SamplerArg};
use crate::cli_outputs::{
    pass_paths, render_part, render_passes, render_watched, save_interrupted, stage_rendered,
    Rendered,
};
pub use crate::cli_outputs::{AovArgs, AovList, DiffArgs, MergeArgs, PartArgs, PartialArgs};
pub use crate::cli_robustness::{
    IntersectArgs, OffsetArgs, SlabArg, TriangleTestArg, TrianglesArg,
};
use crate::cli_stats::{self, speed_text, Perf};
pub use crate::cli_view::ViewArgs;
use crate::error::{escape_control, Error, Result};
use crate::image_out::{check_image_path, check_output_dir, stage};
use crate::model_scene::apply_overrides;
use crate::sandbox::Sandbox;
use crate::scene::{default_scene, load_scene_in, LoadedScene, DEFAULT_SCENE_NAME};
use clap::{Args, Parser, Subcommand, ValueEnum};
use gridrt_bbox::{Aabb, Real, Vec3};
use gridrt_grid::{CellStorage, GridConfig, GridStats, QueryCounters, HIERARCHY_MIN_REFS};
use gridrt_tracer::{
    AccelKind, AovImage, Light, Projection, RenderOptions, RenderStats, Renderer, TriangleStorage,
};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// A ray tracer built on a regular grid (after Suffern's "Ray Tracing from
/// the Ground Up").
///
/// With no subcommand, `gridrt [SCENE] [OPTIONS]` renders like `gridrt render`.
#[derive(Debug, Parser)]
#[command(name = "gridrt", version, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// What to do (default: render).
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Render options when no subcommand is given.
    #[command(flatten)]
    pub render: RenderArgs,
}

/// The subcommands.
// Parsed once per run: the size of `RenderArgs` costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene (or the built-in default scene) to an image.
    Render(RenderArgs),
    /// Print scene and grid statistics without rendering.
    Info(InfoArgs),
    /// Answer closest-hit queries for rays read from a CSV file.
    Rays(RaysArgs),
    /// Assemble the parts of a frame (`render --tile` or `--crop`) into
    /// the full image.
    Merge(MergeArgs),
    /// Compare two images (PNG or EXR): pixels differing, mean error, RMSE,
    /// largest difference; exit code 1 when they differ.
    Diff(DiffArgs),
}

/// Options of `gridrt render`.
#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    /// Scene file (.ron) or model (.obj, .ply, .gltf, .glb); the built-in default
    /// scene when absent.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Output image: .png (8-bit sRGB) or .exr (linear float).
    #[arg(short, long, value_name = "FILE", default_value = "out.png")]
    pub output: PathBuf,
    /// Samples per pixel (overrides the scene), 1 to 65536.
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Image width in pixels (overrides the scene; alone, the height keeps
    /// the aspect ratio).
    #[arg(long, value_name = "W")]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene; alone, the width keeps
    /// the aspect ratio).
    #[arg(long, value_name = "H")]
    pub height: Option<u32>,
    /// Also write the statistics as JSON to this file.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Print only errors and warnings, no summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// A part of the frame (crop window or tile).
    #[command(flatten)]
    pub part: PartArgs,
    /// Render passes.
    #[command(flatten)]
    pub aov: AovArgs,
    /// Partial images.
    #[command(flatten)]
    pub partial: PartialArgs,
    /// Sampler and filter.
    #[command(flatten)]
    pub effects: EffectArgs,
    /// Accelerator options.
    #[command(flatten)]
    pub accel: AccelArgs,
    /// Intersection tests and the grid's optional work.
    #[command(flatten)]
    pub intersect: IntersectArgs,
    /// How secondary rays leave surfaces.
    #[command(flatten)]
    pub offset: OffsetArgs,
    /// File access and budgets.
    #[command(flatten)]
    pub access: AccessArgs,
    /// Camera and depth overrides.
    #[command(flatten)]
    pub view: ViewArgs,
}

/// Options of `gridrt info`.
#[derive(Debug, Clone, Args)]
pub struct InfoArgs {
    /// Scene file (.ron) or model (.obj, .ply, .gltf, .glb); the built-in default
    /// scene when absent.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Accelerator options.
    #[command(flatten)]
    pub accel: AccelArgs,
    /// File access and budgets.
    #[command(flatten)]
    pub access: AccessArgs,
}

/// Options of `gridrt rays`.
#[derive(Debug, Clone, Args)]
pub struct RaysArgs {
    /// The mesh (.obj, .ply, .gltf, .glb); triangle indices follow its order.
    #[arg(value_name = "MESH")]
    pub mesh: PathBuf,
    /// Rays, one `ox,oy,oz,dx,dy,dz[,tmin,tmax]` per line.
    #[arg(value_name = "RAYS.csv")]
    pub rays: PathBuf,
    /// Write the answers to this file instead of standard output.
    #[arg(short, long, value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
    /// Worker threads for the build and the queries (default: all cores);
    /// the answers do not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Also write the statistics as JSON to this file: the accelerator
    /// built, build and trace seconds, rays, hits, Mrays/s, cells and
    /// tests per ray, bytes.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Accelerator options.
    #[command(flatten)]
    pub accel: AccelArgs,
    /// Intersection tests and the grid's optional work.
    #[command(flatten)]
    pub intersect: IntersectArgs,
    /// File access and budgets.
    #[command(flatten)]
    pub access: AccessArgs,
}

/// Accelerator choice, shared by the commands.
#[derive(Debug, Clone, Copy, Args)]
pub struct AccelArgs {
    /// The accelerator.
    #[arg(long, value_enum, default_value_t = Accel::Auto)]
    pub accel: Accel,
    /// The grid multiplier m (about m³ cells per primitive), in (0, 1000];
    /// default: the grid crate's tuned value.
    #[arg(long = "grid-m", value_name = "M", value_parser = parse_grid_m)]
    pub grid_m: Option<f64>,
    /// Give every cell with at least N references a nested grid of its own
    /// (0, the default: none). Helps a detailed model in a large, mostly
    /// empty scene; try with a small --grid-m such as 0.3.
    #[arg(long = "grid-nest", value_name = "N")]
    pub grid_nest: Option<u32>,
    /// The nested grids' multiplier m, in (0, 1000] (default: the same as
    /// --grid-m). A coarse outer grid with finer nested grids can pay, such
    /// as --grid-m 0.3 --grid-nest 8 --grid-nest-m 0.7.
    #[arg(long = "grid-nest-m", value_name = "M", value_parser = parse_grid_m)]
    pub grid_nest_m: Option<f64>,
    /// The most memory, in MiB, the grid's index (cells, references and
    /// nested grids) may take; reaching it stops subdividing, never fails.
    /// Default: 8 times the primitives' own size, and at least 4 MiB.
    #[arg(long = "grid-memory", value_name = "MIB", value_parser = parse_grid_memory)]
    pub grid_memory: Option<usize>,
    /// Test the references of the flat grid's crowded cells one by one
    /// instead of keeping a box per group of four (GridConfig::cell_groups):
    /// a smaller index, more tests per ray; to compare speed and memory.
    #[arg(long = "no-cell-groups")]
    pub no_cell_groups: bool,
    /// Bake every mesh into world space, even one placed many times
    /// (by default such a mesh is stored once with a grid of its own and
    /// each placement is one primitive): to compare speed and memory.
    #[arg(long = "no-instancing")]
    pub no_instancing: bool,
}

/// `--accel` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Accel {
    /// The flat grid or the hierarchy of nested grids, chosen from the
    /// scene's statistics at build time (the default; see the grid
    /// crate's README for the rule).
    Auto,
    /// The flat regular grid, a dense table with one offset per cell
    /// (`dense-grid` is the same); nested grids only with --grid-nest.
    #[value(alias = "dense-grid")]
    Grid,
    /// The regular grid with nested grids in every cell of at least 48
    /// references (--grid-nest N sets another threshold), whatever the
    /// scene's statistics.
    Hierarchy,
    /// Regular grid, only occupied cells, in a hash table keyed by Morton
    /// code (the lecture's; smaller when most cells are empty).
    HashedGrid,
    /// Test every primitive (the baseline).
    Exhaustive,
}

impl Accel {
    fn kind(self) -> AccelKind {
        match self {
            Self::Auto | Self::Grid | Self::Hierarchy | Self::HashedGrid => AccelKind::Grid,
            Self::Exhaustive => AccelKind::Exhaustive,
        }
    }

    /// The value's name on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Grid => "grid",
            Self::Hierarchy => "hierarchy",
            Self::HashedGrid => "hashed-grid",
            Self::Exhaustive => "exhaustive",
        }
    }
}

fn parse_grid_m(s: &str) -> std::result::Result<f64, String> {
    let m: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if m.is_finite() && m > 0.0 && m <= 1000.0 {
        Ok(m)
    } else {
        Err(format!("{m} is out of range: use a number in (0, 1000]"))
    }
}

/// `--grid-memory MIB` in bytes: a whole number of MiB from 1 to 1 TiB.
fn parse_grid_memory(s: &str) -> std::result::Result<usize, String> {
    let mib: usize = s
        .parse()
        .map_err(|_| format!("`{s}` is not a whole number of MiB"))?;
    if (1..=1 << 20).contains(&mib) {
        Ok(mib << 20)
    } else {
        Err(format!("{mib} MiB is out of range: use 1 to 1048576"))
    }
}

impl AccelArgs {
    pub(crate) fn grid_config(&self) -> GridConfig {
        let mut g = GridConfig {
            memory_budget: self.grid_memory,
            cell_groups: !self.no_cell_groups,
            ..GridConfig::default()
        };
        if let Some(m) = self.grid_m {
            g.m = m as Real;
        }
        if let Some(n) = self.grid_nest {
            g.nest_min_refs = n;
        }
        g.nest_m = self.grid_nest_m.map(|m| m as Real);
        match self.accel {
            Accel::Grid | Accel::HashedGrid => g.auto = false,
            Accel::Hierarchy if g.nest_min_refs == 0 => g.nest_min_refs = HIERARCHY_MIN_REFS,
            _ => {}
        }
        g.storage = match self.accel {
            Accel::HashedGrid => CellStorage::Hashed,
            _ => CellStorage::Dense,
        };
        g
    }

    fn options(&self, threads: Option<u32>) -> RenderOptions {
        RenderOptions {
            accel: self.accel.kind(),
            grid: self.grid_config(),
            threads: threads.map(|t| t as usize),
            instancing: !self.no_instancing,
            ..RenderOptions::default()
        }
    }
}

/// Runs a parsed command line. Output goes to `out` (the summary, `rays`
/// answers without `-o`), warnings to standard error. A render cannot be
/// cancelled; see [`run_with_cancel`].
///
/// # Errors
/// Any [`Error`]; the binary prints it as `error: …` and exits with 1.
pub fn run(cli: Cli, out: &mut dyn Write) -> Result<()> {
    run_with_cancel(cli, out, &AtomicBool::new(false))
}

/// [`run`], with a flag that cancels a render when it becomes true (the
/// binary raises it on Ctrl-C). A cancelled render writes nothing: neither
/// the image nor the `--stats` file, and a file already at the output path
/// is left as it was.
///
/// # Errors
/// [`Error::Cancelled`] when the flag was raised before the image was
/// written; any other [`Error`] as [`run`].
pub fn run_with_cancel(cli: Cli, out: &mut dyn Write, cancel: &AtomicBool) -> Result<()> {
    match cli.command {
        None => render(&cli.render, out, cancel),
        Some(Command::Render(a)) => render(&a, out, cancel),
        Some(Command::Info(a)) => info(&a, out),
        Some(Command::Rays(a)) => crate::cli_rays::rays(&a, out),
        Some(Command::Merge(a)) => crate::cli_outputs::merge(&a, out),
        Some(Command::Diff(a)) => crate::cli_outputs::diff(&a, out),
    }
}

impl Cli {
    /// True when the command renders an image (`render`, or no subcommand):
    /// the one command that [`run_with_cancel`] can cancel.
    #[must_use]
    pub fn renders(&self) -> bool {
        matches!(self.command, None | Some(Command::Render(_)))
    }
}

/// [`Error::Cancelled`] when `cancel` is raised.
fn check_cancel(cancel: &AtomicBool) -> Result<()> {
    if cancel.load(Ordering::SeqCst) {
        Err(Error::Cancelled)
    } else {
        Ok(())
    }
}

/// Loads the scene argument, or the built-in scene; returns the sandbox it
/// was read under (which knows the files read).
fn load(scene: Option<&Path>, access: &AccessArgs) -> Result<(LoadedScene, Sandbox)> {
    let sandbox = access.sandbox(scene)?;
    let loaded = match scene {
        Some(p) => load_scene_in(p, &sandbox)?,
        None => default_scene()?,
    };
    Ok((loaded, sandbox))
}

/// Refuses outputs that would destroy an input or each other: two outputs
/// naming the same file, or an output naming a file that was read.
pub(crate) fn check_outputs(outputs: &[(&str, &Path)], inputs: &[PathBuf]) -> Result<()> {
    for (k, (flag, out)) in outputs.iter().enumerate() {
        for (other_flag, other) in &outputs[..k] {
            if same_file(out, other) {
                return Err(Error::output(
                    out,
                    format!("{flag} and {other_flag} name the same file: give each its own"),
                ));
            }
        }
        if let Some(input) = inputs.iter().find(|i| same_file(out, i)) {
            return Err(Error::output(
                out,
                format!(
                    "{flag} names an input of this run ({}): writing it would destroy the input; choose another output path",
                    input.display()
                ),
            ));
        }
    }
    Ok(())
}

/// True when `a` and `b` are the same file: the same device and inode when
/// both exist, else the same path after resolving links.
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return ma.dev() == mb.dev() && ma.ino() == mb.ino();
    }
    crate::sandbox::canonical(a) == crate::sandbox::canonical(b)
}

/// `871307 primitives, triangles indexed`.
fn primitives_text(n: usize, storage: Option<TriangleStorage>) -> String {
    match storage {
        Some(s) => format!("{n} primitives, triangles {}", cli_stats::storage_name(s)),
        None => format!("{n} primitives"),
    }
}

/// Prints warnings, control characters escaped.
pub(crate) fn warn(warnings: &[String]) {
    let mut e = std::io::stderr().lock();
    for w in warnings {
        let _ = writeln!(e, "warning: {}", escape_control(w));
    }
}

/// Writing to the summary stream failed (a closed pipe): not worth an error.
fn put(out: &mut dyn Write, text: &str) {
    let _ = out.write_all(text.as_bytes());
}

fn render(a: &RenderArgs, out: &mut dyn Write, cancel: &AtomicBool) -> Result<()> {
    // Everything that can be checked before rendering is checked first.
    a.intersect.check()?;
    let format = check_image_path(&a.output)?;
    if a.part.spec().is_some() && format != crate::ImageFormat::Exr {
        return Err(Error::output(
            &a.output,
            "a crop or tile is written as .exr, which records its place in the full image; \
             `gridrt merge` turns the parts into a .png or .exr",
        ));
    }
    let pass_files = pass_paths(&a.output, a.aov.aov.as_ref());
    if let Some(s) = &a.stats {
        check_output_dir(s)?;
    }
    let mut outputs = vec![("-o", a.output.as_path())];
    outputs.extend(pass_files.iter().map(|p| ("--aov", p.as_path())));
    if let Some(s) = &a.stats {
        outputs.push(("--stats", s.as_path()));
    }
    check_outputs(&outputs, &a.scene.iter().cloned().collect::<Vec<_>>())?;
    let (mut loaded, sandbox) = load(a.scene.as_deref(), &a.access)?;
    check_outputs(&outputs, &sandbox.files_read())?;
    // Loading and the grid build are not interruptible; a Ctrl-C during
    // them is honoured as soon as they end.
    check_cancel(cancel)?;
    warn(&loaded.warnings);
    apply_overrides(&mut loaded.scene.settings, a.width, a.height, a.spp)?;
    a.view.apply(&mut loaded)?;
    a.effects.apply(&mut loaded.scene.settings);
    let options = a.intersect.options(a.accel.options(a.threads), &a.offset);
    // The renderer keeps what it needs of the scene's objects and lets the
    // rest go before its grid takes memory: what the report and a part's
    // file say of them is taken first.
    let counts = SceneCounts::of(&loaded.scene);
    let fingerprint = a.part.spec().map(|_| crate::fingerprint(&loaded.scene));
    let renderer =
        Renderer::new_taking_objects(&mut loaded.scene, &options).map_err(|e| Error::Render {
            path: loaded.source.clone(),
            msg: e.to_string(),
        })?;

    let bar = progress_bar();
    // Pixels are kept as they come only for partial images.
    let live = if a.partial.write_partial.is_some() || a.partial.save_on_interrupt {
        gridrt_tracer::LiveImage::new()
    } else {
        gridrt_tracer::LiveImage::rays_only()
    };
    let started = Instant::now();
    let progress = |done: u64, total: u64| {
        if let Some(b) = &bar {
            b.set_length(total);
            b.set_position(done);
            b.set_message(speed_text(live.rays(), started.elapsed().as_secs_f64()));
        }
    };
    // A PNG with no image before the end is kept as 8-bit sRGB while it
    // renders: a quarter of the linear image's memory.
    let png8 = format == crate::ImageFormat::Png
        && a.partial.write_partial.is_none()
        && !a.partial.save_on_interrupt;
    let result = match a.part.spec() {
        None if png8 => renderer
            .render_srgb8(&progress, cancel, &live)
            .map(|(img, s)| (Rendered::Srgb8(img), s)),
        None => render_watched(&renderer, &a.output, a.partial, &progress, cancel, &live)
            .map(|(img, s)| (Rendered::Full(img), s)),
        Some(spec) => render_part(&renderer, spec, &progress, cancel)?,
    };
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let (rendered, stats) = match result {
        Ok(r) => r,
        Err(_) if a.partial.save_on_interrupt && a.part.spec().is_none() => {
            WRITING.store(true, Ordering::SeqCst);
            let e = save_interrupted(&a.output, &live);
            WRITING.store(false, Ordering::SeqCst);
            return Err(e);
        }
        Err(_) => return Err(Error::Cancelled),
    };
    // A Ctrl-C after the last tile still means "stop, write nothing".
    check_cancel(cancel)?;
    // The work per ray is counted in a pass of its own, after the timed
    // render, and only for the statistics file.
    let counters = a
        .stats
        .as_ref()
        .map(|_| cli_stats::camera_counters(&renderer));
    let passes = render_passes(&renderer, &rendered, a.aov.aov.as_ref());
    let report = Report {
        loaded: &loaded,
        counts: &counts,
        accel: a.accel,
        robust: a.intersect.label(Some(&a.offset)),
        threads: a.threads,
        primitives: renderer.primitive_count(),
        storage: renderer.triangle_storage(),
        stats: &stats,
        counters,
        output: &a.output,
    };
    let size = renderer.size();
    // The accelerator and the scene's arrays go before the image is
    // encoded, which would otherwise add to the peak.
    drop(renderer);
    // Both outputs are written to temporary files first; they are renamed
    // into place only when both are complete, so a failure keeps both old
    // files byte for byte.
    WRITING.store(true, Ordering::SeqCst);
    let image = (size, &rendered, passes.as_slice(), fingerprint.as_deref());
    let written = write_outputs(a, &report, image, cancel);
    WRITING.store(false, Ordering::SeqCst);
    written?;
    if a.quiet {
        return Ok(());
    }
    put(out, &report.text());
    for p in &pass_files {
        put(out, &format!("pass        {}\n", p.display()));
    }
    Ok(())
}

/// True while `render` writes its outputs: the binary's second Ctrl-C
/// waits for it rather than exiting, so no temporary file is left.
pub static WRITING: AtomicBool = AtomicBool::new(false);

/// Writes the image (of `size` pixels, with its passes and, for a part,
/// the scene's fingerprint) and the statistics: both to temporary files
/// first, renamed into place only when both are complete, so a failure (or
/// a Ctrl-C) keeps both old files byte for byte.
fn write_outputs(
    a: &RenderArgs,
    report: &Report,
    (size, rendered, passes, fingerprint): ((u32, u32), &Rendered, &[AovImage], Option<&str>),
    cancel: &AtomicBool,
) -> Result<()> {
    let image_files = stage_rendered(&a.output, size, rendered, passes, fingerprint)?;
    let stats_file = match &a.stats {
        Some(p) => {
            let json = report
                .json()
                .and_then(|v| serde_json::to_string_pretty(&v))
                .map_err(|e| Error::output(p, format!("cannot encode statistics: {e}")))?;
            Some(stage(p, |f| {
                f.write_all(json.as_bytes())?;
                f.write_all(b"\n")
            })?)
        }
        None => None,
    };
    check_cancel(cancel)?;
    for f in image_files {
        f.commit()?;
    }
    if let Some(f) = stats_file {
        f.commit()?;
    }
    Ok(())
}

/// A progress bar on standard error when it is a terminal, else nothing.
fn progress_bar() -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(0);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "rendering [{bar:40.cyan/blue}] {percent:>3}%  {elapsed_precise} (eta {eta})  {msg}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    Some(bar)
}

/// What a render reports: the text summary and the JSON statistics.
struct Report<'a> {
    loaded: &'a LoadedScene,
    counts: &'a SceneCounts,
    accel: AccelArgs,
    /// The robustness switches turned off (empty: the defaults).
    robust: String,
    threads: Option<u32>,
    primitives: usize,
    storage: Option<TriangleStorage>,
    stats: &'a RenderStats,
    /// Work per camera ray (with `--stats` only).
    counters: Option<QueryCounters>,
    output: &'a Path,
}

/// The JSON statistics (`--stats`): these fields, the render's statistics
/// (with the rays by kind as `rays_by_kind`) and [`Perf`]'s.
#[derive(serde::Serialize)]
struct StatsJson<'a> {
    scene: String,
    output: String,
    width: u32,
    height: u32,
    spp: u32,
    grid_m: f64,
    /// The robustness switches that differ from the defaults, comma
    /// separated (empty: all robust defaults).
    robustness: &'a str,
    threads: Option<u32>,
    objects: usize,
    triangles: usize,
    /// How the grid stored them: `copies` or `indexed` (`null` for scenes
    /// of other shapes).
    triangle_storage: Option<&'static str>,
    primitives: usize,
    rays_total: u64,
    mrays_per_sec: f64,
    /// `plan`, `build_time`, `render_time` (seconds), `rays` (renamed
    /// `rays_by_kind`), `pixels_hit`, `grid`.
    #[serde(flatten)]
    stats: &'a RenderStats,
    grid_occupancy: Option<f64>,
}

impl Report<'_> {
    fn json(&self) -> serde_json::Result<serde_json::Value> {
        let mut v = serde_json::to_value(self.base_json())?;
        let perf = serde_json::to_value(self.perf())?;
        if let (Some(o), serde_json::Value::Object(p)) = (v.as_object_mut(), perf) {
            if let Some(by_kind) = o.remove("rays") {
                o.insert("rays_by_kind".to_string(), by_kind);
            }
            o.extend(p);
        }
        Ok(v)
    }

    fn perf(&self) -> Perf {
        let st = self.stats;
        let c = self.counters.unwrap_or_default();
        let trace_s = st.render_time.as_secs_f64();
        Perf {
            accel: cli_stats::chosen(self.accel.accel, st.grid.as_ref()),
            accel_requested: self.accel.accel.name(),
            build_s: st.build_time.as_secs_f64(),
            trace_s,
            rays: st.rays.total(),
            hits: st.pixels_hit,
            mrays_per_s: cli_stats::mrays(st.rays.total(), trace_s),
            cells_per_ray: c.cells_per_ray(),
            tests_per_ray: c.tests_per_ray(),
            bytes: st.grid.as_ref().map_or(0, |g| g.bytes),
        }
    }

    fn base_json(&self) -> StatsJson<'_> {
        let s = &self.loaded.scene;
        StatsJson {
            scene: self.loaded.source.display().to_string(),
            output: self.output.display().to_string(),
            width: s.settings.width,
            height: s.settings.height,
            spp: s.settings.spp,
            grid_m: crate::model::r64(self.accel.grid_config().m),
            robustness: &self.robust,
            threads: self.threads,
            objects: self.counts.objects,
            triangles: self.counts.triangles,
            triangle_storage: self.storage.map(cli_stats::storage_name),
            primitives: self.primitives,
            rays_total: self.stats.rays.total(),
            mrays_per_sec: self.stats.mrays_per_sec(),
            stats: self.stats,
            grid_occupancy: self.stats.grid.as_ref().map(occupancy),
        }
    }

    fn text(&self) -> String {
        let s = &self.loaded.scene;
        let st = self.stats;
        let mut t = String::new();
        t += &format!(
            "scene       {} ({})\n",
            self.loaded.source.display(),
            self.counts.text
        );
        t += &format!(
            "image       {}×{}, {} spp\n",
            s.settings.width, s.settings.height, s.settings.spp
        );
        t += &format!("{}\n", st.plan);
        t += &format!(
            "accel       {} ({})\n",
            accel_label(&self.accel, st.grid.as_ref()),
            primitives_text(self.primitives, self.storage)
        );
        if !self.robust.is_empty() {
            t += &format!("robustness  off: {}\n", self.robust);
        }
        if let Some(g) = &st.grid {
            t += &grid_line(g);
        }
        t += &format!("build       {:.3} s\n", st.build_time.as_secs_f64());
        t += &format!("render      {:.3} s\n", st.render_time.as_secs_f64());
        t += &format!("rays        {}\n", st.rays);
        t += &format!(
            "speed       {}\n",
            speed_text(st.rays.total(), st.render_time.as_secs_f64())
        );
        t += &format!("wrote       {}\n", self.output.display());
        t
    }
}

/// The accelerator asked for and, for `auto`, what it chose.
pub(crate) fn accel_label(a: &AccelArgs, g: Option<&GridStats>) -> String {
    let built = cli_stats::chosen(a.accel, g);
    let nest = match g {
        Some(g) if g.nested_cells > 0 => format!(
            ", nested grids in cells of at least {} references, {} levels",
            g.nest_min_refs, g.nest_levels
        ),
        _ => String::new(),
    };
    match a.accel {
        Accel::Exhaustive => "exhaustive".to_string(),
        Accel::Auto => format!("auto: {built} (m = {}{nest})", a.grid_config().m),
        other => format!("{} (m = {}{nest})", other.name(), a.grid_config().m),
    }
}

fn occupancy(g: &GridStats) -> f64 {
    if g.cells == 0 {
        0.0
    } else {
        g.occupied_cells as f64 / g.cells as f64
    }
}

fn grid_line(g: &GridStats) -> String {
    // What the occupied cells hold besides their references.
    let mut kinds = String::new();
    if g.nested_cells > 0 {
        kinds += &format!(", {} with nested grids", g.nested_cells);
    }
    if g.grouped_cells > 0 {
        kinds += &format!(", {} with group boxes", g.grouped_cells);
    }
    // Primitives tested by every ray instead of through the cells.
    let outside = match g.unbounded_prims {
        0 => String::new(),
        1 => ", 1 primitive outside the cells".to_string(),
        n => format!(", {n} primitives outside the cells"),
    };
    format!(
        "grid        {}×{}×{} = {} cells, {} occupied ({:.1}%{kinds}), {} refs ({:.2} per occupied cell, max {}){outside}, {:.2} MiB\n",
        g.dims[0],
        g.dims[1],
        g.dims[2],
        g.cells,
        g.occupied_cells,
        100.0 * occupancy(g),
        g.references,
        g.mean_refs_per_occupied,
        g.max_refs_per_cell,
        g.bytes as f64 / (1024.0 * 1024.0)
    ) + &cli_stats::level_lines(g)
}

fn v(p: Vec3) -> String {
    format!("({}, {}, {})", p.x, p.y, p.z)
}

fn info(a: &InfoArgs, out: &mut dyn Write) -> Result<()> {
    let (loaded, _) = load(a.scene.as_deref(), &a.access)?;
    warn(&loaded.warnings);
    let s = &loaded.scene;
    let mut t = String::new();
    t += &format!(
        "scene       {}\n",
        a.scene.as_deref().map_or_else(
            || DEFAULT_SCENE_NAME.to_string(),
            |p| p.display().to_string()
        )
    );
    t += &format!(
        "image       {}×{}, {} spp, max depth {}\n",
        s.settings.width, s.settings.height, s.settings.spp, s.settings.max_depth
    );
    let proj = match s.camera.projection {
        Projection::Perspective { vfov_deg } => format!("perspective, vertical fov {vfov_deg}°"),
        Projection::ViewPlane {
            distance,
            pixel_size,
        } => format!("view plane at {distance}, pixel size {pixel_size}"),
        Projection::Orthographic { height } => format!("orthographic, height {height}"),
    };
    t += &format!(
        "camera      eye {}, look at {}, {proj}{}\n",
        v(s.camera.eye),
        v(s.camera.look_at),
        if loaded.framed_camera {
            " (placed to frame the scene)"
        } else {
            ""
        }
    );
    t += &format!("objects     {}\n", SceneCounts::of(s).text);
    let bounds = s
        .objects
        .iter()
        .fold(Aabb::EMPTY, |b, o| b.union(o.geometry.bounds()));
    if !bounds.is_empty() {
        t += &format!(
            "bounds      {} to {} (planes excluded)\n",
            v(bounds.min),
            v(bounds.max)
        );
    }
    t += &format!("materials   {}\n", s.materials.len());
    let [mut amb, mut pt, mut dir, mut spot, mut area, mut env] = [0; 6];
    for l in &s.lights {
        match l {
            Light::Ambient { .. } => amb += 1,
            Light::Point { .. } => pt += 1,
            Light::Directional { .. } => dir += 1,
            Light::Spot { .. } => spot += 1,
            Light::Rect { .. } | Light::Disk { .. } => area += 1,
            Light::Environment { .. } => env += 1,
        }
    }
    t += &format!(
        "lights      {amb} ambient, {pt} point, {dir} directional, {spot} spot, {area} area, {env} environment\n"
    );
    let renderer = Renderer::new(s, &a.accel.options(None)).map_err(|e| Error::Render {
        path: loaded.source.clone(),
        msg: e.to_string(),
    })?;
    t += &format!("{}\n", renderer.plan());
    t += &format!(
        "accel       {} ({})\n",
        accel_label(&a.accel, renderer.grid_stats()),
        primitives_text(renderer.primitive_count(), renderer.triangle_storage())
    );
    if let Some(g) = renderer.grid_stats() {
        t += &grid_line(g);
    }
    let inst = renderer.instancing();
    if inst.instances > 0 {
        t += &format!(
            "instances   {} placements of {} shared mesh{}, {:.2} MiB\n",
            inst.instances,
            inst.shared_meshes,
            if inst.shared_meshes == 1 { "" } else { "es" },
            inst.bytes as f64 / (1024.0 * 1024.0)
        );
    }
    t += &format!("build       {:.3} s\n", renderer.build_time().as_secs_f64());
    put(out, &t);
    Ok(())
}
