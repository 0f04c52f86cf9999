//! `cargo xtask scenes`: the scene corpus beside Embree. For each scene of
//! [`crate::corpus`] and each of its ray sets: the build time, one-thread
//! rays per second, cells and primitive tests per ray and bytes of the
//! flat grid, the hierarchy of nested grids, `auto` (what the CLI and the
//! renderer use by default), the exhaustive baseline (small scenes) and
//! Embree through `../shared/peers/embree/embree_rays.c`, measured in the
//! same run, Embree between the grids on each ray set. Writes
//! `docs/scenes.md` and `docs/scenes.svg`.

use crate::corpus::{self, CorpusScene, Entry, Prims, Query};
use crate::peer::{self, Peer, PeerRun};
use crate::scenes_report::{self, Cell, Report, Row};
use crate::util;
use gridrt_grid::{
    Accelerator, Exhaustive, Grid, GridConfig, Primitive, QueryCounters, Real, HIERARCHY_MIN_REFS,
};
use std::path::PathBuf;
use std::time::Instant;

#[repr(C)]
struct Timespec {
    sec: i64,
    nsec: i64,
}

extern "C" {
    fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
}

/// Linux `CLOCK_THREAD_CPUTIME_ID`.
pub const THREAD_CPU: i32 = 3;
/// Linux `CLOCK_PROCESS_CPUTIME_ID`.
pub const PROCESS_CPU: i32 = 2;

/// CPU seconds of the calling thread (`CLOCK_THREAD_CPUTIME_ID`):
/// other processes on a shared machine do not inflate them. The grids are
/// built and traced on this thread alone, and the peer is compiled to time
/// itself the same way ([`crate::peer`]).
///
/// `clock` is [`THREAD_CPU`] or [`PROCESS_CPU`].
///
/// # Panics
/// When the clock cannot be read (not Linux).
pub fn cpu_s(clock: i32) -> f64 {
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: a valid clock id and a valid out-pointer.
    let ok = unsafe { clock_gettime(clock, &mut ts) } == 0;
    assert!(ok, "the thread CPU clock cannot be read");
    ts.sec as f64 + 1e-9 * ts.nsec as f64
}

/// Options of `cargo xtask scenes`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Only these scenes (comma-separated names as in docs/scenes.md).
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// Camera image size in pixels (Suffern's scenes keep his 400×400).
    #[arg(long, default_value_t = 320)]
    width: u32,
    /// Camera image height in pixels.
    #[arg(long, default_value_t = 240)]
    height: u32,
    /// Repetitions of each timing; the best is reported (as the peer does).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    runs: u32,
    /// Ray–primitive tests one timing may make; past it an evenly spread
    /// subset of the rays is traced and the figure marked "est.".
    #[arg(long, default_value_t = 3e8)]
    budget: f64,
    /// Scenes with at most this many primitives also get the exhaustive
    /// baseline.
    #[arg(long, default_value_t = 10_000)]
    exhaustive_max: usize,
    /// Leave Embree out.
    #[arg(long)]
    no_embree: bool,
    /// The folder holding `scenes/` and `peers/` (default: `../shared`
    /// beside the repository).
    #[arg(long, value_name = "DIR")]
    shared: Option<PathBuf>,
    /// Directory for scenes.md and scenes.svg (default: docs/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// The accelerators measured, in report order.
pub const ACCELS: [&str; 4] = ["grid", "hierarchy", "auto", "exhaustive"];

/// The grid configuration of each grid column, built on one thread.
fn config(name: &str) -> GridConfig {
    let mut c = GridConfig {
        parallel_build: false,
        ..GridConfig::default()
    };
    match name {
        "grid" => c.auto = false,
        "hierarchy" => {
            c.auto = false;
            c.nest_min_refs = HIERARCHY_MIN_REFS;
        }
        _ => {}
    }
    c
}

/// An accelerator of one column.
enum Acc<P: Primitive> {
    Grid(Box<Grid<P>>),
    Exhaustive(Exhaustive<P>),
}

impl<P: Primitive> Acc<P> {
    fn trace(&self, rays: &[Query]) -> u64 {
        match self {
            Acc::Grid(g) => hits(&**g, rays),
            Acc::Exhaustive(e) => hits(e, rays),
        }
    }

    fn count(&self, rays: &[Query]) -> QueryCounters {
        let mut c = QueryCounters::default();
        match self {
            Acc::Grid(g) => {
                let mut s = g.scratch();
                for q in rays {
                    g.closest_hit_counted(&q.ray, q.t_min, Real::INFINITY, &mut s, &mut c);
                }
            }
            Acc::Exhaustive(e) => {
                for q in rays {
                    e.closest_hit_counted(&q.ray, q.t_min, Real::INFINITY, &mut c);
                }
            }
        }
        c
    }
}

