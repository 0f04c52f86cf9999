//! `cargo xtask speedup-table`: Suffern's Table 22.1 regenerated, grid
//! against exhaustive, with the book's numbers beside ours.
//!
//! Per N: the grid with the book's m = 2 and with gridrt's default
//! configuration, each on 1 thread (as the book) and on all cores,
//! generate + build + render repeated `--runs` times (median); a
//! closest-hit-only pass for the "trace only" time; a counting pass for
//! primitive tests per ray; the exhaustive renderer on every row (small N,
//! or `--full`) or on evenly spread rows of the image, extrapolated ("est."). Every image
//! must equal the first grid image bit for bit, and the pixels hit must
//! equal the Embree peer's counts.

use crate::bitdiff::bitwise_diff;
use crate::measure;
use crate::table::{self, GridCell, Row, Secs, Table};
use crate::util;
use gridrt_grid::GridConfig;
use gridrt_tracer::suffern::{self, DEFAULT_SEED, REFERENCE_PIXELS_HIT, RESOLUTION};
use gridrt_tracer::Framebuffer;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

/// Ray–sphere tests one exhaustive measurement may make before it renders
/// only some rows and extrapolates: one whole frame at N = 10,000 (a few
/// seconds on one core), 40 rows at 100,000, 4 at 1,000,000. With the
/// defaults the whole table takes a few minutes on 2 cores.
pub const DEFAULT_BUDGET: f64 = 1.6e9;

/// The fewest rows an estimated exhaustive measurement renders.
pub const MIN_ROWS: usize = 4;

/// Options of `cargo xtask speedup-table`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Sphere counts, comma-separated (1000, 1e6 and 1_000_000 are all fine).
    #[arg(long, value_delimiter = ',', value_parser = parse_count,
          default_value = "10,100,1000,10000,100000,1000000")]
    sizes: Vec<usize>,
    /// Threads of the multi-threaded columns (default: all cores; 1 leaves
    /// them out).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    threads: Option<u32>,
    /// Repetitions of each measurement; the median is reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    runs: u32,
    /// Directory for speedup-table.md and speedup.svg.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Measure the exhaustive renderer on every row at every N (hours at
    /// 1,000,000 spheres) instead of extrapolating from some rows.
    #[arg(long)]
    full: bool,
    /// Ray–sphere tests an exhaustive measurement may make before it
    /// switches to a subset of rows.
    #[arg(long, value_name = "TESTS", default_value_t = DEFAULT_BUDGET, value_parser = parse_budget)]
    exhaustive_budget: f64,
}

/// Parses a sphere count: `1000`, `1_000`, `1e6`.
pub fn parse_count(s: &str) -> Result<usize, String> {
    let t = s.trim().replace('_', "");
    let n = if t.contains(['e', 'E']) {
        let x: f64 = t.parse().map_err(|_| format!("`{s}` is not a number"))?;
        if !(x.fract() == 0.0 && (1.0..=1e8).contains(&x)) {
            return Err(format!("`{s}` is not a whole number from 1 to 100,000,000"));
        }
        x as usize
    } else {
        t.parse::<usize>()
            .map_err(|_| format!("`{s}` is not a whole number"))?
    };
    if !(1..=100_000_000).contains(&n) {
        return Err(format!("{n} spheres: choose 1 to 100,000,000"));
    }
    Ok(n)
}

fn parse_budget(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .replace('_', "")
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err("the budget must be > 0".to_string())
    }
}

fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

fn median_secs(xs: &[Duration]) -> f64 {
    secs(util::median(xs.to_vec()))
}

/// The grid configurations: the book's m = 2, then gridrt's default (one
/// entry when they are the same).
pub fn configs() -> Vec<(String, GridConfig)> {
    let default = GridConfig::default();
    let book = GridConfig { m: 2.0, ..default };
    if book == default {
        vec![("m = 2 (book, default)".to_string(), default)]
    } else {
        vec![
            ("m = 2 (book)".to_string(), book),
            (format!("default (m = {})", default.m), default),
        ]
    }
}

