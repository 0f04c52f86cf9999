//! What `gridrt render` and `gridrt rays` report in numbers: a speed that
//! never rounds a slow run to zero, the accelerator that `--accel auto`
//! chose, the work per ray counted in a pass of its own, and the JSON of
//! `--stats`.

use crate::cli::Accel;
use gridrt_grid::{Exhaustive, Grid, GridStats, NestLevel, Primitive, QueryCounters};
use gridrt_tracer::{Aov, PixelRect, Renderer};
use serde::Serialize;

/// `rays` in `secs` as millions per second (0 when nothing was timed).
#[must_use]
pub(crate) fn mrays(rays: u64, secs: f64) -> f64 {
    if secs > 0.0 {
        rays as f64 / secs * 1e-6
    } else {
        0.0
    }
}

/// A speed in Mrays/s with three significant digits, so a slow run reads
/// `0.00612 Mrays/s`, never `0.00 Mrays/s`.
#[must_use]
pub(crate) fn speed_text(rays: u64, secs: f64) -> String {
    let m = mrays(rays, secs);
    if rays == 0 || m <= 0.0 || !m.is_finite() {
        return "no rays timed".to_string();
    }
    let digits = if m >= 100.0 {
        0
    } else {
        // Three significant digits: 2 decimals at 1..10, 3 at 0.1..1, ...
        (2 - m.log10().floor() as i32).max(0) as usize
    };
    format!("{m:.digits$} Mrays/s")
}

/// What the accelerator is once built: `exhaustive`, `grid` (a flat grid)
/// or `hierarchy` (a grid with nested grids in its crowded cells), which
/// is what `--accel auto` chose.
#[must_use]
pub(crate) fn chosen(accel: Accel, grid: Option<&GridStats>) -> &'static str {
    match (accel, grid) {
        (Accel::Exhaustive, _) | (_, None) => "exhaustive",
        (_, Some(g)) if g.nested_cells > 0 => "hierarchy",
        _ => "grid",
    }
}

/// The performance figures common to `render --stats` and `rays --stats`.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct Perf {
    /// What was built: `grid`, `hierarchy` or `exhaustive`.
    pub accel: &'static str,
    /// What `--accel` asked for (`auto`, `grid`, …).
    pub accel_requested: &'static str,
    /// Building the accelerator, in seconds.
    pub build_s: f64,
    /// The query loop alone (render: the pixels), in seconds.
    pub trace_s: f64,
    /// Rays traced in `trace_s` (render: all kinds).
    pub rays: u64,
    /// Rays that hit something (render: pixels whose camera ray hit).
    pub hits: u64,
    /// `rays / trace_s`, in millions.
    pub mrays_per_s: f64,
    /// Cells visited per ray (`rays`: every query; render: the camera ray
    /// through each pixel's centre), counted in a pass of its own.
    pub cells_per_ray: f64,
    /// Primitive tests per ray, counted likewise.
    pub tests_per_ray: f64,
    /// Bytes of the accelerator's index (cells, references, nested grids).
    pub bytes: usize,
}

/// The grid's figures in `rays --stats`.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct GridJson {
    dims: [u32; 3],
    cells: u64,
    occupied_cells: u64,
    references: u64,
    max_refs_per_cell: u32,
    nested_grids: u64,
    nest_levels: u32,
    nest_min_refs: u32,
    /// The nested grids level by level ([`GridStats::levels`]).
    levels: Vec<LevelJson>,
    /// Cells tested by groups of four with a box each.
    grouped_cells: u64,
    /// Primitives kept outside the cells and tested by every ray: those
    /// whose box is not finite, and outsized ones (a ground under a model).
    prims_outside_cells: u64,
    budget: usize,
    bytes: usize,
}

/// One level of nested grids in `--stats`.
#[derive(Clone, Debug, Serialize)]
struct LevelJson {
    grids: u64,
    cells: u64,
    occupied_cells: u64,
    references: u64,
    direct_refs: u64,
    max_refs_per_cell: u32,
    wide_grids: u64,
    wide_references: u64,
}

impl From<&NestLevel> for LevelJson {
    fn from(l: &NestLevel) -> Self {
        Self {
            grids: l.grids,
            cells: l.cells,
            occupied_cells: l.occupied_cells,
            references: l.references,
            direct_refs: l.direct_refs,
            max_refs_per_cell: l.max_refs_per_cell,
            wide_grids: l.wide_grids,
            wide_references: l.wide_references,
        }
    }
}

/// One line per level of nested grids, for the grid line of `info` and
/// of the render summary: where the references stopped separating (a
/// level whose cells hold many references each, or whose references
/// outnumber the level above's many times).
pub(crate) fn level_lines(g: &GridStats) -> String {
    let mut t = String::new();
    for (i, l) in g.levels.iter().enumerate() {
        let per = l.references as f64 / l.occupied_cells.max(1) as f64;
        let grids = if l.grids == 1 { "grid" } else { "grids" };
        let direct = if l.direct_refs > 0 {
            format!(", {} tested on entry", l.direct_refs)
        } else {
            String::new()
        };
        let wide = match l.wide_grids {
            0 => String::new(),
            1 => format!(", 1 wide grid of {} refs", l.wide_references),
            n => format!(", {n} wide grids of {} refs", l.wide_references),
        };
        t += &format!(
            "  level {:<4}{} {grids}, {} cells, {} occupied, {} refs ({per:.2} per occupied cell, max {}){direct}{wide}\n",
            i + 1,
            l.grids,
            l.cells,
            l.occupied_cells,
            l.references,
            l.max_refs_per_cell,
        );
    }
    t
}

