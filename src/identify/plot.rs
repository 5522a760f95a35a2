//! SVG figures of the identification tools: panels of dots and lines, side by
//! side, so the method-specific code only says what to draw.

use plotters::prelude::*;

use crate::report::plots::{PlotError, series_labels};

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// Small grey-ish dots (measured samples).
    Dots,
    /// A line.
    Line,
}

/// One series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text; empty for no legend entry.
    pub label: String,
    /// Points `(x, y)`; non-finite ones are skipped.
    pub points: Vec<(f64, f64)>,
    /// Dots or a line.
    pub style: Style,
    /// Colour as RGB.
    pub color: (u8, u8, u8),
}

/// One panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Caption above the panel.
    pub caption: String,
    /// Horizontal axis label.
    pub x_desc: String,
    /// Vertical axis label.
    pub y_desc: String,
    /// The series, drawn in order.
    pub series: Vec<Series>,
}

/// Measured samples: grey dots.
pub const MEASURED: (u8, u8, u8) = (150, 150, 150);
/// The fit: blue.
pub const FIT: (u8, u8, u8) = (31, 119, 180);
/// A second estimate: orange.
pub const OTHER: (u8, u8, u8) = (255, 127, 14);
/// A third: red.
pub const THIRD: (u8, u8, u8) = (214, 39, 40);

/// A line through `(freqs[k], f(k))` for each line `k` of `ks`: a spectral
/// figure's series over its band.
pub(crate) fn line_over(
    label: &str,
    freqs: &[f64],
    ks: &[usize],
    f: &dyn Fn(usize) -> f64,
    color: (u8, u8, u8),
) -> Series {
    Series {
        label: label.into(),
        points: ks.iter().map(|&k| (freqs[k], f(k))).collect(),
        style: Style::Line,
        color,
    }
}

fn err(e: impl std::fmt::Display) -> PlotError {
    PlotError {
        path: "identify figure".into(),
        message: e.to_string(),
    }
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1e-300));
    (lo - pad, hi + pad)
}

/// A tick label: plain for moderate magnitudes, scientific otherwise.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-2..1e4).contains(&a) {
        format!("{v:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{v:.2e}")
    }
}

/// At most `max` evenly spaced points of `points`, so a figure of a long record
/// stays small.
pub fn thin(points: Vec<(f64, f64)>, max: usize) -> Vec<(f64, f64)> {
    if points.len() <= max {
        return points;
    }
    let stride = points.len().div_ceil(max);
    points.into_iter().step_by(stride).collect()
}

/// Draws the panels in a row of `columns` (wrapping into more rows) under one
/// title. Returns the SVG text.
pub fn panels_svg(title: &str, panels: &[Panel], columns: usize) -> Result<String, PlotError> {
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns).max(1);
    let mut svg = String::new();
    {
        let size = (520 * columns as u32, 420 * rows as u32 + 40);
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(title, ("sans-serif", 22)).map_err(err)?;
        let areas = root.split_evenly((rows, columns));
        for (panel, area) in panels.iter().zip(areas) {
            let all = || panel.series.iter().flat_map(|s| s.points.iter());
            let (x0, x1) = bounds(all().map(|p| p.0));
            let (y0, y1) = bounds(all().map(|p| p.1));
            let mut chart = ChartBuilder::on(&area)
                .caption(&panel.caption, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(err)?;
            chart
                .configure_mesh()
                .x_desc(panel.x_desc.as_str())
                .y_desc(panel.y_desc.as_str())
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v))
                .draw()
                .map_err(err)?;
            for s in &panel.series {
                let color = RGBColor(s.color.0, s.color.1, s.color.2);
                let pts = s
                    .points
                    .iter()
                    .copied()
                    .filter(|(x, y)| x.is_finite() && y.is_finite());
                let drawn = match s.style {
                    Style::Dots => chart
                        .draw_series(pts.map(|p| Circle::new(p, 1, color.filled())))
                        .map_err(err)?,
                    Style::Line => chart
                        .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                        .map_err(err)?,
                };
                // A series without a label (the second half of a pair) has no
                // legend entry.
                if !s.label.is_empty() {
                    drawn.label(s.label.as_str()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                }
            }
            series_labels(&mut chart, SeriesLabelPosition::UpperLeft).map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}
