//! The speed-up table's data and its Markdown, with no measuring in it (so
//! it can be tested): the book's numbers, row subsets and extrapolation,
//! number formatting.

use std::fmt::Write as _;

/// One row of Suffern's Table 22.1 (400 × 400, 1 ray per pixel, no shadows,
/// a 450 MHz G3; seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BookRow {
    /// Spheres.
    pub n: usize,
    /// Render time with the grid.
    pub grid: f64,
    /// Render time without acceleration (`None`: "forget it!").
    pub exhaustive: Option<f64>,
    /// The book's speed-up factor (for 1,000,000 an estimate, "≈ 46,307").
    pub speedup: f64,
}

/// The book's table.
pub const BOOK: [BookRow; 6] = [
    BookRow {
        n: 10,
        grid: 1.5,
        exhaustive: Some(2.5),
        speedup: 1.6,
    },
    BookRow {
        n: 100,
        grid: 2.0,
        exhaustive: Some(16.0),
        speedup: 8.0,
    },
    BookRow {
        n: 1_000,
        grid: 2.7,
        exhaustive: Some(164.0),
        speedup: 61.0,
    },
    BookRow {
        n: 10_000,
        grid: 3.8,
        exhaustive: Some(2_041.0),
        speedup: 537.0,
    },
    BookRow {
        n: 100_000,
        grid: 4.7,
        exhaustive: Some(22_169.0),
        speedup: 4_717.0,
    },
    BookRow {
        n: 1_000_000,
        grid: 5.2,
        exhaustive: None,
        speedup: 46_307.0,
    },
];

/// The book's row for `n`, if it has one.
pub fn book(n: usize) -> Option<&'static BookRow> {
    BOOK.iter().find(|b| b.n == n)
}

/// `k` rows spread evenly over an image `height` rows high (y = 0 at the
/// top), ascending: the row in the middle of each of `k` equal strips, so
/// sky and spheres are sampled in proportion. `k` is capped at `height`.
pub fn spread_rows(k: usize, height: u32) -> Vec<u32> {
    let h = height as usize;
    let k = k.clamp(1, h.max(1));
    (0..k).map(|i| ((2 * i + 1) * h / (2 * k)) as u32).collect()
}

/// How many rows an exhaustive measurement renders so that it makes at most
/// `budget` ray–sphere tests (`width · rows · n`), but at least `min_rows`
/// and at most `height` (every row: no estimate).
pub fn rows_for_budget(n: usize, width: u32, height: u32, budget: f64, min_rows: usize) -> usize {
    let per_row = width as f64 * n.max(1) as f64;
    let rows = (budget / per_row).floor();
    // `as` saturates: an infinite budget gives usize::MAX, NaN gives 0.
    let rows = if rows > 0.0 { rows as usize } else { 0 };
    rows.max(min_rows).min(height as usize)
}

/// The whole frame's render time from the time of `rows` of `height` rows:
/// per-row cost times the row count. The exhaustive accelerator tests every
/// sphere for every ray, so each ray costs nearly the same; only shading
/// differs between hit and missed pixels, and evenly spread rows
/// ([`spread_rows`]) sample both in proportion.
pub fn extrapolate(seconds: f64, rows: usize, height: u32) -> f64 {
    if rows == 0 {
        return f64::NAN;
    }
    seconds * f64::from(height) / rows as f64
}

/// A time in seconds, measured or extrapolated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Secs {
    /// Seconds.
    pub value: f64,
    /// Extrapolated from a subset of rows.
    pub estimated: bool,
}

impl Secs {
    /// A measured time.
    pub fn measured(value: f64) -> Self {
        Self {
            value,
            estimated: false,
        }
    }
}

/// `x` with about three significant digits, and thousands separated by
/// commas from 1,000 up (`46,307`, `2,041`, `164`, `2.70`, `0.0123`).
pub fn num(x: f64) -> String {
    if !x.is_finite() {
        return "—".to_string();
    }
    if x.abs() >= 1000.0 {
        let mut digits = format!("{:.0}", x.abs());
        let mut out = String::new();
        while digits.len() > 3 {
            let tail = digits.split_off(digits.len() - 3);
            out = format!(",{tail}{out}");
        }
        format!("{}{digits}{out}", if x < 0.0 { "-" } else { "" })
    } else {
        crate::util::sig3(x)
    }
}

