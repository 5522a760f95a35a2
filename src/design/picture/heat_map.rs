//! The heat map ([`heat_map_svg`]): a metric over two design variables,
//! coloured by viridis, with its grid checks and cell edges.

use std::fmt::Write as _;

use super::{
    Axis, Frame, LABEL_SIZE, Svg, TICK_SIZE, esc, fail, finite_range, linear_ticks, padded, rgb,
    text_width, thinned_labels, tick_labels,
};
use crate::report::plots::PlotError;

/// Viridis at nine evenly spaced points, interpolated linearly between.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (72, 40, 120),
    (62, 73, 137),
    (49, 104, 142),
    (38, 130, 142),
    (31, 158, 137),
    (53, 183, 121),
    (110, 206, 88),
    (253, 231, 37),
];

/// Viridis at `t` in [0, 1] (clamped).
fn viridis(t: f64) -> (u8, u8, u8) {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let f = t * (VIRIDIS.len() - 1) as f64;
    let i = (f.floor() as usize).min(VIRIDIS.len() - 2);
    let u = f - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |x: u8, y: u8| (f64::from(x) + u * (f64::from(y) - f64::from(x))).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

const HEAT_FILE: &str = "heat_map.svg";

/// Checks one grid of [`heat_map_svg`]: not empty, finite, strictly
/// increasing or decreasing, and positive on a log axis.
fn check_grid(which: &str, name: &str, v: &[f64], log: bool) -> Result<(), PlotError> {
    if v.is_empty() {
        return Err(fail(
            HEAT_FILE,
            format!("no {which} values to draw ({which}s for {name} is empty)"),
        ));
    }
    if let Some(bad) = v.iter().find(|v| !v.is_finite()) {
        return Err(fail(
            HEAT_FILE,
            format!("the {which} grid ({name}) holds {bad}: every grid value must be finite"),
        ));
    }
    if log && let Some(bad) = v.iter().find(|v| **v <= 0.0) {
        return Err(fail(
            HEAT_FILE,
            format!(
                "the {which} axis ({name}) is logarithmic but holds {which} = {bad} \
                 (every {which} must be > 0)"
            ),
        ));
    }
    let rising = v.windows(2).all(|w| w[0] < w[1]);
    let falling = v.windows(2).all(|w| w[0] > w[1]);
    if !(rising || falling) {
        return Err(fail(
            HEAT_FILE,
            format!("the {which} grid ({name}) is not strictly increasing or decreasing"),
        ));
    }
    Ok(())
}

/// The edges of the cells centred on the grid values `v` (checked by
/// [`check_grid`]): half-way between neighbours, in log space on a log
/// axis, and as far past the ends as the neighbouring half-step.
fn cell_edges(v: &[f64], log: bool) -> Vec<f64> {
    if let [only] = v {
        return if log {
            vec![only / 2.0, only * 2.0]
        } else {
            let half = if *only == 0.0 { 0.5 } else { 0.1 * only.abs() };
            vec![only - half, only + half]
        };
    }
    let to = |v: f64| if log { v.ln() } else { v };
    let from = |t: f64| if log { t.exp() } else { t };
    let t: Vec<f64> = v.iter().map(|v| to(*v)).collect();
    let n = t.len();
    let mut edges = Vec::with_capacity(n + 1);
    edges.push(t[0] - (t[1] - t[0]) / 2.0);
    edges.extend(t.windows(2).map(|w| (w[0] + w[1]) / 2.0));
    edges.push(t[n - 1] + (t[n - 1] - t[n - 2]) / 2.0);
    edges.into_iter().map(from).collect()
}

/// Ticks for a heat map's axis: the grid values themselves where there are
/// few, else round values.
fn grid_ticks(axis: &Axis, grid: &[f64], across: bool) -> (Vec<(f64, String)>, Vec<f64>) {
    if grid.len() <= 15 {
        let labels = thinned_labels(grid, (axis.b - axis.a).abs(), across);
        return (grid.iter().copied().zip(labels).collect(), Vec::new());
    }
    let (major, minor) = axis.ticks();
    let labels = tick_labels(&major, 3);
    (major.into_iter().zip(labels).collect(), minor)
}

/// A heat map of `z[i][j]` over x = `xs[j]` (columns) and y = `ys[i]`
/// (rows), with a colour bar of z's scale (`z_name`) in a viridis colour
/// map; a cell without a value (NaN) is hatched grey. Cells are centred on
/// the grid values, their edges half-way between neighbours (in log space
/// with `log_x`, `log_y`). With a `level`, the outline of the cells whose z
/// is above it is drawn (black on white, so it reads on every colour) and
/// the level marked on the colour bar. Refused: an empty grid, a grid that
/// is not finite or strictly monotonic, `z` not `ys.len()` rows of
/// `xs.len()` values, and a zero or negative value on a log axis. Returns
/// the SVG text.
#[allow(clippy::too_many_arguments)] // The caller's plain data, named.
pub fn heat_map_svg(
    title: &str,
    x_name: &str,
    y_name: &str,
    z_name: &str,
    xs: &[f64],
    ys: &[f64],
    z: &[Vec<f64>],
    log_x: bool,
    log_y: bool,
    level: Option<f64>,
) -> Result<String, PlotError> {
    check_grid("x", x_name, xs, log_x)?;
    check_grid("y", y_name, ys, log_y)?;
    if z.len() != ys.len() {
        return Err(fail(
            HEAT_FILE,
            format!("z has {} rows, one per y value needs {}", z.len(), ys.len()),
        ));
    }
    if let Some((i, row)) = z.iter().enumerate().find(|(_, r)| r.len() != xs.len()) {
        return Err(fail(
            HEAT_FILE,
            format!(
                "z row {i} has {} values, one per x value needs {}",
                row.len(),
                xs.len()
            ),
        ));
    }
    let z_range = finite_range(z.iter().flatten().copied());
    let (z_lo, z_hi) = match z_range {
        Some((lo, hi)) => padded(lo, hi, false, 0.0),
        None => (0.0, 1.0),
    };
    let any_nan = z.iter().flatten().any(|v| !v.is_finite());
    let level = level.filter(|l| l.is_finite());

    let width = 880.0;
    let height = 600.0;
    let x_edges = cell_edges(xs, log_x);
    let y_edges = cell_edges(ys, log_y);
    let span = |e: &[f64]| {
        let (a, b) = (e[0], e[e.len() - 1]);
        (a.min(b), a.max(b))
    };
    let (x_lo, x_hi) = span(&x_edges);
    let (y_lo, y_hi) = span(&y_edges);
    let x = Axis {
        lo: x_lo,
        hi: x_hi,
        log: log_x,
        a: 110.0,
        b: width - 190.0,
    };
    let y = Axis {
        lo: y_lo,
        hi: y_hi,
        log: log_y,
        a: height - 75.0,
        b: 70.0,
    };
    let (x_ticks, x_minor) = grid_ticks(&x, xs, true);
    let (y_ticks, y_minor) = grid_ticks(&y, ys, false);
    let frame = Frame {
        x,
        y,
        x_ticks,
        x_minor,
        y_ticks,
        y_minor,
        x_name,
        y_name,
        grid: false,
    };

    let note = match level {
        Some(l) => format!(
            "outlined: cells with {z_name} above {}",
            tick_labels(&[l], 4)[0]
        ),
        None => String::new(),
    };
    let mut svg = Svg::new(width, height);
    svg.title(width, title, &note);
    w!(
        svg.s,
        "<defs>\n<linearGradient id=\"rigfit-viridis\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">\n"
    );
    for (k, c) in VIRIDIS.iter().enumerate() {
        w!(
            svg.s,
            "<stop offset=\"{:.4}\" stop-color=\"{}\"/>\n",
            k as f64 / (VIRIDIS.len() - 1) as f64,
            rgb(*c)
        );
    }
    w!(
        svg.s,
        "</linearGradient>\n\
         <pattern id=\"rigfit-nan\" patternUnits=\"userSpaceOnUse\" width=\"8\" height=\"8\" \
         patternTransform=\"rotate(45)\">\n\
         <rect x=\"0\" y=\"0\" width=\"8\" height=\"8\" fill=\"#e0e0e0\"/>\n\
         <line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"8\" stroke=\"#9a9a9a\" stroke-width=\"3\"/>\n\
         </pattern>\n</defs>\n<g shape-rendering=\"crispEdges\">\n"
    );
    let x_labels = tick_labels(xs, 4);
    let y_labels = tick_labels(ys, 4);
    for (i, row) in z.iter().enumerate() {
        let (y0, y1) = (y.px(y_edges[i]), y.px(y_edges[i + 1]));
        for (j, v) in row.iter().enumerate() {
            let (x0, x1) = (x.px(x_edges[j]), x.px(x_edges[j + 1]));
            let (class, fill, value) = if v.is_finite() {
                let c = rgb(viridis((v - z_lo) / (z_hi - z_lo)));
                ("cell", c, tick_labels(&[*v], 4).remove(0))
            } else {
                (
                    "cell nan",
                    "url(#rigfit-nan)".to_string(),
                    "no value".into(),
                )
            };
            w!(
                svg.s,
                "<rect class=\"{class}\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" \
                 height=\"{:.2}\" fill=\"{fill}\"><title>{}: {}, {}: {}, {}: {}</title></rect>\n",
                x0.min(x1),
                y0.min(y1),
                (x1 - x0).abs(),
                (y1 - y0).abs(),
                esc(x_name),
                x_labels[j],
                esc(y_name),
                y_labels[i],
                esc(z_name),
                value
            );
        }
    }
    svg.s.push_str("</g>\n");
    if let Some(l) = level {
        let above = |i: usize, j: usize| z[i][j].is_finite() && z[i][j] > l;
        let mut d = String::new();
        for i in 0..ys.len() {
            for j in 0..xs.len() {
                if !above(i, j) {
                    continue;
                }
                let (x0, x1) = (x.px(x_edges[j]), x.px(x_edges[j + 1]));
                let (y0, y1) = (y.px(y_edges[i]), y.px(y_edges[i + 1]));
                if j == 0 || !above(i, j - 1) {
                    w!(d, "M{x0:.2} {y0:.2}L{x0:.2} {y1:.2}");
                }
                if j + 1 == xs.len() || !above(i, j + 1) {
                    w!(d, "M{x1:.2} {y0:.2}L{x1:.2} {y1:.2}");
                }
                if i == 0 || !above(i - 1, j) {
                    w!(d, "M{x0:.2} {y0:.2}L{x1:.2} {y0:.2}");
                }
                if i + 1 == ys.len() || !above(i + 1, j) {
                    w!(d, "M{x0:.2} {y1:.2}L{x1:.2} {y1:.2}");
                }
            }
        }
        if !d.is_empty() {
            w!(
                svg.s,
                "<path class=\"level-casing\" d=\"{d}\" fill=\"none\" stroke=\"#ffffff\" \
                 stroke-width=\"5\" stroke-linecap=\"square\"/>\n\
                 <path class=\"level\" d=\"{d}\" fill=\"none\" stroke=\"#000000\" \
                 stroke-width=\"2\" stroke-linecap=\"square\"/>\n"
            );
        }
    }
    if z_range.is_none() {
        frame.say_nothing_to_draw(&mut svg);
    }
    frame.axes(&mut svg);

    // The colour bar, right of the map; the swatch of "no value" under it.
    let bar_left = frame.right() + 30.0;
    let bar_width = 22.0;
    let bar_bottom = if any_nan {
        frame.bottom() - 44.0
    } else {
        frame.bottom()
    };
    let bar = Axis {
        lo: z_lo,
        hi: z_hi,
        log: false,
        a: bar_bottom,
        b: frame.top(),
    };
    w!(
        svg.s,
        "<rect class=\"colour-bar\" x=\"{bar_left:.1}\" y=\"{:.1}\" width=\"{bar_width}\" \
         height=\"{:.1}\" fill=\"url(#rigfit-viridis)\" stroke=\"#000000\" stroke-width=\"1\"/>\n",
        frame.top(),
        bar_bottom - frame.top()
    );
    let z_ticks = linear_ticks(z_lo, z_hi, 6);
    let z_labels = tick_labels(&z_ticks, 4);
    let black = "stroke=\"#000000\" stroke-width=\"1\"";
    let mut widest: f64 = 0.0;
    for (v, label) in z_ticks.iter().zip(&z_labels) {
        let p = bar.px(*v);
        svg.line(
            (bar_left + bar_width, p),
            (bar_left + bar_width + 6.0, p),
            black,
        );
        svg.text(
            bar_left + bar_width + 9.0,
            p + 4.5,
            TICK_SIZE,
            "start",
            label,
        );
        widest = widest.max(text_width(label, TICK_SIZE));
    }
    if let Some(l) = level
        && (z_lo..=z_hi).contains(&l)
    {
        let p = bar.px(l);
        svg.line(
            (bar_left - 4.0, p),
            (bar_left + bar_width, p),
            "class=\"level-mark\" stroke=\"#000000\" stroke-width=\"2\"",
        );
        svg.line(
            (bar_left, p),
            (bar_left + bar_width, p),
            "stroke=\"#ffffff\" stroke-width=\"1\" stroke-dasharray=\"3 3\"",
        );
    }
    svg.vertical_text(
        bar_left + bar_width + widest + 28.0,
        (frame.top() + bar_bottom) / 2.0,
        LABEL_SIZE,
        z_name,
    );
    if any_nan {
        let top = frame.bottom() - 22.0;
        w!(
            svg.s,
            "<rect class=\"nan-swatch\" x=\"{bar_left:.1}\" y=\"{top:.1}\" \
             width=\"{bar_width}\" height=\"16\" fill=\"url(#rigfit-nan)\" \
             stroke=\"#000000\" stroke-width=\"1\"/>\n"
        );
        svg.text(
            bar_left + bar_width + 9.0,
            top + 13.0,
            TICK_SIZE,
            "start",
            "no value",
        );
    }
    Ok(svg.finish())
}

#[cfg(test)]
mod tests {
    use super::super::tests::{assert_svg, count, logspace};
    use super::*;

    #[test]
    fn a_heat_map_draws_every_cell_and_hatches_the_missing_ones() {
        let xs = logspace(1e3, 1e5, 9);
        let ys: Vec<f64> = (0..7).map(|k| 0.01 + 0.01 * k as f64).collect();
        let mut z: Vec<Vec<f64>> = ys
            .iter()
            .map(|y| xs.iter().map(|x| y * x.log10()).collect())
            .collect();
        z[2][3] = f64::NAN;
        z[6][8] = f64::NAN;
        let svg = heat_map_svg(
            "Heat title",
            "stiffness (N/m)",
            "damping ratio",
            "ringing (%)",
            &xs,
            &ys,
            &z,
            true,
            false,
            Some(0.2),
        )
        .unwrap();
        assert_svg(&svg);
        for text in [
            "Heat title",
            "stiffness (N/m)",
            "damping ratio",
            "ringing (%)",
        ] {
            assert!(svg.contains(text), "{text}");
        }
        assert_eq!(count(&svg, "<rect class=\"cell"), 9 * 7);
        assert_eq!(count(&svg, "<rect class=\"cell nan\""), 2);
        assert_eq!(count(&svg, "fill=\"url(#rigfit-nan)\""), 2 + 1);
        assert!(svg.contains("no value"));
        assert_eq!(count(&svg, "<path class=\"level\""), 1);
        // No level: no outline; no NaN: no swatch.
        z[2][3] = 1.0;
        z[6][8] = 1.0;
        let svg = heat_map_svg("h", "x", "y", "z", &xs, &ys, &z, true, false, None).unwrap();
        assert_eq!(count(&svg, "class=\"level"), 0);
        assert_eq!(count(&svg, "cell nan"), 0);
        assert!(!svg.contains("nan-swatch"));
    }

    #[test]
    fn cell_edges_lie_half_way_in_the_axis_space() {
        let e = cell_edges(&[1.0, 10.0, 100.0], true);
        let want = [
            10f64.powf(-0.5),
            10f64.powf(0.5),
            10f64.powf(1.5),
            10f64.powf(2.5),
        ];
        for (a, b) in e.iter().zip(want) {
            assert!((a / b - 1.0).abs() < 1e-12, "{e:?}");
        }
        assert_eq!(cell_edges(&[0.0, 1.0, 3.0], false), [-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(cell_edges(&[3.0, 1.0], false), [4.0, 2.0, 0.0]);
    }

    #[test]
    fn a_heat_map_survives_constant_nan_and_single_cell_grids() {
        let svg = heat_map_svg(
            "const",
            "x",
            "y",
            "z",
            &[1.0, 2.0],
            &[1.0, 2.0],
            &[vec![0.5, 0.5], vec![0.5, 0.5]],
            false,
            false,
            Some(0.1),
        )
        .unwrap();
        assert_svg(&svg);
        assert_eq!(count(&svg, "<rect class=\"cell\""), 4);
        let nan = vec![vec![f64::NAN; 3]; 2];
        let svg = heat_map_svg(
            "nan",
            "x",
            "y",
            "z",
            &[1.0, 2.0, 3.0],
            &[1.0, 2.0],
            &nan,
            false,
            false,
            None,
        )
        .unwrap();
        assert_eq!(count(&svg, "<rect class=\"cell nan\""), 6);
        assert!(svg.contains("no finite values"));
        let svg = heat_map_svg(
            "one",
            "x",
            "y",
            "z",
            &[5.0],
            &[0.0],
            &[vec![1.0]],
            true,
            false,
            None,
        )
        .unwrap();
        assert_eq!(count(&svg, "<rect class=\"cell\""), 1);
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    #[test]
    fn a_heat_map_refuses_empty_ragged_and_nonpositive_log_grids() {
        let call = |xs: &[f64], ys: &[f64], z: &[Vec<f64>], lx, ly| {
            heat_map_svg("t", "mass (kg)", "length (m)", "z", xs, ys, z, lx, ly, None)
                .unwrap_err()
                .message
        };
        assert!(call(&[], &[1.0], &[vec![]], false, false).contains("no x values"));
        assert!(call(&[1.0], &[], &[], false, false).contains("no y values"));
        let m = call(&[1.0, 2.0], &[1.0], &[vec![1.0]], false, false);
        assert!(m.contains("z row 0 has 1 values"), "{m}");
        let m = call(&[1.0], &[1.0, 2.0], &[vec![1.0]], false, false);
        assert!(m.contains("z has 1 rows"), "{m}");
        let m = call(&[0.0, 1.0], &[1.0], &[vec![1.0, 1.0]], true, false);
        assert!(m.contains("x axis (mass (kg)) is logarithmic"), "{m}");
        let m = call(&[1.0], &[-1.0, 1.0], &[vec![1.0], vec![1.0]], false, true);
        assert!(m.contains("y axis (length (m)) is logarithmic"), "{m}");
        let m = call(&[1.0, 1.0], &[1.0], &[vec![1.0, 1.0]], false, false);
        assert!(m.contains("not strictly"), "{m}");
    }
}