fn hits<A: Accelerator>(a: &A, rays: &[Query]) -> u64 {
    let mut s = a.scratch();
    rays.iter()
        .filter(|q| {
            a.closest_hit(&q.ray, q.t_min, Real::INFINITY, &mut s)
                .is_some()
        })
        .count() as u64
}

/// Builds one column's accelerator `runs` times (best time kept).
fn build<P: Primitive<Shared = ()> + Clone + Send>(
    prims: &[P],
    name: &str,
    runs: u32,
) -> (Acc<P>, f64, usize, &'static str) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..runs.min(3) {
        let v = prims.to_vec();
        let t = cpu_s(THREAD_CPU);
        let a = if name == "exhaustive" {
            Acc::Exhaustive(Exhaustive::new(v))
        } else {
            Acc::Grid(Box::new(Grid::build(v, &config(name))))
        };
        best = best.min(cpu_s(THREAD_CPU) - t);
        last = Some(a);
    }
    let Some(a) = last else {
        unreachable!("runs is at least 1")
    };
    let (bytes, chose) = match &a {
        Acc::Grid(g) => (
            g.stats().bytes,
            if g.stats().nested_cells > 0 {
                "hierarchy"
            } else {
                "grid"
            },
        ),
        Acc::Exhaustive(_) => (0, "exhaustive"),
    };
    (a, best, bytes, chose)
}

/// One column's timing on one ray set: the rays it traces (all, or an
/// evenly spread subset when the estimated tests exceed the budget) and
/// its best time so far.
struct Timing {
    sub: Vec<Query>,
    estimated: bool,
    best: f64,
    hits: u64,
}

impl Timing {
    fn new<P: Primitive>(a: &Acc<P>, rays: &[Query], budget: f64) -> Self {
        let mut stride = 1;
        if !rays.is_empty() {
            let probe: Vec<Query> = rays.iter().step_by(97).copied().collect();
            let est = a.count(&probe).tests_per_ray() * rays.len() as f64;
            stride = (est / budget).ceil().max(1.0) as usize;
        }
        Self {
            sub: rays.iter().step_by(stride).copied().collect(),
            estimated: stride > 1,
            best: f64::INFINITY,
            hits: 0,
        }
    }

    /// Traces the rays once, keeping the best time.
    fn run<P: Primitive>(&mut self, a: &Acc<P>) {
        if self.sub.is_empty() {
            return;
        }
        let t = cpu_s(THREAD_CPU);
        self.hits = a.trace(&self.sub);
        self.best = self.best.min(cpu_s(THREAD_CPU) - t);
    }

    fn cell<P: Primitive>(&self, a: &Acc<P>) -> Cell {
        if self.sub.is_empty() {
            return Cell::default();
        }
        let c = a.count(&self.sub);
        Cell {
            mrays: self.sub.len() as f64 / self.best.max(1e-9) * 1e-6,
            cells: c.cells_per_ray(),
            tests: c.tests_per_ray(),
            hits: self.hits,
            rays: self.sub.len() as u64,
            estimated: self.estimated,
            ..Cell::default()
        }
    }
}

/// Runs the task.
///
/// # Errors
/// When an output cannot be written.
pub fn run(args: &Args) -> crate::Outcome {
    let root = util::root();
    let shared = args
        .shared
        .clone()
        .unwrap_or_else(|| root.join("../shared"));
    let work = util::target_dir().join("scenes");
    let mut notes = Vec::new();
    let mut peer = if args.no_embree {
        notes.push("Embree left out (`--no-embree`).".to_string());
        None
    } else {
        match Peer::build(&shared, &work) {
            Ok(p) => Some(p),
            Err(e) => {
                notes.push(format!("Embree left out: {e}."));
                None
            }
        }
    };
    let mut rows = Vec::new();
    let mut scenes = Vec::new();
    let started = Instant::now();
    for e in corpus::entries(&root, &shared) {
        if !args.only.is_empty() && !args.only.iter().any(|o| o == e.name) {
            continue;
        }
        if e.shared && !shared.join("scenes").is_dir() {
            notes.push(format!(
                "{} skipped: {} is absent.",
                e.name,
                shared.join("scenes").display()
            ));
            continue;
        }
        eprintln!("scenes: {} ...", e.name);
        let scene = match corpus::load(&e, &root, args.width, args.height) {
            Ok(s) => s,
            Err(msg) => {
                notes.push(format!("{} skipped: {msg}", e.name));
                continue;
            }
        };
        scenes.push((scene.name, scene.about.clone(), scene.prims.len()));
        let new_rows = measure_scene(&e, &scene, args, peer.as_mut(), &work, &mut notes)?;
        for r in &new_rows {
            eprintln!("  {}", scenes_report::summary(r));
        }
        rows.extend(new_rows);
    }
    let close_up = if args.only.is_empty() || args.only.iter().any(|o| o == "stadium") {
        crate::scenes_render::close_up(&shared)
    } else {
        None
    };
    let report = Report {
        machine: util::machine(),
        embree: peer.as_ref().map(|p| p.version.clone()),
        width: args.width,
        height: args.height,
        runs: args.runs,
        scenes,
        rows,
        notes,
        close_up,
        seconds: started.elapsed().as_secs_f64(),
    };
    let dir = args.out.clone().unwrap_or_else(|| root.join("docs"));
    scenes_report::write(&report, &dir)?;
    eprintln!(
        "scenes: wrote {} and {} in {:.0} s",
        util::show(&dir.join("scenes.md")),
        util::show(&dir.join("scenes.svg")),
        report.seconds
    );
    Ok(true)
}

