//! The speed-up plot: time vs N (ours and the book's), and primitive tests per ray vs N.

use plotters::prelude::*;
use std::path::Path;

/// One series of (N, value) points.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub dashed: bool,
}

/// Draws two log-log panels side by side into an SVG file.
pub fn speedup_svg(
    path: &Path,
    times: &[Series],
    tests: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1400, 600)).into_drawing_area();
        root.fill(&WHITE)?;
        let (left, right) = root.split_horizontally(700);
        panel(
            &left,
            "Time vs N, 1 thread (grid: build + render)",
            "seconds",
            times,
        )?;
        panel(&right, "Primitive tests per ray", "tests per ray", tests)?;
        root.present()?;
    }
    crate::util::write_atomic(path, svg.as_bytes())?;
    Ok(())
}

fn panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    title: &str,
    y_desc: &str,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    let all = || {
        series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|p| p.1 > 0.0)
    };
    let (x0, x1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    if x0 > x1 || y0 > y1 {
        return Ok(());
    }
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 2.0..y1 * 2.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("number of spheres N")
        .y_desc(y_desc)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    for s in series {
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(|p| p.1 > 0.0).collect();
        let color = s.color;
        let style = color.stroke_width(2);
        let anno = if s.dashed {
            chart.draw_series(DashedLineSeries::new(pts.clone(), 6, 4, style))?
        } else {
            chart.draw_series(LineSeries::new(pts.clone(), style))?
        };
        anno.label(s.label.clone()).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
        });
        // Markers on measured points only, not on sampled reference curves.
        if pts.len() <= 12 {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// Fits `c` in `y = c · f(N)` to the points in log space (the geometric
/// mean of `y / f(N)`), for reference curves drawn through the data.
pub fn fit_scale(points: &[(f64, f64)], f: impl Fn(f64) -> f64) -> f64 {
    let logs: Vec<f64> = points
        .iter()
        .filter(|p| p.1 > 0.0 && f(p.0) > 0.0)
        .map(|&(n, y)| (y / f(n)).ln())
        .collect();
    if logs.is_empty() {
        return f64::NAN;
    }
    (logs.iter().sum::<f64>() / logs.len() as f64).exp()
}

/// The two panels of `docs/speedup.svg` from a speed-up table: time (1
/// thread) vs N, ours and the book's, and primitive tests per ray vs N with
/// the lecture's O(∛n) and O(log n) drawn through our grid's points.
pub fn speedup_plot(
    path: &Path,
    t: &crate::table::Table,
) -> Result<(), Box<dyn std::error::Error>> {
    use crate::table::BOOK;
    let blue = RGBColor(31, 119, 180);
    let light_blue = RGBColor(120, 180, 230);
    let red = RGBColor(214, 39, 40);
    let green = RGBColor(44, 160, 44);
    let grey = RGBColor(110, 110, 110);
    let d = t.default_config();
    let ns: Vec<usize> = t.rows.iter().map(|r| r.n).collect();
    let in_range =
        |n: usize| ns.first().is_some_and(|&lo| n >= lo) && ns.last().is_some_and(|&hi| n <= hi);

    let mut times = vec![
        Series {
            label: "book: grid (450 MHz G3)".into(),
            points: BOOK
                .iter()
                .filter(|b| in_range(b.n))
                .map(|b| (b.n as f64, b.grid))
                .collect(),
            color: light_blue,
            dashed: true,
        },
        Series {
            label: "book: exhaustive (1e6: grid × ≈46,307)".into(),
            points: BOOK
                .iter()
                .filter(|b| in_range(b.n))
                .map(|b| (b.n as f64, b.exhaustive.unwrap_or(b.grid * b.speedup)))
                .collect(),
            color: RGBColor(240, 140, 140),
            dashed: true,
        },
    ];
    for (i, (label, _)) in t.configs.iter().enumerate() {
        times.push(Series {
            label: format!("gridrt: grid {label}, 1 thread"),
            points: t
                .rows
                .iter()
                .filter_map(|r| {
                    r.grids
                        .get(i)
                        .and_then(|g| g.total.first())
                        .map(|&v| (r.n as f64, v))
                })
                .collect(),
            color: if i == d { blue } else { green },
            dashed: false,
        });
    }
    let est = t
        .rows
        .iter()
        .find(|r| r.exhaustive.total.first().is_some_and(|s| s.estimated));
    times.push(Series {
        label: match est {
            Some(r) => format!(
                "gridrt: exhaustive, 1 thread (est. from N = {})",
                crate::table::count(r.n as u64)
            ),
            None => "gridrt: exhaustive, 1 thread".into(),
        },
        points: t
            .rows
            .iter()
            .filter_map(|r| r.exhaustive.total.first().map(|s| (r.n as f64, s.value)))
            .collect(),
        color: red,
        dashed: false,
    });

    let grid_tests: Vec<(f64, f64)> = t
        .rows
        .iter()
        .filter_map(|r| r.grids.get(d).map(|g| (r.n as f64, g.tests_per_ray)))
        .collect();
    let cbrt_c = fit_scale(&grid_tests, f64::cbrt);
    let log_c = fit_scale(&grid_tests, f64::ln);
    let curve = |c: f64, f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        let (lo, hi) = (
            ns.first().copied().unwrap_or(1) as f64,
            ns.last().copied().unwrap_or(1) as f64,
        );
        (0..=24)
            .map(|i| lo * (hi / lo).powf(f64::from(i) / 24.0))
            .map(|n| (n, c * f(n)))
            .collect()
    };
    let mut tests = Vec::new();
    for (i, (label, _)) in t.configs.iter().enumerate() {
        tests.push(Series {
            label: format!("grid {label}: tests per ray"),
            points: t
                .rows
                .iter()
                .filter_map(|r| r.grids.get(i).map(|g| (r.n as f64, g.tests_per_ray)))
                .collect(),
            color: if i == d { blue } else { green },
            dashed: false,
        });
    }
    tests.push(Series {
        label: format!("grid {}: cells visited per ray", t.configs[d].0),
        points: t
            .rows
            .iter()
            .filter_map(|r| r.grids.get(d).map(|g| (r.n as f64, g.cells_per_ray)))
            .collect(),
        color: light_blue,
        dashed: false,
    });
    tests.push(Series {
        label: "exhaustive: tests per ray (= N)".into(),
        points: t
            .rows
            .iter()
            .map(|r| (r.n as f64, r.exhaustive.tests_per_ray))
            .collect(),
        color: red,
        dashed: false,
    });
    if cbrt_c.is_finite() && ns.len() > 1 {
        tests.push(Series {
            label: format!("lecture, in theory: O(∛n) ({cbrt_c:.3}·∛n)"),
            points: curve(cbrt_c, &f64::cbrt),
            color: grey,
            dashed: true,
        });
    }
    if log_c.is_finite() && ns.len() > 1 {
        tests.push(Series {
            label: format!("lecture, in practice: O(log n) ({log_c:.3}·ln n)"),
            points: curve(log_c, &f64::ln),
            color: RGBColor(190, 150, 40),
            dashed: true,
        });
    }
    speedup_svg(path, &times, &tests)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitted_scale_reproduces_an_exact_law() {
        let pts: Vec<(f64, f64)> = [10.0, 1000.0, 1e6]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.cbrt()))
            .collect();
        assert!((fit_scale(&pts, f64::cbrt) - 3.0).abs() < 1e-12);
        assert!(fit_scale(&[], f64::cbrt).is_nan());
    }
}