/// A time for a table cell: "2.70", "1,234 est.".
pub fn secs_cell(s: Secs) -> String {
    if s.estimated {
        format!("{} est.", num(s.value))
    } else {
        num(s.value)
    }
}

/// `slow / fast` as a cell, "est." when either is estimated.
pub fn ratio_cell(slow: Secs, fast: Secs) -> String {
    secs_cell(Secs {
        value: slow.value / fast.value,
        estimated: slow.estimated || fast.estimated,
    })
}

/// A count with thousands separated: `160000` → `160,000`, `10` → `10`.
pub fn count(x: u64) -> String {
    if x >= 1000 {
        num(x as f64)
    } else {
        x.to_string()
    }
}

/// One grid configuration's measurement at one N.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridCell {
    /// Build time per thread count (median; index as `Table::threads`).
    pub build: Vec<f64>,
    /// Render time per thread count (median).
    pub render: Vec<f64>,
    /// Build + render per thread count (median of the sums).
    pub total: Vec<f64>,
    /// Generation + build + render per thread count (median of the sums).
    pub end_to_end: Vec<f64>,
    /// Cells per axis.
    pub dims: [u32; 3],
    /// All cells.
    pub cells: u64,
    /// Cells holding at least one reference.
    pub occupied: u64,
    /// Primitive references.
    pub references: u64,
    /// Primitive tests per camera ray.
    pub tests_per_ray: f64,
    /// Cells visited per camera ray.
    pub cells_per_ray: f64,
    /// Tracing the camera rays only (closest hit, no shading), 1 thread.
    pub trace_only: f64,
}

/// The exhaustive measurement at one N, per thread count.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExhaustiveCell {
    /// Build (preparation) + render of the whole frame, per thread count;
    /// estimated when only some rows were rendered.
    pub total: Vec<Secs>,
    /// Rows rendered (= image height when measured in full).
    pub rows: usize,
    /// Primitive tests per camera ray.
    pub tests_per_ray: f64,
}

/// Embree's numbers at one N (the peer program's model: closest hit only).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EmbreeCell {
    /// BVH build (`rtcCommitScene`), median.
    pub build: f64,
    /// 160,000 `rtcIntersect1` calls on one thread, median.
    pub trace: f64,
    /// Pixels hit.
    pub pixels_hit: u64,
    /// Pixels whose hit sphere (or miss) differs from gridrt's.
    pub differing: usize,
}

/// One N.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Row {
    /// Spheres.
    pub n: usize,
    /// Generating the spheres, median.
    pub generate: f64,
    /// One entry per grid configuration (index as `Table::configs`).
    pub grids: Vec<GridCell>,
    /// The exhaustive baseline.
    pub exhaustive: ExhaustiveCell,
    /// Pixels hit by the camera rays.
    pub pixels_hit: u64,
    /// What the Embree peer reports for this N (LCG, seed 15).
    pub reference_hit: Option<u64>,
    /// Problems: image mismatches, pixel-hit mismatches (empty: fine).
    pub problems: Vec<String>,
    /// Embree, when built with the `embree` feature.
    pub embree: Option<EmbreeCell>,
}

/// A whole run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// `util::machine()`.
    pub machine: String,
    /// When (UTC date).
    pub date: String,
    /// Thread counts measured: `[1]` or `[1, T]`.
    pub threads: Vec<usize>,
    /// Repetitions per measurement.
    pub runs: usize,
    /// Grid configurations: label and m (the first is the book's m = 2).
    pub configs: Vec<(String, f64)>,
    /// Image side.
    pub resolution: u32,
    /// The rows.
    pub rows: Vec<Row>,
    /// Embree's version, when its columns are present.
    pub embree: Option<String>,
    /// The command line that made the table.
    pub command: String,
}