fn measure_scene(
    e: &Entry,
    scene: &CorpusScene,
    args: &Args,
    peer: Option<&mut Peer>,
    work: &std::path::Path,
    notes: &mut Vec<String>,
) -> Result<Vec<Row>, Box<dyn std::error::Error>> {
    // Embree's inputs: the triangles as an OBJ, each ray set as a CSV.
    let mut peer = match (&scene.prims, peer) {
        (Prims::Tris(t), Some(p)) => {
            let obj = work.join(format!("{}.obj", e.name));
            peer::write_obj(&obj, t)?;
            Some((p, obj))
        }
        (Prims::Spheres(_), Some(_)) => {
            notes.push(format!(
                "{}: no Embree column (embree_rays reads triangles; `cargo xtask speedup-table` with the `embree` feature compares Embree's spheres).",
                e.name
            ));
            None
        }
        _ => None,
    };
    let rows = match &scene.prims {
        Prims::Tris(_) => {
            let tris = scene.prims.triangles();
            measure_prims(&tris, scene, args, &mut peer, work)?
        }
        Prims::Spheres(s) => measure_prims(s, scene, args, &mut peer, work)?,
    };
    Ok(rows)
}

fn measure_prims<P: Primitive<Shared = ()> + Clone + Send>(
    prims: &[P],
    scene: &CorpusScene,
    args: &Args,
    peer: &mut Option<(&mut Peer, PathBuf)>,
    work: &std::path::Path,
) -> Result<Vec<Row>, Box<dyn std::error::Error>> {
    let mut accs = Vec::new();
    for name in ACCELS {
        if name == "exhaustive" && prims.len() > args.exhaustive_max {
            continue;
        }
        let (a, build_s, bytes, chose) = build(prims, name, args.runs);
        accs.push((name, a, build_s, bytes, chose));
    }
    let mut rows = Vec::new();
    for set in &scene.sets {
        let mut row = Row {
            scene: scene.name.to_string(),
            kind: set.kind.to_string(),
            about: set.about.clone(),
            rays: set.rays.len(),
            ..Row::default()
        };
        // The columns are timed in rounds, one pass each, and Embree runs
        // half-way through: a slow spell of a shared machine then slows
        // every column alike instead of one.
        let mut timings: Vec<Timing> = accs
            .iter()
            .map(|(_, a, ..)| Timing::new(a, &set.rays, args.budget))
            .collect();
        for round in 0..args.runs {
            if round == args.runs / 2 {
                row.embree = run_peer(peer, &set.rays, scene, set.kind, args.runs, work);
            }
            for ((_, a, ..), t) in accs.iter().zip(&mut timings) {
                t.run(a);
            }
        }
        for ((name, a, build_s, bytes, chose), t) in accs.iter().zip(&timings) {
            let mut c = t.cell(a);
            c.build_s = *build_s;
            c.bytes = *bytes;
            c.chose = chose;
            row.cells.push(((*name).to_string(), c));
        }
        rows.push(row);
    }
    Ok(rows)
}

fn run_peer(
    peer: &mut Option<(&mut Peer, PathBuf)>,
    rays: &[Query],
    scene: &CorpusScene,
    kind: &str,
    runs: u32,
    work: &std::path::Path,
) -> Option<Result<PeerRun, String>> {
    let (p, obj) = peer.as_mut()?;
    let csv = work.join(format!("{}-{}.csv", scene.name, kind.replace(' ', "-")));
    if let Err(e) = peer::write_rays(&csv, rays) {
        return Some(Err(e.to_string()));
    }
    Some(p.run(obj, &csv, runs))
}
