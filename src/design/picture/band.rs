//! The band picture ([`band_svg`]): a metric with its 95 % band against
//! one design variable, one line per series.

use std::fmt::Write as _;

use super::{
    Axis, Frame, LABEL_SIZE, PALETTE, Svg, fail, finite_range, padded, rgb, text_width, tick_labels,
};
use crate::report::plots::PlotError;

/// One line of a [`band_svg`] picture: its label, the x values, the central
/// values and the band (`lo`, `hi`); any value may be NaN (a gap). `mid`,
/// `lo` and `hi` hold one value per x.
#[derive(Debug, Clone, Copy)]
pub struct BandLine<'a> {
    /// The legend's label for this line.
    pub label: &'a str,
    /// The design variable's values, in any order.
    pub x: &'a [f64],
    /// The central value at each x.
    pub mid: &'a [f64],
    /// The band's lower edge at each x, if any.
    pub lo: Option<&'a [f64]>,
    /// The band's upper edge at each x, if any.
    pub hi: Option<&'a [f64]>,
}

const BAND_FILE: &str = "band.svg";

/// A line with its shaded band (95 %) for each series against one design
/// variable: `x_name` labels the x axis, `y_name` the y axis; `log_x` draws
/// x on a log axis. A NaN in x, the central value or the band leaves a gap;
/// a run of one point is drawn as a dot with an error bar. Refused: no
/// lines, no x values at all, a line whose `mid`, `lo` or `hi` has not one
/// value per x, and, with `log_x`, an x that is zero or negative. Returns
/// the SVG text.
pub fn band_svg(
    title: &str,
    x_name: &str,
    y_name: &str,
    log_x: bool,
    lines: &[BandLine<'_>],
) -> Result<String, PlotError> {
    if lines.is_empty() {
        return Err(fail(
            BAND_FILE,
            "no lines to draw (the list of lines is empty)",
        ));
    }
    if lines.iter().all(|l| l.x.is_empty()) {
        return Err(fail(
            BAND_FILE,
            "no x values to draw (every line's x is empty)",
        ));
    }
    for l in lines {
        let n = l.x.len();
        let parts = [("mid", Some(l.mid)), ("lo", l.lo), ("hi", l.hi)];
        for (part, values) in parts {
            if let Some(v) = values
                && v.len() != n
            {
                return Err(fail(
                    BAND_FILE,
                    format!(
                        "line '{}': {part} has {} values, x has {n}",
                        l.label,
                        v.len()
                    ),
                ));
            }
        }
        if log_x && let Some(bad) = l.x.iter().find(|v| v.is_finite() && **v <= 0.0) {
            return Err(fail(
                BAND_FILE,
                format!(
                    "the x axis ({x_name}) is logarithmic but line '{}' has x = {bad} \
                     (every x must be > 0)",
                    l.label
                ),
            ));
        }
    }
    let x_range = finite_range(lines.iter().flat_map(|l| l.x.iter().copied()));
    let Some((x_lo, x_hi)) = x_range else {
        return Err(fail(BAND_FILE, "no finite x value to draw"));
    };
    let ys = lines.iter().flat_map(|l| {
        let parts = [Some(l.mid), l.lo, l.hi];
        parts
            .into_iter()
            .flatten()
            .flat_map(move |v| v.iter().zip(l.x).filter(|(_, x)| x.is_finite()))
            .map(|(y, _)| *y)
    });
    let y_range = finite_range(ys);
    let (x_lo, x_hi) = padded(x_lo, x_hi, log_x, 0.02);
    let (y_lo, y_hi) = match y_range {
        Some((lo, hi)) => padded(lo, hi, false, 0.05),
        None => (0.0, 1.0),
    };

    // The legend stands right of the plot, never over data; the figure
    // grows to hold it.
    let legend = lines.len() > 1;
    let (plot_width, legend_width) = if legend {
        let widest = lines
            .iter()
            .map(|l| text_width(l.label, LABEL_SIZE) + 90.0)
            .fold(0.0, f64::max);
        (540.0, widest.max(230.0))
    } else {
        (770.0, 0.0)
    };
    let width = 100.0 + plot_width + 30.0 + legend_width;
    let height = (150.0 + 26.0 * lines.len() as f64).max(540.0);
    let x = Axis {
        lo: x_lo,
        hi: x_hi,
        log: log_x,
        a: 100.0,
        b: 100.0 + plot_width,
    };
    let y = Axis {
        lo: y_lo,
        hi: y_hi,
        log: false,
        a: height - 70.0,
        b: 70.0,
    };
    let (x_major, x_minor) = x.ticks();
    let (y_major, _) = y.ticks();
    let x_labels = tick_labels(&x_major, 3);
    let y_labels = tick_labels(&y_major, 4);
    let frame = Frame {
        x,
        y,
        x_ticks: x_major.into_iter().zip(x_labels).collect(),
        x_minor,
        y_ticks: y_major.into_iter().zip(y_labels).collect(),
        y_minor: Vec::new(),
        x_name,
        y_name,
        grid: true,
    };

    let mut svg = Svg::new(width, height);
    let banded = lines.iter().any(|l| l.lo.is_some() && l.hi.is_some());
    let note = if banded {
        "lines: central value; shaded: 95 % band"
    } else {
        ""
    };
    svg.title(width, title, note);
    frame.grid(&mut svg);
    for (k, l) in lines.iter().enumerate() {
        let colour = rgb(PALETTE[k % PALETTE.len()]);
        let dash = dash(k);
        let mut order: Vec<usize> = (0..l.x.len()).filter(|i| l.x[*i].is_finite()).collect();
        order.sort_by(|a, b| l.x[*a].total_cmp(&l.x[*b]));
        if let (Some(lo), Some(hi)) = (l.lo, l.hi) {
            let ok = |i: &usize| lo[*i].is_finite() && hi[*i].is_finite();
            for run in runs(&order, ok) {
                if let [i] = run {
                    let p = x.px(l.x[*i]);
                    svg.line(
                        (p, y.px(lo[*i])),
                        (p, y.px(hi[*i])),
                        &format!("class=\"band-bar\" stroke=\"{colour}\" stroke-width=\"2\""),
                    );
                    continue;
                }
                let mut points = String::new();
                for i in run {
                    w!(points, "{:.2},{:.2} ", x.px(l.x[*i]), y.px(lo[*i]));
                }
                for i in run.iter().rev() {
                    w!(points, "{:.2},{:.2} ", x.px(l.x[*i]), y.px(hi[*i]));
                }
                w!(
                    svg.s,
                    "<polygon class=\"band\" points=\"{}\" fill=\"{colour}\" \
                     fill-opacity=\"0.22\" stroke=\"none\"/>\n",
                    points.trim_end()
                );
            }
        }
        for run in runs(&order, |i| l.mid[*i].is_finite()) {
            if let [i] = run {
                w!(
                    svg.s,
                    "<circle class=\"point\" cx=\"{:.2}\" cy=\"{:.2}\" r=\"3.5\" \
                     fill=\"{colour}\"/>\n",
                    x.px(l.x[*i]),
                    y.px(l.mid[*i])
                );
                continue;
            }
            let mut points = String::new();
            for i in run {
                w!(points, "{:.2},{:.2} ", x.px(l.x[*i]), y.px(l.mid[*i]));
            }
            w!(
                svg.s,
                "<polyline class=\"mid\" points=\"{}\" fill=\"none\" stroke=\"{colour}\" \
                 stroke-width=\"2\" stroke-linejoin=\"round\"{dash}/>\n",
                points.trim_end()
            );
        }
    }
    if y_range.is_none() {
        frame.say_nothing_to_draw(&mut svg);
    }
    frame.axes(&mut svg);
    if legend {
        let left = frame.right() + 20.0;
        for (k, l) in lines.iter().enumerate() {
            let colour = rgb(PALETTE[k % PALETTE.len()]);
            let top = frame.top() + 10.0 + 26.0 * k as f64;
            w!(
                svg.s,
                "<rect class=\"swatch\" x=\"{left:.1}\" y=\"{top:.1}\" width=\"28\" \
                 height=\"14\" fill=\"{colour}\" fill-opacity=\"0.22\"/>\n"
            );
            svg.line(
                (left, top + 7.0),
                (left + 28.0, top + 7.0),
                &format!("stroke=\"{colour}\" stroke-width=\"2\"{}", dash(k)),
            );
            let empty = l.mid.iter().all(|v| !v.is_finite());
            let label = if empty {
                format!("{} (no values)", l.label)
            } else {
                l.label.to_string()
            };
            svg.text(left + 36.0, top + 12.0, LABEL_SIZE, "start", &label);
        }
    }
    Ok(svg.finish())
}

/// The dash pattern of line `k` (an SVG attribute, or nothing): solid for
/// the first round of the palette's colours, dashed, dotted and dash-dotted
/// for the rounds after, so no two of 28 lines look alike.
fn dash(k: usize) -> &'static str {
    const DASHES: [&str; 4] = [
        "",
        " stroke-dasharray=\"8 4\"",
        " stroke-dasharray=\"2 3\"",
        " stroke-dasharray=\"10 3 2 3\"",
    ];
    DASHES[(k / PALETTE.len()) % DASHES.len()]
}