impl Table {
    /// The index of the default configuration (the last one).
    pub fn default_config(&self) -> usize {
        self.configs.len().saturating_sub(1)
    }
}

fn row_line(cells: &[String]) -> String {
    format!("| {} |\n", cells.join(" | "))
}

fn header(cells: &[&str]) -> String {
    let mut s = row_line(&cells.iter().map(|c| (*c).to_string()).collect::<Vec<_>>());
    s += &row_line(&cells.iter().map(|_| "---:".to_string()).collect::<Vec<_>>());
    s
}

/// The whole Markdown page.
pub fn markdown(t: &Table) -> String {
    let mut md = String::new();
    let d = t.default_config();
    let res = t.resolution;
    let rays = u64::from(res) * u64::from(res);
    let _ = writeln!(md, "# Suffern's speed-up table, regenerated\n");
    let _ = writeln!(
        md,
        "Generated by `{}` on {} ({}), {} run{} per measurement, median reported. \
         Do not edit: rerun the command.\n",
        t.command,
        t.machine,
        t.date,
        t.runs,
        if t.runs == 1 { "" } else { "s" }
    );
    let _ = writeln!(
        md,
        "The scene is the book's (*Ray Tracing from the Ground Up*, ch. 22, Table 22.1): N spheres \
         of total volume 0.1 with centres uniform in [−1, 1]³, {res} × {res} pixels, 1 ray per pixel, \
         no shadows, matte shading with an ambient and a directional light. The spheres come from \
         the portable LCG (seed 15) of `gridrt_tracer::suffern`, the same spheres as the Embree peer \
         (`shared/peers/embree`); the book used `rand()`. Times are wall-clock seconds: **grid** is \
         build + render (as the book's), **exhaustive** is the same renderer with \
         `AccelKind::Exhaustive` (every ray tests every sphere, same intersection and shading code). \
         *est.* marks an exhaustive time extrapolated from evenly spread rows of the image (`--full` \
         measures every row).\n"
    );

    // 1. The book beside us, one thread.
    let _ = writeln!(md, "## The book's table beside ours (1 thread)\n");
    let mut cols = vec![
        "N".to_string(),
        "book: grid".into(),
        "book: exhaustive".into(),
        "book: speed-up".into(),
    ];
    for (label, _) in &t.configs {
        cols.push(format!("grid {label}"));
    }
    cols.push("exhaustive".into());
    for (label, _) in &t.configs {
        cols.push(format!("speed-up {label}"));
    }
    cols.push("tests-per-ray ratio".into());
    md += &header(&cols.iter().map(String::as_str).collect::<Vec<_>>());
    for r in &t.rows {
        let b = book(r.n);
        let mut c = vec![count(r.n as u64)];
        c.push(b.map_or("—".into(), |b| num(b.grid)));
        c.push(b.map_or("—".into(), |b| {
            b.exhaustive.map_or("forget it!".into(), num)
        }));
        c.push(b.map_or("—".into(), |b| {
            if b.exhaustive.is_some() {
                num(b.speedup)
            } else {
                format!("≈ {}", num(b.speedup))
            }
        }));
        for g in &r.grids {
            c.push(g.total.first().map_or("—".into(), |&v| num(v)));
        }
        let ex = r.exhaustive.total.first().copied();
        c.push(ex.map_or("—".into(), secs_cell));
        for g in &r.grids {
            c.push(match (ex, g.total.first()) {
                (Some(e), Some(&v)) => ratio_cell(e, Secs::measured(v)),
                _ => "—".into(),
            });
        }
        c.push(tests_ratio(r, d));
        md += &row_line(&c);
    }
    md.push('\n');

    // 2. All cores.
    if t.threads.len() > 1 {
        let th = t.threads[1];
        let _ = writeln!(md, "## All cores ({th} threads)\n");
        let mut cols = vec!["N".to_string()];
        for (label, _) in &t.configs {
            cols.push(format!("grid {label}"));
        }
        cols.push("exhaustive".into());
        cols.push(format!("speed-up {}", t.configs[d].0));
        cols.push(format!("grid {} vs 1 thread", t.configs[d].0));
        md += &header(&cols.iter().map(String::as_str).collect::<Vec<_>>());
        for r in &t.rows {
            let mut c = vec![count(r.n as u64)];
            for g in &r.grids {
                c.push(g.total.get(1).map_or("—".into(), |&v| num(v)));
            }
            let ex = r.exhaustive.total.get(1).copied();
            c.push(ex.map_or("—".into(), secs_cell));
            let gd = r.grids.get(d).and_then(|g| g.total.get(1).copied());
            c.push(match (ex, gd) {
                (Some(e), Some(g)) => ratio_cell(e, Secs::measured(g)),
                _ => "—".into(),
            });
            let g1 = r.grids.get(d).and_then(|g| g.total.first().copied());
            c.push(match (g1, gd) {
                (Some(a), Some(b)) => format!("{}×", num(a / b)),
                _ => "—".into(),
            });
            md += &row_line(&c);
        }
        md.push('\n');
    }

    // 3. Where the time goes.
    let _ = writeln!(
        md,
        "## Where the grid's time goes (grid {}, milliseconds)\n",
        t.configs[d].0
    );
    let mut cols = vec!["N".to_string(), "generate".into()];
    for &th in &t.threads {
        let tl = if th == 1 {
            "1 thread".to_string()
        } else {
            format!("{th} threads")
        };
        cols.push(format!("build, {tl}"));
        cols.push(format!("render, {tl}"));
        cols.push(format!("generate + build + render, {tl}"));
    }
    cols.push("trace only, 1 thread".into());
    cols.push("pixels hit".into());
    cols.push("Embree peer".into());
    md += &header(&cols.iter().map(String::as_str).collect::<Vec<_>>());
    for r in &t.rows {
        let ms = |v: f64| num(1e3 * v);
        let mut c = vec![count(r.n as u64), ms(r.generate)];
        let g = r.grids.get(d);
        for i in 0..t.threads.len() {
            for v in [
                g.and_then(|g| g.build.get(i)),
                g.and_then(|g| g.render.get(i)),
                g.and_then(|g| g.end_to_end.get(i)),
            ] {
                c.push(v.map_or("—".into(), |&v| ms(v)));
            }
        }
        c.push(g.map_or("—".into(), |g| ms(g.trace_only)));
        c.push(count(r.pixels_hit));
        c.push(match r.reference_hit {
            Some(h) if h == r.pixels_hit => format!("{} ✓", count(h)),
            Some(h) => format!("**{} ✗**", count(h)),
            None => "—".into(),
        });
        md += &row_line(&c);
    }
    md.push('\n');

    // 4. Grid shape and tests per ray.
    let _ = writeln!(md, "## Grid cells and primitive tests per ray\n");
    let mut cols = vec!["N".to_string()];
    for (label, _) in &t.configs {
        cols.push(format!("cells {label}"));
        cols.push(format!("objects per cell {label}"));
        cols.push(format!("objects per occupied cell {label}"));
    }
    for (label, _) in &t.configs {
        cols.push(format!("tests/ray grid {label}"));
    }
    cols.push(format!("cells/ray grid {}", t.configs[d].0));
    cols.push("tests/ray exhaustive".into());
    cols.push(format!("tests ratio {}", t.configs[d].0));
    cols.push(format!("time ratio {}", t.configs[d].0));
    md += &header(&cols.iter().map(String::as_str).collect::<Vec<_>>());
    for r in &t.rows {
        let mut c = vec![count(r.n as u64)];
        for g in &r.grids {
            c.push(format!(
                "{}×{}×{} = {}",
                g.dims[0],
                g.dims[1],
                g.dims[2],
                count(g.cells)
            ));
            c.push(num(g.references as f64 / g.cells.max(1) as f64));
            c.push(num(g.references as f64 / g.occupied.max(1) as f64));
        }
        for g in &r.grids {
            c.push(num(g.tests_per_ray));
        }
        c.push(r.grids.get(d).map_or("—".into(), |g| num(g.cells_per_ray)));
        c.push(num(r.exhaustive.tests_per_ray));
        c.push(tests_ratio(r, d));
        c.push(
            match (
                r.exhaustive.total.first(),
                r.grids.get(d).and_then(|g| g.total.first()),
            ) {
                (Some(&e), Some(&g)) => ratio_cell(e, Secs::measured(g)),
                _ => "—".into(),
            },
        );
        md += &row_line(&c);
    }
    md.push('\n');

    // 5. Embree.
    if let Some(v) = &t.embree {
        let _ = writeln!(
            md,
            "## Embree {v} on the same spheres (1 thread, closest hit only)\n"
        );
        md += &header(&[
            "N",
            "Embree BVH build",
            "Embree trace",
            "Embree build + trace",
            "gridrt grid build",
            "gridrt trace only",
            "gridrt build + trace",
            "gridrt / Embree",
            "same hit per pixel",
        ]);
        for r in &t.rows {
            let (Some(e), Some(g)) = (&r.embree, r.grids.get(d)) else {
                continue;
            };
            let ours = g.build.first().copied().unwrap_or(f64::NAN) + g.trace_only;
            let theirs = e.build + e.trace;
            md += &row_line(&[
                count(r.n as u64),
                num(e.build),
                num(e.trace),
                num(theirs),
                g.build.first().map_or("—".into(), |&v| num(v)),
                num(g.trace_only),
                num(ours),
                format!("{}×", num(ours / theirs)),
                match e.differing {
                    0 => "✓".into(),
                    1 => "1 pixel differs".into(),
                    d => format!("{} pixels differ", count(d as u64)),
                },
            ]);
        }
        md.push('\n');
        let _ = writeln!(
            md,
            "Embree's numbers follow `embree_bench.c`: `rtcCommitScene` of `RTC_GEOMETRY_TYPE_SPHERE_POINT` \
             (build quality medium, device `threads=1`), then {} `rtcIntersect1` calls on one thread, \
             no shading. gridrt's *trace only* is the same closest-hit work (`Renderer::count_camera_hits`, \
             1 thread); *same hit per pixel* compares the hit sphere of every pixel (a pixel or two \
             may differ at grazing hits: Embree's sphere test rounds differently).\n",
            count(rays)
        );
    }

    // Problems and notes.
    let problems: Vec<String> = t
        .rows
        .iter()
        .flat_map(|r| {
            r.problems
                .iter()
                .map(move |p| format!("N = {}: {p}", count(r.n as u64)))
        })
        .collect();
    if !problems.is_empty() {
        let _ = writeln!(md, "## Problems\n");
        for p in &problems {
            let _ = writeln!(md, "- **{p}**");
        }
        md.push('\n');
    }
    let _ = writeln!(md, "## How to read it\n");
    let est_rows: Vec<String> = t
        .rows
        .iter()
        .filter(|r| r.exhaustive.total.iter().any(|s| s.estimated))
        .map(|r| {
            format!(
                "{} ({} of {res} rows)",
                count(r.n as u64),
                r.exhaustive.rows
            )
        })
        .collect();
    let _ = writeln!(
        md,
        "- *speed-up* = exhaustive time / grid time; *tests-per-ray ratio* = exhaustive tests per ray / \
         grid tests per ray ({}). The tests ratio is what the grid saves in work; the time ratio is \
         smaller because a grid ray also pays for walking cells, and every ray pays for shading.",
        t.configs[d].0
    );
    if !est_rows.is_empty() {
        let _ = writeln!(
            md,
            "- *est.*: at N = {} the exhaustive render covered only some rows of the image, spread \
             evenly over it (`Renderer::render_rows`: the same rays and pixels, bit for bit, as \
             in the whole frame); the frame's time is that time × {res} / rows. Every exhaustive \
             ray tests all N spheres, so the cost per row hardly varies, and evenly spread rows \
             sample sky and spheres (shading) in proportion. Those rows were compared with the \
             grid's image, pixel for pixel.",
            est_rows.join(", ")
        );
    }
    let _ = writeln!(
        md,
        "- *objects per cell* = references / cells; the book's m = 2 aims at about 8 cells per \
         object. *tests/ray* counts calls of the sphere intersection routine for the {} camera \
         rays (a sphere spanning several cells may be tested more than once without mailboxing).",
        count(rays)
    );
    let _ = writeln!(
        md,
        "- *trace only* traces the camera rays without shading (closest hit only), the work \
         Embree's column measures.\n- The lecture says a ray is tested against O(∛n) objects \
         in theory and O(log n) in practice for a dense scene: see the right panel of \
         [speedup.svg](speedup.svg).\n- Every row renders the same image with every grid and \
         exhaustively (compared bit for bit), and its pixels hit must equal the Embree peer's."
    );
    md
}

