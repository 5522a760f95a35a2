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

/// One model output for [`fit_svg`]: the rig's name and unit and its values.
#[derive(Debug, Clone, Copy)]
pub struct Series<'a> {
    /// The rig's output name (`"load_cell_force"`).
    pub name: &'a str,
    /// Its unit (`"N"`).
    pub unit: &'a str,
    /// One value per sample.
    pub values: &'a [f64],
}

/// A decimal prefix and the factor that takes values into it, so the axis of
/// a quantity of peak magnitude `peak` reads in units of about 1 to 1000; none
/// for a unit that does not start with a letter (`"°C"`, a dimensionless one).
fn si_prefix(peak: f64, unit: &str) -> (f64, &'static str) {
    const PREFIXES: [(i32, &str); 7] = [
        (-9, "n"),
        (-6, "µ"),
        (-3, "m"),
        (0, ""),
        (3, "k"),
        (6, "M"),
        (9, "G"),
    ];
    let lettered = unit.starts_with(|c: char| c.is_ascii_alphabetic());
    if !(peak.is_finite() && peak > 0.0 && lettered) {
        return (1.0, "");
    }
    let exp = ((peak.log10() / 3.0).floor() as i32 * 3).clamp(-9, 9);
    let (e, p) = PREFIXES
        .iter()
        .find(|(e, _)| *e == exp)
        .copied()
        .unwrap_or((0, ""));
    (10f64.powi(-e), p)
}

/// The measurement against the model's output 0, with every other output
/// in output 0's unit (the tensile rig's cleaned specimen force), against
/// time in milliseconds. `outputs` holds at least output 0. Returns the SVG
/// text.
pub fn fit_svg(
    title: &str,
    t_s: &[f64],
    measured: &[f64],
    outputs: &[Series<'_>],
) -> Result<String, PlotError> {
    let here = Path::new("fit.svg");
    let Some(first) = outputs.first() else {
        return Err(err(here, "the rig has no output to plot"));
    };
    let spaced = |name: &str| name.replace('_', " ");
    let mut series: Vec<(String, &[f64], RGBColor, u32)> = vec![
        (
            format!("measured {}", spaced(first.name)),
            measured,
            RGBColor(175, 175, 175),
            4,
        ),
        (
            format!("model {}", spaced(first.name)),
            first.values,
            RGBColor(31, 119, 180),
            1,
        ),
    ];
    const OTHERS: [RGBColor; 5] = [
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
    ];
    let same_unit = outputs[1..].iter().filter(|o| o.unit == first.unit);
    for (o, color) in same_unit.zip(OTHERS.iter().cycle()) {
        series.push((format!("model {}", spaced(o.name)), o.values, *color, 2));
    }
    let values: Vec<&[f64]> = series.iter().map(|s| s.1).collect();
    let (lo, hi) = range(&values);
    let (scale, prefix) = si_prefix(lo.abs().max(hi.abs()), first.unit);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(here, e))?;
        let t_ms: Vec<f64> = t_s.iter().map(|t| t * 1e3).collect();
        let (x0, x1) = range(&[&t_ms]);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, lo * scale..hi * scale)
            .map_err(|e| err(here, e))?;
        chart
            .configure_mesh()
            .x_desc("time (ms)")
            .y_desc(format!("{} ({prefix}{})", spaced(first.name), first.unit))
            .draw()
            .map_err(|e| err(here, e))?;
        for (label, ys, color, width) in &series {
            let points = t_ms.iter().zip(*ys).map(|(t, v)| (*t, v * scale));
            labelled_line(&mut chart, points, label, *color, *width).map_err(|e| err(here, e))?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_prefix_brings_the_peak_into_one_to_a_thousand() {
        for (peak, unit, prefix) in [
            (2.4e4, "N", "k"),
            (3.0e-4, "m", "µ"),
            (0.5, "m/s", "m"),
            (7.0, "N", ""),
            (1e13, "Pa", "G"),
        ] {
            let (scale, p) = si_prefix(peak, unit);
            assert_eq!(p, prefix, "{peak} {unit}");
            let v = peak * scale;
            assert!(
                (1.0..1000.0).contains(&v) || p == "G",
                "{peak} {unit} → {v}"
            );
        }
        assert_eq!(si_prefix(2.4e4, "°C"), (1.0, ""));
        assert_eq!(si_prefix(2.4e4, ""), (1.0, ""));
        assert_eq!(si_prefix(0.0, "N"), (1.0, ""));
    }
}
