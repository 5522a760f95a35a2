//! SVG plots a person looks at first: the fit and the search's progress.

use std::path::Path;

use plotters::prelude::*;

/// Errors raised while drawing.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {message}")]
pub struct PlotError {
    /// The SVG being written.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

fn range(series: &[&[f64]]) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for s in series {
        for &v in *s {
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if !lo.is_finite() || !hi.is_finite() {
        return (0.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).max(1e-12);
    (lo - pad, hi + pad)
}

/// Measured vs model load-cell force with the cleaned specimen force, against
/// time in milliseconds. Returns the SVG text.
pub fn fit_svg(
    title: &str,
    t_s: &[f64],
    measured: &[f64],
    model: &[f64],
    cleaned: &[f64],
) -> Result<String, PlotError> {
    let mut svg = String::new();
    let here = Path::new("fit.svg");
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(here, e))?;
        let t_ms: Vec<f64> = t_s.iter().map(|t| t * 1e3).collect();
        let (x0, x1) = range(&[&t_ms]);
        let (y0, y1) = range(&[measured, model, cleaned]);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0 / 1e3..y1 / 1e3)
            .map_err(|e| err(here, e))?;
        chart
            .configure_mesh()
            .x_desc("time (ms)")
            .y_desc("force (kN)")
            .draw()
            .map_err(|e| err(here, e))?;
        let series: [(&str, &[f64], RGBColor, u32); 3] = [
            (
                "measured load-cell force",
                measured,
                RGBColor(175, 175, 175),
                4,
            ),
            ("model load-cell force", model, RGBColor(31, 119, 180), 1),
            (
                "model specimen force (cleaned)",
                cleaned,
                RGBColor(214, 39, 40),
                2,
            ),
        ];
        for (label, ys, color, width) in series {
            let points = t_ms.iter().zip(ys).map(|(t, f)| (*t, f / 1e3));
            labelled_line(&mut chart, points, label, color, width).map_err(|e| err(here, e))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| err(here, e))?;
        root.present().map_err(|e| err(here, e))?;
    }
    Ok(svg)
}

/// Best and median fitness (1 − R², log scale) against generation. Returns the
/// SVG text.
pub fn fitness_svg(title: &str, best: &[f64], median: &[f64]) -> Result<String, PlotError> {
    let mut svg = String::new();
    let here = Path::new("fitness.svg");
    {
        let root = SVGBackend::with_string(&mut svg, (900, 500)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(here, e))?;
        let clean = |v: &f64| v.clamp(1e-12, 1e3);
        let lo = best.iter().map(clean).fold(f64::INFINITY, f64::min);
        let hi = median.iter().chain(best).map(clean).fold(0.0, f64::max);
        let (lo, hi) = if lo.is_finite() && hi > lo {
            (lo / 2.0, hi * 2.0)
        } else {
            (1e-6, 1.0)
        };
        let n = best.len().max(2) as f64;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..n, (lo..hi).log_scale())
            .map_err(|e| err(here, e))?;
        chart
            .configure_mesh()
            .x_desc("generation")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_desc("1 − R²")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| err(here, e))?;
        let series: [(&str, &[f64], RGBColor); 2] = [
            ("best", best, RGBColor(31, 119, 180)),
            ("median", median, RGBColor(255, 127, 14)),
        ];
        for (label, ys, color) in series {
            let points = ys.iter().enumerate().map(|(g, v)| (g as f64, clean(v)));
            labelled_line(&mut chart, points, label, color, 2).map_err(|e| err(here, e))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| err(here, e))?;
        root.present().map_err(|e| err(here, e))?;
    }
    Ok(svg)
}

/// Draws one line series with a legend entry.
fn labelled_line<'a, X, Y>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
    points: impl Iterator<Item = (X::ValueType, Y::ValueType)>,
    label: &str,
    color: RGBColor,
    width: u32,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>>
where
    X: Ranged,
    Y: Ranged,
    X::ValueType: Clone + 'static,
    Y::ValueType: Clone + 'static,
{
    chart
        .draw_series(LineSeries::new(points, color.stroke_width(width)))?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    Ok(())
}
