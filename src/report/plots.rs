//! SVG plots a person looks at first: the fit and the search's progress.

use std::ops::Range;
use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
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

/// Most points a series of [`fit_svg`] is drawn with: two per pixel column
/// of the plot (its least and its largest value there), so a figure of a
/// record of millions of samples is a few hundred kilobytes and draws in a
/// fraction of a second, and a peak one sample wide still shows. The
/// experiment's CSV keeps every sample.
pub const FIT_POINTS_PER_SERIES: usize = 2 * FIT_WIDTH as usize;

/// The points of `(t, y)` drawn on `columns` pixel columns: every point
/// where there are at most `2 × columns`, else, in each of `columns` runs of
/// consecutive samples, the least and the largest finite value in the order
/// they occur (the envelope a line drawn through every sample fills).
pub fn envelope(t: &[f64], y: &[f64], columns: usize) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    if n <= 2 * columns.max(1) {
        return t.iter().zip(y).map(|(t, y)| (*t, *y)).collect();
    }
    let columns = columns.max(1);
    let mut points = Vec::with_capacity(2 * columns);
    for c in 0..columns {
        let (a, b) = (c * n / columns, (c + 1) * n / columns);
        let (mut lo, mut hi): (Option<usize>, Option<usize>) = (None, None);
        for k in a..b {
            if !y[k].is_finite() {
                continue;
            }
            if lo.is_none_or(|i| y[k] < y[i]) {
                lo = Some(k);
            }
            if hi.is_none_or(|i| y[k] > y[i]) {
                hi = Some(k);
            }
        }
        match (lo, hi) {
            (Some(i), Some(j)) if i == j => points.push((t[i], y[i])),
            (Some(i), Some(j)) => {
                let (first, second) = if i < j { (i, j) } else { (j, i) };
                points.push((t[first], y[first]));
                points.push((t[second], y[second]));
            }
            _ => {}
        }
    }
    points
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

/// The time axis's unit for a record spanning `span` seconds, and the factor
/// from seconds: ms below 2 s, µs below 2 ms, s otherwise, so its ticks read
/// in ones to thousands.
fn time_unit(span: f64) -> (f64, &'static str) {
    if span < 2e-3 {
        (1e6, "µs")
    } else if span < 2.0 {
        (1e3, "ms")
    } else {
        (1.0, "s")
    }
}

/// Width of the fit figure, its legend column and the height of its panels
/// (pixels).
const FIT_WIDTH: u32 = 1100;
/// The legend's column, right of the plots: it never covers data.
const LEGEND_WIDTH: u32 = 250;
const FIT_HEIGHT: u32 = 480;
const RESIDUAL_HEIGHT: u32 = 220;

/// A legend drawn in its own area: one short line and label per series.
fn legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    top: i32,
    entries: &[(String, RGBColor)],
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    for (i, (label, color)) in entries.iter().enumerate() {
        let y = top + 24 * i as i32;
        area.draw(&PathElement::new(
            vec![(8, y), (32, y)],
            color.stroke_width(3),
        ))?;
        area.draw(&Text::new(
            label.clone(),
            (40, y - 8),
            ("sans-serif", 15).into_font(),
        ))?;
    }
    Ok(())
}

/// A panel of the fit figure on `area`: time across, a quantity up, with
/// `x_labels` pixels under it for the time axis's labels.
fn fit_panel<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    x_labels: u32,
    x: Range<f64>,
    y: Range<f64>,
) -> Result<
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    DrawingAreaErrorKind<std::io::Error>,
> {
    ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(x_labels)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
}