/// Exhaustive tests per ray over the grid's, for configuration `d`.
fn tests_ratio(r: &Row, d: usize) -> String {
    match r.grids.get(d) {
        Some(g) if g.tests_per_ray > 0.0 => num(r.exhaustive.tests_per_ray / g.tests_per_ray),
        _ => "—".into(),
    }
}

/// Today's date (UTC) as YYYY-MM-DD, from the system clock.
pub fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (y, m, d) = civil_from_days((secs / 86_400) as i64);
    format!("{y:04}-{m:02}-{d:02}")
}

/// Howard Hinnant's `civil_from_days`: days since 1970-01-01 → (y, m, d).
pub fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn book_table_is_consistent() {
        for b in &BOOK[..5] {
            let e = b.exhaustive.unwrap();
            // The book's speed-ups are its two columns' ratio (rounded).
            assert!((e / b.grid - b.speedup).abs() / b.speedup < 0.1, "{b:?}");
        }
        assert!(book(1_000_000).unwrap().exhaustive.is_none());
        assert!(book(42).is_none());
    }

    #[test]
    fn spread_rows_are_even_distinct_and_capped() {
        assert_eq!(spread_rows(4, 400), vec![50, 150, 250, 350]);
        assert_eq!(spread_rows(1, 10), vec![5]);
        assert_eq!(spread_rows(3, 10), vec![1, 5, 8]);
        assert_eq!(spread_rows(400, 400), (0..400).collect::<Vec<_>>());
        assert_eq!(spread_rows(1000, 4), vec![0, 1, 2, 3]);
        assert_eq!(spread_rows(0, 4), vec![2]);
    }

    #[test]
    fn budget_picks_rows_between_the_bounds() {
        // 400 rays per row × 1000 spheres = 4e5 tests per row.
        assert_eq!(rows_for_budget(1000, 400, 400, 1e9, 4), 400);
        assert_eq!(rows_for_budget(1_000_000, 400, 400, 2e9, 4), 5);
        assert_eq!(rows_for_budget(100_000, 400, 400, 1.6e9, 4), 40);
        assert_eq!(rows_for_budget(10_000, 400, 400, 1.6e9, 4), 400);
        assert_eq!(rows_for_budget(100_000, 400, 400, 1.2e9, 4), 30);
        assert_eq!(rows_for_budget(100_000, 400, 400, 1.25e9, 4), 31);
        assert_eq!(rows_for_budget(1_000_000, 400, 400, 1e6, 4), 4);
        assert_eq!(rows_for_budget(100_000, 400, 400, 2e9, 4), 50);
        assert_eq!(rows_for_budget(10, 400, 400, f64::INFINITY, 4), 400);
    }

    #[test]
    fn extrapolation_scales_by_rows() {
        assert_eq!(extrapolate(2.0, 10, 400), 80.0);
        assert_eq!(extrapolate(2.0, 400, 400), 2.0);
        assert!(extrapolate(1.0, 0, 400).is_nan());
    }

    #[test]
    fn numbers_get_three_digits_and_thousands_separators() {
        assert_eq!(num(46_307.0), "46,307");
        assert_eq!(num(2041.0), "2,041");
        assert_eq!(num(1_234_567.4), "1,234,567");
        assert_eq!(num(164.0), "164");
        assert_eq!(num(2.7), "2.70");
        assert_eq!(num(0.012345), "0.0123");
        assert_eq!(num(f64::NAN), "—");
        assert_eq!(
            secs_cell(Secs {
                value: 1234.0,
                estimated: true
            }),
            "1,234 est."
        );
        assert_eq!(
            ratio_cell(Secs::measured(10.0), Secs::measured(4.0)),
            "2.50"
        );
        assert_eq!(
            ratio_cell(
                Secs {
                    value: 10.0,
                    estimated: true
                },
                Secs::measured(4.0)
            ),
            "2.50 est."
        );
        assert_eq!(count(160_000), "160,000");
        assert_eq!(count(10), "10");
    }

    #[test]
    fn dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(today().len(), 10);
    }

    fn sample() -> Table {
        let grid = |t: f64| GridCell {
            build: vec![0.1 * t, 0.05 * t],
            render: vec![0.9 * t, 0.5 * t],
            total: vec![t, 0.55 * t],
            end_to_end: vec![1.1 * t, 0.6 * t],
            dims: [10, 10, 10],
            cells: 1000,
            occupied: 500,
            references: 1500,
            tests_per_ray: 3.0,
            cells_per_ray: 12.0,
            trace_only: 0.5 * t,
        };
        Table {
            machine: "Test CPU, 2 cores".into(),
            date: "2024-01-01".into(),
            threads: vec![1, 2],
            runs: 3,
            configs: vec![("m = 2".into(), 2.0), ("default (m = 3)".into(), 3.0)],
            resolution: 400,
            rows: vec![
                Row {
                    n: 10,
                    generate: 1e-6,
                    grids: vec![grid(0.01), grid(0.02)],
                    exhaustive: ExhaustiveCell {
                        total: vec![Secs::measured(0.02), Secs::measured(0.011)],
                        rows: 400,
                        tests_per_ray: 10.0,
                    },
                    pixels_hit: 16_972,
                    reference_hit: Some(16_972),
                    ..Row::default()
                },
                Row {
                    n: 1_000_000,
                    generate: 0.01,
                    grids: vec![grid(0.1), grid(0.08)],
                    exhaustive: ExhaustiveCell {
                        total: vec![
                            Secs {
                                value: 500.0,
                                estimated: true,
                            },
                            Secs {
                                value: 260.0,
                                estimated: true,
                            },
                        ],
                        rows: 5,
                        tests_per_ray: 1e6,
                    },
                    pixels_hit: 139_027,
                    reference_hit: Some(139_028),
                    problems: vec!["pixels hit 139,027, the Embree peer's 139,028".into()],
                    embree: None,
                },
            ],
            embree: None,
            command: "cargo xtask speedup-table".into(),
        }
    }

    #[test]
    fn markdown_has_the_book_beside_ours_and_marks_estimates() {
        let md = markdown(&sample());
        // Every table row has as many cells as its header.
        for block in md.split("\n\n").filter(|b| b.starts_with('|')) {
            let widths: Vec<usize> = block.lines().map(|l| l.matches(" | ").count()).collect();
            assert!(
                widths.windows(2).all(|w| w[0] == w[1]),
                "ragged table:\n{block}"
            );
        }
        assert!(
            md.contains("| 1,000,000 | 5.20 | forget it! | ≈ 46,307 |"),
            "{md}"
        );
        assert!(md.contains("| 10 | 1.50 | 2.50 | 1.60 |"));
        assert!(md.contains("500 est."));
        assert!(md.contains("6,250 est.")); // 500 / 0.08
        assert!(md.contains("16,972 ✓") && md.contains("**139,028 ✗**"));
        assert!(md.contains("## All cores (2 threads)"));
        assert!(md.contains("1,000,000 (5 of 400 rows)"));
        assert!(md.contains("## Problems"));
        // tests ratio: 1e6 / 3
        assert!(md.contains("333,333"));
        assert!(!md.contains("Embree 3"));
    }

    #[test]
    fn one_thread_only_has_no_all_cores_table() {
        let mut t = sample();
        t.threads = vec![1];
        assert!(!markdown(&t).contains("## All cores"));
    }
}
