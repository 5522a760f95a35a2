//! The indices chart ([`indices_svg`]): a metric's first-order and total
//! Sobol indices as bars with their 95 % intervals.

use std::fmt::Write as _;

use super::{
    Axis, Frame, PALETTE, Svg, TICK_SIZE, esc, fail, finite_range, linear_ticks, rgb, text_width,
    tick_labels,
};
use crate::report::plots::PlotError;

/// One design variable of an [`indices_svg`] chart: its first-order and
/// total Sobol indices with their 95 % intervals (`[lo, hi]`); NaN where
/// not known.
#[derive(Debug, Clone, Copy)]
pub struct IndexBar<'a> {
    /// The design variable's name.
    pub name: &'a str,
    /// The first-order index S₁.
    pub first: f64,
    /// S₁'s 95 % interval, `[lo, hi]`.
    pub first_95: [f64; 2],
    /// The total index Sᴛ.
    pub total: f64,
    /// Sᴛ's 95 % interval, `[lo, hi]`.
    pub total_95: [f64; 2],
}

const INDICES_FILE: &str = "indices.svg";

/// A bar chart of the Sobol indices of `metric`: per design variable a
/// first-order bar and a total bar side by side, each with its 95 %
/// interval as an error bar; y from 0 to max(1, the largest interval's
/// upper end), reaching below 0 only where an estimate or interval does
/// (sampling can give a slightly negative estimate of an index near 0). A
/// value that is NaN is written "n/a" in place of its bar. Refused: no
/// variables. Returns the SVG text.
pub fn indices_svg(title: &str, metric: &str, bars: &[IndexBar<'_>]) -> Result<String, PlotError> {
    if bars.is_empty() {
        return Err(fail(
            INDICES_FILE,
            "no variables to draw (the list of index bars is empty)",
        ));
    }
    let values = bars.iter().flat_map(|b| {
        [
            b.first,
            b.first_95[0],
            b.first_95[1],
            b.total,
            b.total_95[0],
            b.total_95[1],
        ]
    });
    let (lo, hi) = finite_range(values).unwrap_or((0.0, 1.0));
    let (y_lo, y_top) = (lo.min(0.0), hi.max(1.0));
    let y_hi = y_top + 0.03 * (y_top - y_lo);

    let first_colour = rgb(PALETTE[0]);
    let total_colour = rgb(PALETTE[1]);
    let entries = [
        ("first-order index S1", Some(&first_colour)),
        ("total index ST", Some(&total_colour)),
        ("error bars: 95 % interval", None),
    ];
    let entry_width = |label: &str| 30.0 + text_width(label, TICK_SIZE) + 16.0;
    let row: f64 = entries.iter().map(|(l, _)| entry_width(l)).sum();
    let n = bars.len();
    let group = 130.0;
    let width = (140.0 + group * n as f64).max(row + 40.0).max(560.0);
    let group = (width - 140.0) / n as f64;
    let widest = bars
        .iter()
        .map(|b| text_width(b.name, TICK_SIZE))
        .fold(0.0, f64::max);
    let turned = widest > group - 12.0;
    let below = if turned {
        40.0 + (0.5 * widest).min(140.0)
    } else {
        50.0
    };
    let height = 460.0 + below;
    let x = Axis {
        lo: 0.0,
        hi: n as f64,
        log: false,
        a: 110.0,
        b: width - 30.0,
    };
    let y = Axis {
        lo: y_lo,
        hi: y_hi,
        log: false,
        a: height - below,
        b: 80.0,
    };
    let y_major = linear_ticks(y_lo, y_top, 6);
    let y_labels = tick_labels(&y_major, 3);
    let y_name = format!("Sobol index of {metric}");
    let frame = Frame {
        x,
        y,
        x_ticks: Vec::new(),
        x_minor: Vec::new(),
        y_ticks: y_major.into_iter().zip(y_labels).collect(),
        y_minor: Vec::new(),
        x_name: "",
        y_name: &y_name,
        grid: true,
    };

    let mut svg = Svg::new(width, height);
    svg.title(width, title, "");
    // The legend, a row under the title.
    let mut left = (width - row) / 2.0;
    for (label, colour) in entries {
        match colour {
            Some(c) => w!(
                svg.s,
                "<rect class=\"swatch\" x=\"{left:.1}\" y=\"46\" width=\"22\" height=\"14\" \
                 fill=\"{c}\"/>\n"
            ),
            None => w!(
                svg.s,
                "<path d=\"M{:.1} 45L{:.1} 61M{:.1} 45L{:.1} 45M{:.1} 61L{:.1} 61\" \
                 stroke=\"#000000\" stroke-width=\"1.5\" fill=\"none\"/>\n",
                left + 11.0,
                left + 11.0,
                left + 6.0,
                left + 16.0,
                left + 6.0,
                left + 16.0
            ),
        }
        svg.text(left + 30.0, 58.0, TICK_SIZE, "start", label);
        left += entry_width(label);
    }
    frame.grid(&mut svg);
    if y_lo < 0.0 {
        svg.line(
            (frame.left(), y.px(0.0)),
            (frame.right(), y.px(0.0)),
            "stroke=\"#000000\" stroke-width=\"1\"",
        );
    }
    let bar_width = (group * 0.3).min(44.0);
    for (k, b) in bars.iter().enumerate() {
        let centre = x.px(k as f64 + 0.5);
        let sides = [
            (
                "first",
                b.first,
                b.first_95,
                &first_colour,
                centre - bar_width - 2.0,
            ),
            ("total", b.total, b.total_95, &total_colour, centre + 2.0),
        ];
        for (class, v, [lo, hi], colour, left) in sides {
            if v.is_finite() {
                let (p0, p1) = (y.px(v.max(0.0)), y.px(v.min(0.0)));
                w!(
                    svg.s,
                    "<rect class=\"bar {class}\" x=\"{left:.2}\" y=\"{p0:.2}\" \
                     width=\"{bar_width:.2}\" height=\"{:.2}\" fill=\"{colour}\">\
                     <title>{}: {class} {}</title></rect>\n",
                    p1 - p0,
                    esc(b.name),
                    tick_labels(&[v], 3)[0]
                );
            } else {
                w!(
                    svg.s,
                    "<text class=\"missing\" x=\"{:.2}\" y=\"{:.2}\" font-size=\"11\" \
                     text-anchor=\"middle\" fill=\"#555555\">n/a</text>\n",
                    left + bar_width / 2.0,
                    y.px(0.0) - 5.0
                );
            }
            if lo.is_finite() && hi.is_finite() {
                let mid = left + bar_width / 2.0;
                let cap = bar_width * 0.25;
                let (a, c) = (y.px(lo), y.px(hi));
                w!(
                    svg.s,
                    "<path class=\"err\" d=\"M{mid:.2} {a:.2}L{mid:.2} {c:.2}\
                     M{:.2} {a:.2}L{:.2} {a:.2}M{:.2} {c:.2}L{:.2} {c:.2}\" \
                     stroke=\"#000000\" stroke-width=\"1.5\" fill=\"none\"/>\n",
                    mid - cap,
                    mid + cap,
                    mid - cap,
                    mid + cap
                );
            }
        }
        let top = frame.bottom() + 20.0;
        if turned {
            w!(
                svg.s,
                "<text x=\"{centre:.1}\" y=\"{top:.1}\" font-size=\"{TICK_SIZE}\" \
                 text-anchor=\"end\" transform=\"rotate(-30 {centre:.1} {top:.1})\">{}</text>\n",
                esc(b.name)
            );
        } else {
            svg.text(centre, top, TICK_SIZE, "middle", b.name);
        }
        if k > 0 {
            let p = x.px(k as f64);
            svg.line(
                (p, frame.bottom()),
                (p, frame.bottom() + 6.0),
                "stroke=\"#000000\" stroke-width=\"1\"",
            );
        }
    }
    frame.axes(&mut svg);
    Ok(svg.finish())
}

#[cfg(test)]
mod tests {
    use super::super::tests::{assert_svg, count, example_bars};
    use super::*;

    #[test]
    fn an_indices_chart_draws_two_bars_and_two_intervals_per_variable() {
        let bars = example_bars();
        let svg = indices_svg("Indices title", "overshoot", &bars).unwrap();
        assert_svg(&svg);
        assert!(svg.contains("Indices title") && svg.contains("Sobol index of overshoot"));
        assert_eq!(count(&svg, "<rect class=\"bar first\""), 3);
        assert_eq!(count(&svg, "<rect class=\"bar total\""), 3);
        assert_eq!(count(&svg, "<path class=\"err\""), 6);
        for b in &bars {
            assert!(svg.contains(&format!(">{}</text>", b.name)));
        }
        // An unknown index: "n/a", no bar, no interval.
        let mut odd = bars.clone();
        odd[1].total = f64::NAN;
        odd[1].total_95 = [f64::NAN, f64::NAN];
        let svg = indices_svg("t", "m", &odd).unwrap();
        assert_eq!(count(&svg, "<rect class=\"bar total\""), 2);
        assert_eq!(count(&svg, "<path class=\"err\""), 5);
        assert_eq!(count(&svg, "class=\"missing\""), 1);
        assert!(!svg.contains("NaN"));
        let e = indices_svg("t", "m", &[]).unwrap_err();
        assert!(e.message.contains("no variables"), "{e}");
    }
}