/// The measurement against the model's output 0, with every other output
/// in output 0's unit (the tensile rig's cleaned specimen force), and under
/// it the residual (model output 0 − measured, as in the experiment's CSV),
/// against time in a unit chosen from the record's length; the legend stands
/// right of the plots. `outputs` holds at least output 0. Returns the SVG
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
    // The measurement thin and light, under the model: a dense noisy record
    // drawn wide reads as a solid band that hides the fit.
    let mut series: Vec<(String, &[f64], RGBColor, u32)> = vec![
        (
            format!("measured {}", spaced(first.name)),
            measured,
            RGBColor(160, 160, 160),
            1,
        ),
        (
            format!("model {}", spaced(first.name)),
            first.values,
            RGBColor(31, 119, 180),
            2,
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
    let residual: Vec<f64> = measured
        .iter()
        .zip(first.values)
        .map(|(m, v)| v - m)
        .collect();
    let values: Vec<&[f64]> = series.iter().map(|s| s.1).collect();
    let (lo, hi) = range(&values);
    let (scale, prefix) = si_prefix(lo.abs().max(hi.abs()), first.unit);
    let (r_lo, r_hi) = range(&[&residual]);
    let (r_scale, r_prefix) = si_prefix(r_lo.abs().max(r_hi.abs()), first.unit);
    let span = match (t_s.first(), t_s.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    let (t_factor, t_unit) = time_unit(span);
    let t: Vec<f64> = t_s.iter().map(|x| x * t_factor).collect();
    let (x0, x1) = range(&[&t]);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (FIT_WIDTH, FIT_HEIGHT + RESIDUAL_HEIGHT))
            .into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(here, e))?;
        let root = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| err(here, e))?;
        let (plots, legend_area) = root.split_horizontally(FIT_WIDTH - LEGEND_WIDTH);
        let (upper, lower) = plots.split_vertically(FIT_HEIGHT - 30);
        let mut chart =
            fit_panel(&upper, 30, x0..x1, lo * scale..hi * scale).map_err(|e| err(here, e))?;
        chart
            .configure_mesh()
            .y_desc(format!("{} ({prefix}{})", spaced(first.name), first.unit))
            .draw()
            .map_err(|e| err(here, e))?;
        for (_, ys, color, width) in &series {
            let points = envelope(&t, ys, FIT_POINTS_PER_SERIES / 2)
                .into_iter()
                .map(|(t, v)| (t, v * scale));
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(*width)))
                .map_err(|e| err(here, e))?;
        }
        let r_range = r_lo * r_scale..r_hi * r_scale;
        let mut residual_chart =
            fit_panel(&lower, 44, x0..x1, r_range).map_err(|e| err(here, e))?;
        residual_chart
            .configure_mesh()
            .x_desc(format!("time ({t_unit})"))
            .y_desc(format!("residual ({r_prefix}{})", first.unit))
            .draw()
            .map_err(|e| err(here, e))?;
        let residual_color = RGBColor(214, 39, 40);
        let points = envelope(&t, &residual, FIT_POINTS_PER_SERIES / 2)
            .into_iter()
            .map(|(t, r)| (t, r * r_scale));
        residual_chart
            .draw_series(LineSeries::new(points, residual_color.stroke_width(1)))
            .map_err(|e| err(here, e))?;
        let mut entries: Vec<(String, RGBColor)> =
            series.iter().map(|s| (s.0.clone(), s.2)).collect();
        entries.push(("residual (model − measured)".into(), residual_color));
        legend(&legend_area, 40, &entries).map_err(|e| err(here, e))?;
        root.present().map_err(|e| err(here, e))?;
    }
    Ok(svg)
}

/// Best and median fitness (1 − R², log scale) against generation, then the
/// polish's best cost per iteration (`polish`, from the GA's best, after the
/// last generation), and, where known, the cost the record's noise alone
/// would give (`noise_floor`, a horizontal line: the fit cannot go much
/// below it). Returns the SVG text.
pub fn convergence_svg(
    title: &str,
    best: &[f64],
    median: &[f64],
    polish: &[f64],
    noise_floor: Option<f64>,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    let here = Path::new("fitness.svg");
    {
        let root = SVGBackend::with_string(&mut svg, (900, 500)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(here, e))?;
        let clean = |v: &f64| v.clamp(1e-12, 1e3);
        let floor = noise_floor.filter(|f| f.is_finite() && *f > 0.0);
        let lo = best
            .iter()
            .chain(polish)
            .chain(floor.as_ref())
            .map(clean)
            .fold(f64::INFINITY, f64::min);
        let hi = median
            .iter()
            .chain(best)
            .chain(polish)
            .map(clean)
            .fold(0.0, f64::max);
        let (lo, hi) = if lo.is_finite() && hi > lo {
            (lo / 2.0, hi * 2.0)
        } else {
            (1e-6, 1.0)
        };
        let generations = best.len();
        let n = (generations + polish.len()).max(2) as f64;
        let x_desc = if polish.is_empty() {
            "generation".to_string()
        } else {
            format!(
                "generation, then polish iteration (from {})",
                generations.saturating_sub(1)
            )
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..n, (lo..hi).log_scale())
            .map_err(|e| err(here, e))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
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
        if !polish.is_empty() {
            // Joined to the GA's last best, where the polish starts.
            let start = generations.saturating_sub(1);
            let joined = best.last().into_iter().chain(polish);
            let points = joined
                .enumerate()
                .map(|(i, v)| ((start + i) as f64, clean(v)));
            labelled_line(&mut chart, points, "polish", RGBColor(44, 160, 44), 2)
                .map_err(|e| err(here, e))?;
        }
        if let Some(f) = floor {
            let points = [(0.0, clean(&f)), (n, clean(&f))].into_iter();
            let label = "noise floor (the record's noise alone)";
            labelled_line(&mut chart, points, label, RGBColor(120, 120, 120), 1)
                .map_err(|e| err(here, e))?;
        }
        // Upper right: the costs fall from the upper left towards the floor.
        series_labels(&mut chart, SeriesLabelPosition::UpperRight).map_err(|e| err(here, e))?;
        root.present().map_err(|e| err(here, e))?;
    }
    Ok(svg)
}