impl GridJson {
    pub(crate) fn new(g: &GridStats) -> Self {
        Self {
            dims: g.dims,
            cells: g.cells,
            occupied_cells: g.occupied_cells,
            references: g.references,
            max_refs_per_cell: g.max_refs_per_cell,
            nested_grids: g.nested_cells,
            nest_levels: g.nest_levels,
            nest_min_refs: g.nest_min_refs,
            levels: g.levels.iter().map(LevelJson::from).collect(),
            grouped_cells: g.grouped_cells,
            prims_outside_cells: g.unbounded_prims,
            budget: g.budget,
            bytes: g.bytes,
        }
    }
}

/// The JSON of `gridrt rays --stats`.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct RaysJson {
    pub mesh: String,
    pub rays_file: String,
    pub triangles: usize,
    /// How the grid stored them: `copies` or `indexed`.
    pub triangle_storage: &'static str,
    pub threads: usize,
    #[serde(flatten)]
    pub perf: Perf,
    pub grid: Option<GridJson>,
}

/// Work per ray of the camera rays through the pixel centres, counted with
/// the render passes `cells-visited` and `tests`.
pub(crate) fn camera_counters(renderer: &Renderer) -> QueryCounters {
    let (w, h) = renderer.size();
    if w == 0 || h == 0 {
        return QueryCounters::default();
    }
    let passes = renderer.render_aovs(
        &[Aov::CellsVisited, Aov::Tests],
        PixelRect {
            x0: 0,
            y0: 0,
            x1: w,
            y1: h,
        },
    );
    let sum = |k: usize| -> u64 { passes[k].values.iter().map(|&v| v as u64).sum() };
    QueryCounters {
        rays: u64::from(w) * u64::from(h),
        cells: sum(0),
        tests: sum(1),
        mailbox_skips: 0,
    }
}

/// Counts the work of every query against a grid (not timed).
pub(crate) fn count_grid<P: Primitive>(
    grid: &Grid<P>,
    queries: &[crate::RayQuery],
) -> QueryCounters {
    let mut c = QueryCounters::default();
    let mut scratch = gridrt_grid::Accelerator::scratch(grid);
    for q in queries {
        grid.closest_hit_counted(&q.ray, q.t_min, q.t_max, &mut scratch, &mut c);
    }
    c
}

/// Counts the work of every query against the exhaustive baseline.
pub(crate) fn count_exhaustive<P: Primitive>(
    e: &Exhaustive<P>,
    queries: &[crate::RayQuery],
) -> QueryCounters {
    let mut c = QueryCounters::default();
    for q in queries {
        e.closest_hit_counted(&q.ray, q.t_min, q.t_max, &mut c);
    }
    c
}

/// The name of a triangle storage in reports: `copies` or `indexed`.
pub(crate) fn storage_name(s: gridrt_tracer::TriangleStorage) -> &'static str {
    match s {
        gridrt_tracer::TriangleStorage::Auto => "auto",
        gridrt_tracer::TriangleStorage::Copies => "copies",
        gridrt_tracer::TriangleStorage::Indexed => "indexed",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_speeds_keep_three_significant_digits() {
        assert_eq!(speed_text(6_120, 1.0), "0.00612 Mrays/s");
        assert_eq!(speed_text(1, 1.0), "0.00000100 Mrays/s");
        assert_eq!(speed_text(8_300_000, 1.0), "8.30 Mrays/s");
        assert_eq!(speed_text(412_000, 1.0), "0.412 Mrays/s");
        assert_eq!(speed_text(123_400_000, 1.0), "123 Mrays/s");
        assert_eq!(speed_text(0, 1.0), "no rays timed");
        assert_eq!(speed_text(10, 0.0), "no rays timed");
    }

    #[test]
    fn chosen_names_what_was_built() {
        let flat = GridStats::default();
        let nested = GridStats {
            nested_cells: 3,
            ..GridStats::default()
        };
        assert_eq!(chosen(Accel::Auto, Some(&flat)), "grid");
        assert_eq!(chosen(Accel::Auto, Some(&nested)), "hierarchy");
        assert_eq!(chosen(Accel::Exhaustive, None), "exhaustive");
    }

    #[test]
    fn each_level_of_nested_grids_gets_a_line() {
        assert_eq!(level_lines(&GridStats::default()), "");
        let level = |grids, direct_refs, wide_grids| NestLevel {
            grids,
            cells: 512,
            occupied_cells: 100,
            references: 250,
            direct_refs,
            max_refs_per_cell: 9,
            wide_grids,
            wide_references: 40 * wide_grids,
        };
        let g = GridStats {
            levels: vec![level(1, 14, 1), level(3, 0, 2)],
            ..GridStats::default()
        };
        assert_eq!(
            level_lines(&g),
            "  level 1   1 grid, 512 cells, 100 occupied, 250 refs (2.50 per occupied cell, max 9), 14 tested on entry, 1 wide grid of 40 refs\n\
             \x20 level 2   3 grids, 512 cells, 100 occupied, 250 refs (2.50 per occupied cell, max 9), 2 wide grids of 80 refs\n"
        );
    }
}