/// The maximal runs of consecutive entries of `order` for which `ok` holds.
fn runs(order: &[usize], ok: impl Fn(&usize) -> bool) -> Vec<&[usize]> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, i) in order.iter().enumerate() {
        match (ok(i), start) {
            (true, None) => start = Some(k),
            (false, Some(s)) => {
                out.push(&order[s..k]);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push(&order[s..]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::tests::{assert_svg, count};
    use super::*;

    #[test]
    fn a_band_picture_draws_one_band_and_line_per_unbroken_run() {
        let x = [1.0, 2.0, 3.0, 4.0, 5.0];
        let mid = [1.0, 2.0, f64::NAN, 4.0, 5.0];
        let lo = [0.5, 1.5, 2.5, 3.5, 4.5];
        let hi = [1.5, 2.5, 3.5, 4.5, 5.5];
        let line = BandLine {
            label: "peak force",
            x: &x,
            mid: &mid,
            lo: Some(&lo),
            hi: Some(&hi),
        };
        // Unsorted x and a NaN band value: two runs of the band.
        let x2 = [5.0, 4.0, 3.0, 2.0, 1.0];
        let lo2 = [1.0, 1.0, f64::NAN, 1.0, 1.0];
        let other = BandLine {
            label: "other",
            x: &x2,
            mid: &hi,
            lo: Some(&lo2),
            hi: Some(&hi),
        };
        let svg = band_svg(
            "Band title",
            "stiffness (N/m)",
            "overshoot (%)",
            false,
            &[line, other],
        )
        .unwrap();
        assert_svg(&svg);
        assert!(svg.contains("Band title"));
        assert!(svg.contains("stiffness (N/m)") && svg.contains("overshoot (%)"));
        assert_eq!(count(&svg, "<polygon class=\"band\""), 1 + 2);
        // The first line's gap splits it; the second's mid is whole.
        assert_eq!(count(&svg, "<polyline class=\"mid\""), 2 + 1);
        // A legend for two lines.
        assert!(svg.contains(">peak force</text>") && svg.contains(">other</text>"));
        assert_eq!(count(&svg, "<rect class=\"swatch\""), 2);
    }

    #[test]
    fn a_band_picture_survives_nan_series_and_a_single_x() {
        let nan = [f64::NAN; 3];
        let x = [1.0, 2.0, 3.0];
        let line = BandLine {
            label: "empty",
            x: &x,
            mid: &nan,
            lo: Some(&nan),
            hi: Some(&nan),
        };
        let svg = band_svg("all nan", "x", "y", true, &[line]).unwrap();
        assert_svg(&svg);
        assert_eq!(count(&svg, "<polygon class=\"band\""), 0);
        assert!(svg.contains("no finite values"));
        // One x value: a dot and an error bar, on either axis.
        for log in [false, true] {
            let one = BandLine {
                label: "one",
                x: &[1e4],
                mid: &[2.0],
                lo: Some(&[1.0]),
                hi: Some(&[3.0]),
            };
            let svg = band_svg("single", "x", "y", log, &[one]).unwrap();
            assert_svg(&svg);
            assert_eq!(count(&svg, "class=\"point\""), 1);
            assert_eq!(count(&svg, "class=\"band-bar\""), 1);
            assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        }
        // No band at all: lines only.
        let plain = BandLine {
            label: "plain",
            x: &x,
            mid: &x,
            lo: None,
            hi: None,
        };
        let svg = band_svg("plain", "x", "y", false, &[plain]).unwrap();
        assert_eq!(count(&svg, "<polygon"), 0);
        assert_eq!(count(&svg, "<polyline class=\"mid\""), 1);
    }

    #[test]
    fn a_band_picture_of_many_lines_grows_to_hold_its_legend() {
        let x = [1.0, 2.0, 3.0];
        let labels: Vec<String> = (0..20)
            .map(|k| format!("fixture mass = {k}, damping ratio = 0.{k}"))
            .collect();
        let lines: Vec<BandLine<'_>> = labels
            .iter()
            .map(|label| BandLine {
                label,
                x: &x,
                mid: &x,
                lo: None,
                hi: None,
            })
            .collect();
        let svg = band_svg("many", "x", "y", false, &lines).unwrap();
        assert_svg(&svg);
        let number = |key: &str| -> f64 {
            let at = svg.find(key).unwrap() + key.len();
            svg[at..].split('"').next().unwrap().parse().unwrap()
        };
        let (width, height) = (number("width=\""), number("height=\""));
        let widest = text_width(&labels[19], LABEL_SIZE);
        let legend_x: f64 = svg
            .split("<rect class=\"swatch\" x=\"")
            .skip(1)
            .map(|t| t.split('"').next().unwrap().parse::<f64>().unwrap())
            .fold(0.0, f64::max);
        assert!(
            legend_x + 36.0 + widest <= width,
            "{legend_x} + {widest} > {width}"
        );
        assert!(height >= 80.0 + 26.0 * 20.0, "{height}");
        // Past the palette's seven colours the lines are dashed; no band: no note of one.
        assert_eq!(count(&svg, "<polyline class=\"mid\""), 20);
        assert_eq!(count(&svg, "stroke-dasharray"), 2 * 13);
        assert!(!svg.contains("shaded"));
    }

    #[test]
    fn a_band_picture_refuses_empty_input_and_nonpositive_log_x() {
        let e = band_svg("t", "x", "y", false, &[]).unwrap_err();
        assert!(e.message.contains("no lines"), "{e}");
        let empty = BandLine {
            label: "a",
            x: &[],
            mid: &[],
            lo: None,
            hi: None,
        };
        let e = band_svg("t", "x", "y", false, &[empty]).unwrap_err();
        assert!(e.message.contains("no x values"), "{e}");
        let zero = BandLine {
            label: "a",
            x: &[0.0, 1.0],
            mid: &[1.0, 2.0],
            lo: None,
            hi: None,
        };
        let e = band_svg("t", "mass (kg)", "y", true, &[zero]).unwrap_err();
        assert!(
            e.message.contains("x axis (mass (kg)) is logarithmic"),
            "{e}"
        );
        assert!(band_svg("t", "mass (kg)", "y", false, &[zero]).is_ok());
        let short = BandLine {
            label: "a",
            x: &[1.0, 2.0],
            mid: &[1.0],
            lo: None,
            hi: None,
        };
        let e = band_svg("t", "x", "y", false, &[short]).unwrap_err();
        assert!(e.message.contains("mid has 1 values, x has 2"), "{e}");
    }
}