/// Draws the chart's legend at `position`, in the box every figure's legend
/// has (white, mostly opaque, a black border).
pub(crate) fn series_labels<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()
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

    /// The x coordinates of the `<text>` elements that hold `label`.
    fn text_x(svg: &str, label: &str) -> Vec<f64> {
        svg.split("<text")
            .skip(1)
            .filter(|t| {
                t.split_once('>')
                    .is_some_and(|(_, rest)| rest.trim_start().starts_with(label))
            })
            .filter_map(|t| {
                let at = t.find(" x=\"")? + 4;
                t[at..].split('"').next()?.parse().ok()
            })
            .collect()
    }

    #[test]
    fn the_fit_of_a_long_record_reads_in_seconds_with_residuals_and_a_legend_aside() {
        // 4 s at 1 kHz with noise: the old figure read "time (ms)" to 4000.
        let t: Vec<f64> = (0..4000).map(|k| k as f64 * 1e-3).collect();
        let model: Vec<f64> = t.iter().map(|t| 100.0 * (3.0 * t).sin()).collect();
        let measured: Vec<f64> = model
            .iter()
            .enumerate()
            .map(|(k, m)| m + if k % 2 == 0 { 3.0 } else { -3.0 })
            .collect();
        let outputs = [Series {
            name: "load_cell",
            unit: "N",
            values: &model,
        }];
        let svg = fit_svg("fit", &t, &measured, &outputs).unwrap();
        assert!(svg.contains("time (s)"), "no time axis in seconds");
        assert!(!svg.contains("time (ms)"));
        assert!(svg.contains("residual (N)"), "no residual panel");
        let legend = text_x(&svg, "measured load cell");
        assert_eq!(legend.len(), 1, "{legend:?}");
        assert!(
            legend[0] >= f64::from(FIT_WIDTH - LEGEND_WIDTH),
            "the legend at x = {} is over the plots",
            legend[0]
        );
        // A short record keeps milliseconds.
        let short: Vec<f64> = t.iter().map(|t| t * 1e-3).collect();
        let svg = fit_svg("fit", &short, &measured, &outputs).unwrap();
        assert!(svg.contains("time (ms)"));
    }

    #[test]
    fn a_long_record_is_drawn_with_its_envelope_and_keeps_a_one_sample_peak() {
        let n = 2_000_000;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-4).collect();
        let mut model: Vec<f64> = t.iter().map(|t| (3.0 * t).sin()).collect();
        // One sample far above the rest: a decimation that kept every k-th
        // sample would lose it.
        model[1_234_567] = 40.0;
        let measured = model.clone();
        let outputs = [Series {
            name: "load_cell",
            unit: "N",
            values: &model,
        }];
        let svg = fit_svg("fit", &t, &measured, &outputs).unwrap();
        assert!(svg.len() < 2_000_000, "{} bytes", svg.len());
        // The peak sets the axis (40 N, padded) and is drawn: a point of
        // the model's line lies at the top of the upper panel's range.
        let e = envelope(&t, &model, FIT_POINTS_PER_SERIES / 2);
        assert!(e.len() <= FIT_POINTS_PER_SERIES, "{}", e.len());
        assert!(e.contains(&(t[1_234_567], 40.0)), "the peak was dropped");
        assert!(e.windows(2).all(|w| w[0].0 < w[1].0), "not in time order");
        // A short series is drawn whole.
        assert_eq!(envelope(&t[..100], &model[..100], 800).len(), 100);
    }

    #[test]
    fn the_convergence_plot_shows_the_polish_and_the_noise_floor() {
        let best = [1e-1, 5e-2, 2e-2];
        let median = [3e-1, 1e-1, 5e-2];
        let svg = convergence_svg("c", &best, &median, &[1e-3, 2e-4], Some(1e-4)).unwrap();
        assert!(svg.contains("\npolish\n"), "no polish in the legend");
        assert!(svg.contains("noise floor"), "no noise floor");
        assert!(svg.contains("then polish iteration"));
        let plain = convergence_svg("c", &best, &median, &[], None).unwrap();
        assert!(!plain.contains("\npolish\n") && !plain.contains("noise floor"));
    }

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