/// A progress bar on stderr when it is a terminal; hidden otherwise.
fn bar(len: u64, n: usize) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(len);
    let style =
        ProgressStyle::with_template("{prefix:>12} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
            .map(|s| s.progress_chars("=> "))
            .unwrap_or_else(|_| ProgressStyle::default_bar());
    pb.set_style(style);
    pb.set_prefix(format!("N = {}", table::count(n as u64)));
    pb
}

/// Runs the whole table; `Ok(false)` when a row failed its checks.
pub fn run(args: &Args) -> crate::Outcome {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let multi = args.threads.map_or(cores, |t| t as usize);
    let threads: Vec<usize> = if multi > 1 { vec![1, multi] } else { vec![1] };
    let runs = args.runs as usize;
    let configs = configs();
    let out_dir = match &args.out {
        Some(d) => d.clone(),
        None => util::root().join("docs"),
    };
    let mut command = if cfg!(feature = "embree") {
        "cargo run --release -p xtask --features embree -- speedup-table".to_string()
    } else {
        "cargo xtask speedup-table".to_string()
    };
    for a in std::env::args().skip(2) {
        command.push(' ');
        command.push_str(&a);
    }
    let mut table = Table {
        machine: util::machine(),
        date: table::today(),
        threads: threads.clone(),
        runs,
        configs: configs
            .iter()
            .map(|(l, c)| (l.clone(), gridrt_bbox::math::to_f64(c.m)))
            .collect(),
        resolution: RESOLUTION,
        rows: Vec::new(),
        embree: None,
        command,
    };
    eprintln!(
        "speedup-table: N = {:?}, threads {:?}, {runs} runs, grids: {}; {}",
        args.sizes,
        threads,
        configs
            .iter()
            .map(|c| c.0.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        table.machine
    );
    #[cfg(feature = "embree")]
    let device = crate::embree::Device::new().map_err(|e| format!("embree: {e}"))?;
    #[cfg(feature = "embree")]
    let embree: Option<&EmbreeDevice> = {
        table.embree = Some(crate::embree::version());
        Some(&device)
    };
    #[cfg(not(feature = "embree"))]
    let embree: Option<&EmbreeDevice> = None;
    for &n in &args.sizes {
        let row = measure_row(n, args, &threads, &configs, embree)?;
        eprintln!("{}", summary(&row, &table));
        table.rows.push(row);
        // Write after every row, so a long run shows progress and an
        // interrupted one keeps what it measured.
        write_outputs(&table, &out_dir)?;
    }
    let md = out_dir.join("speedup-table.md");
    eprintln!(
        "wrote {} and {}",
        util::show(&md),
        util::show(&out_dir.join("speedup.svg"))
    );
    let failed: Vec<&Row> = table
        .rows
        .iter()
        .filter(|r| !r.problems.is_empty())
        .collect();
    if failed.is_empty() {
        return Ok(true);
    }
    eprintln!("FAILED:");
    for r in failed {
        eprintln!("  N = {}: {}", r.n, r.problems.join("; "));
    }
    Ok(false)
}

fn write_outputs(table: &Table, dir: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    let md = dir.join("speedup-table.md");
    util::write_atomic(&md, table::markdown(table).as_bytes())
        .map_err(|e| format!("{}: {e}", md.display()))?;
    crate::plot::speedup_plot(&dir.join("speedup.svg"), table)?;
    Ok(())
}

/// One line per finished row.
fn summary(r: &Row, t: &Table) -> String {
    let d = t.default_config();
    let g = r.grids.get(d);
    let g1 = g.and_then(|g| g.total.first()).copied().unwrap_or(f64::NAN);
    let e1 = r
        .exhaustive
        .total
        .first()
        .copied()
        .unwrap_or(Secs::measured(f64::NAN));
    format!(
        "N = {:>9}: grid {} s, exhaustive {} s, speed-up {}, tests/ray {} vs {}, gen+build+render {} s{}{}",
        table::count(r.n as u64),
        table::num(g1),
        table::secs_cell(e1),
        table::ratio_cell(e1, Secs::measured(g1)),
        g.map_or("—".into(), |g| table::num(g.tests_per_ray)),
        table::num(r.exhaustive.tests_per_ray),
        g.and_then(|g| g.end_to_end.first()).map_or("—".into(), |&v| table::num(v)),
        t.threads
            .get(1)
            .and_then(|&th| g.and_then(|g| g.end_to_end.get(1)).map(|v| format!(" ({} s on {th} threads)", table::num(*v))))
            .unwrap_or_default(),
        if r.problems.is_empty() { String::new() } else { format!("  PROBLEM: {}", r.problems.join("; ")) }
    )
}

/// Compares an image with the row's first grid image.
fn check_image(
    row: &mut Row,
    first: &Option<Framebuffer>,
    image: &Framebuffer,
    rows: Option<&[u32]>,
    what: &str,
) {
    if let Some(f) = first {
        match bitwise_diff(f, image, rows) {
            Ok(None) => {}
            Ok(Some(d)) => row
                .problems
                .push(format!("{what} differs from the first grid image: {d}")),
            Err(e) => row.problems.push(format!("{what}: {e}")),
        }
    }
}

#[cfg(feature = "embree")]
type EmbreeDevice = crate::embree::Device;
#[cfg(not(feature = "embree"))]
type EmbreeDevice = ();

fn measure_row(
    n: usize,
    args: &Args,
    threads: &[usize],
    configs: &[(String, GridConfig)],
    embree: Option<&EmbreeDevice>,
) -> Result<Row, Box<dyn std::error::Error>> {
    let runs = args.runs as usize;
    let height = RESOLUTION;
    let ex_rows = if args.full {
        height as usize
    } else {
        table::rows_for_budget(n, RESOLUTION, height, args.exhaustive_budget, MIN_ROWS)
    };
    let subset = (ex_rows < height as usize).then(|| table::spread_rows(ex_rows, height));
    let steps =
        (threads.len() * configs.len() * runs + runs + configs.len() + 1 + threads.len() * runs)
            as u64
            + u64::from(embree.is_some());
    let pb = bar(steps, n);
    let mut row = Row {
        n,
        reference_hit: REFERENCE_PIXELS_HIT.iter().find(|r| r.0 == n).map(|r| r.1),
        ..Row::default()
    };
    let mut first: Option<Framebuffer> = None;
    let mut generate = Vec::new();

    // Grid: every configuration, every thread count, `runs` times.
    for (label, config) in configs {
        let mut cell = GridCell::default();
        for &th in threads {
            pb.set_message(format!(
                "grid {label}, {th} thread{}",
                if th == 1 { "" } else { "s" }
            ));
            let (mut b, mut r, mut tot, mut e2e) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for _ in 0..runs {
                let g = measure::grid_run(n, *config, th)?;
                generate.push(g.generate);
                b.push(g.build);
                r.push(g.render);
                tot.push(g.build + g.render);
                e2e.push(g.generate + g.build + g.render);
                if first.is_none() {
                    row.pixels_hit = g.pixels_hit;
                    let s = &g.stats;
                    (cell.dims, cell.cells, cell.occupied, cell.references) =
                        (s.dims, s.cells, s.occupied_cells, s.references);
                    first = Some(g.image);
                } else {
                    if cell.cells == 0 {
                        let s = &g.stats;
                        (cell.dims, cell.cells, cell.occupied, cell.references) =
                            (s.dims, s.cells, s.occupied_cells, s.references);
                    }
                    check_image(
                        &mut row,
                        &first,
                        &g.image,
                        None,
                        &format!("grid {label} on {th} threads"),
                    );
                }
                pb.inc(1);
            }
            cell.build.push(median_secs(&b));
            cell.render.push(median_secs(&r));
            cell.total.push(median_secs(&tot));
            cell.end_to_end.push(median_secs(&e2e));
        }
        row.grids.push(cell);
    }
    row.generate = median_secs(&generate);

    // Trace only (closest hit, no shading), default configuration, 1 thread.
    let d = configs.len() - 1;
    pb.set_message("trace only");
    let (times, hits) = measure::trace_only(n, configs[d].1, runs)?;
    pb.inc(runs as u64);
    row.grids[d].trace_only = median_secs(&times);
    if hits != row.pixels_hit {
        row.problems.push(format!(
            "the trace-only pass hits {hits} pixels, the render {}",
            row.pixels_hit
        ));
    }

    // Primitive tests per ray.
    pb.set_message("counting tests");
    let spheres = suffern::sphere_set(n, DEFAULT_SEED).spheres;
    let mut prims = Vec::new();
    for (i, (label, config)) in configs.iter().enumerate() {
        let c = measure::count_grid(spheres.clone(), config, RESOLUTION);
        row.grids[i].tests_per_ray = c.counters.tests_per_ray();
        row.grids[i].cells_per_ray = c.counters.cells_per_ray();
        if c.pixels_hit() != row.pixels_hit {
            row.problems.push(format!(
                "the counting pass ({label}) hits {} pixels, the render {}",
                c.pixels_hit(),
                row.pixels_hit
            ));
        }
        prims = c.prims;
        pb.inc(1);
    }
    let samples = (2e8 / n as f64).clamp(16.0, 4096.0) as u32;
    row.exhaustive.tests_per_ray =
        measure::count_exhaustive(spheres.clone(), RESOLUTION, samples).tests_per_ray();
    pb.inc(1);

    // Exhaustive, the same renderer without a grid.
    row.exhaustive.rows = ex_rows;
    for &th in threads {
        pb.set_message(format!(
            "exhaustive, {th} thread{}, {ex_rows} of {height} rows",
            if th == 1 { "" } else { "s" }
        ));
        let (mut b, mut r) = (Vec::new(), Vec::new());
        for _ in 0..runs {
            let e = measure::exhaustive_run(n, th, subset.as_deref())?;
            b.push(e.build);
            r.push(e.render);
            check_image(
                &mut row,
                &first,
                &e.image,
                subset.as_deref(),
                &format!("exhaustive on {th} threads"),
            );
            pb.inc(1);
        }
        let render = median_secs(&r);
        let total = median_secs(&b) + table::extrapolate(render, ex_rows, height);
        row.exhaustive.total.push(Secs {
            value: total,
            estimated: subset.is_some(),
        });
    }

    // Embree on the same spheres.
    #[cfg(feature = "embree")]
    if let Some(dev) = embree {
        pb.set_message("embree");
        let e = crate::embree::measure(dev, &spheres, RESOLUTION, runs)?;
        let differing = e.prims.iter().zip(&prims).filter(|(a, b)| a != b).count();
        row.embree = Some(table::EmbreeCell {
            build: e.build,
            trace: e.trace,
            pixels_hit: e.pixels_hit,
            differing,
        });
        pb.inc(1);
    }
    #[cfg(not(feature = "embree"))]
    let _ = (embree, &prims);

    if let Some(h) = row.reference_hit {
        if h != row.pixels_hit {
            row.problems.push(format!(
                "{} pixels hit, the Embree peer's reference is {}",
                row.pixels_hit, h
            ));
        }
    }
    pb.finish_and_clear();
    Ok(row)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_parse_in_several_spellings() {
        assert_eq!(parse_count("1000"), Ok(1000));
        assert_eq!(parse_count("1_000_000"), Ok(1_000_000));
        assert_eq!(parse_count("1e6"), Ok(1_000_000));
        assert_eq!(parse_count(" 10 "), Ok(10));
        assert!(parse_count("0").is_err());
        assert!(parse_count("1.5e0").is_err());
        assert!(parse_count("ten").is_err());
        assert!(parse_count("1e9").is_err());
    }

    /// `fixtures/scenes/speedup.ron` is the benchmark scene of this table
    /// (its N = 1,000 row), object for object.
    #[test]
    fn the_fixture_scene_is_the_benchmark() {
        let path = util::root().join("fixtures/scenes/speedup.ron");
        let loaded = crate::util::load_scene(&path).unwrap();
        assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
        assert!(
            loaded.scene == suffern::scene(1000),
            "speedup.ron differs from suffern::scene(1000)"
        );
    }

    #[test]
    fn the_book_configuration_comes_first_and_the_default_last() {
        let c = configs();
        assert_eq!(c[0].1.m, 2.0);
        assert_eq!(c.last().map(|c| c.1), Some(GridConfig::default()));
    }
}
