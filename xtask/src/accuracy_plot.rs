//! The plots of `cargo xtask accuracy`: log-log and log-linear charts of
//! measured series.

use crate::plot::Series;
use plotters::prelude::*;
use std::path::Path;

/// One chart: a title, axis names, whether y is logarithmic, the series.
pub struct Chart<'a> {
    pub title: &'a str,
    pub x_desc: &'a str,
    pub y_desc: &'a str,
    pub series: &'a [Series],
}

/// Draws the charts side by side (log x, log y) into an SVG file; series
/// points with y ≤ 0 are left out (a log axis cannot show them).
pub fn charts_svg(path: &Path, charts: &[Chart<'_>]) -> Result<(), Box<dyn std::error::Error>> {
    let mut svg = String::new();
    {
        let w = 700 * charts.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut svg, (w, 560)).into_drawing_area();
        root.fill(&WHITE)?;
        let areas = root.split_evenly((1, charts.len().max(1)));
        for (area, c) in areas.iter().zip(charts) {
            chart(area, c)?;
        }
        root.present()?;
    }
    crate::util::write_atomic(path, svg.as_bytes())?;
    Ok(())
}

fn chart(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    c: &Chart<'_>,
) -> Result<(), Box<dyn std::error::Error>> {
    let all = || {
        c.series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
    };
    let (x0, x1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    if x0 > x1 || y0 > y1 {
        return Ok(());
    }
    let mut ch = ChartBuilder::on(area)
        .caption(c.title, ("sans-serif", 19))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 2.0..y1 * 2.0).log_scale(),
        )?;
    ch.configure_mesh()
        .x_desc(c.x_desc)
        .y_desc(c.y_desc)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    for s in c.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect();
        let color = s.color;
        let style = color.stroke_width(2);
        let anno = if s.dashed {
            ch.draw_series(DashedLineSeries::new(pts.clone(), 6, 4, style))?
        } else {
            ch.draw_series(LineSeries::new(pts.clone(), style))?
        };
        anno.label(s.label.clone()).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
        });
        if !s.dashed {
            ch.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
        }
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}
