//! Pictures of a sweep's table: a metric with its 95 % band against one
//! design variable ([`band_svg`]), a metric over two design variables as a
//! heat map ([`heat_map_svg`]) and a metric's Sobol indices as bars
//! ([`indices_svg`]).
//!
//! The SVG is written by hand (a heat map's cells, its colour bar and the
//! hatching of cells without a value are not in the plotters features the
//! crate builds with), in the house style of [`crate::report::plots`]: white
//! ground, sans-serif text, a 22 px title, the same colours. Every element a
//! caller or a test may want to find carries a class: `band` (a band's
//! polygon), `mid` (a central line), `cell` and `cell nan` (heat-map cells),
//! `level` (the outline of the cells above a level), `bar first` and
//! `bar total` (index bars), `err` (their intervals).

use std::fmt::Write as _;

use crate::report::plots::PlotError;

/// Appends formatted text to an SVG string (writing to a `String` cannot
/// fail).
macro_rules! w {
    ($s:expr, $($arg:tt)*) => {{
        let _ = write!($s, $($arg)*);
    }};
}

/// The series colours of [`crate::report::plots`] (matplotlib's tab10).
const PALETTE: [(u8, u8, u8); 7] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
];

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

const TITLE_SIZE: f64 = 22.0;
const LABEL_SIZE: f64 = 15.0;
const TICK_SIZE: f64 = 13.0;
const GRID: &str = "#e6e6e6";

fn fail(file: &str, message: impl Into<String>) -> PlotError {
    PlotError {
        path: file.to_string(),
        message: message.into(),
    }
}

/// `s` as SVG text: `&`, `<`, `>` and `"` escaped.
fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

fn rgb((r, g, b): (u8, u8, u8)) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

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

/// Rough width of `s` in pixels at font size `size` (sans-serif).
fn text_width(s: &str, size: f64) -> f64 {
    0.58 * size * s.chars().count() as f64
}

/// An SVG document being written.
struct Svg {
    s: String,
}

impl Svg {
    fn new(width: f64, height: f64) -> Svg {
        let mut s = String::new();
        w!(
            s,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" \
             height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" \
             font-family=\"sans-serif\">\n\
             <rect class=\"background\" x=\"0\" y=\"0\" width=\"{width:.0}\" \
             height=\"{height:.0}\" fill=\"#ffffff\"/>\n"
        );
        Svg { s }
    }

    /// Text at (`x`, `y`) (its baseline), `anchor` one of start, middle, end.
    fn text(&mut self, x: f64, y: f64, size: f64, anchor: &str, text: &str) {
        w!(
            self.s,
            "<text x=\"{x:.1}\" y=\"{y:.1}\" font-size=\"{size}\" \
             text-anchor=\"{anchor}\">{}</text>\n",
            esc(text)
        );
    }

    /// Text turned a quarter anticlockwise, centred on (`x`, `y`).
    fn vertical_text(&mut self, x: f64, y: f64, size: f64, text: &str) {
        w!(
            self.s,
            "<text x=\"{x:.1}\" y=\"{y:.1}\" font-size=\"{size}\" text-anchor=\"middle\" \
             transform=\"rotate(-90 {x:.1} {y:.1})\">{}</text>\n",
            esc(text)
        );
    }

    fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), style: &str) {
        w!(
            self.s,
            "<line x1=\"{x0:.2}\" y1=\"{y0:.2}\" x2=\"{x1:.2}\" y2=\"{y1:.2}\" {style}/>\n"
        );
    }

    /// The title, centred at the top of a figure `width` wide, and a note
    /// under it when not empty.
    fn title(&mut self, width: f64, title: &str, note: &str) {
        w!(
            self.s,
            "<text class=\"title\" x=\"{:.1}\" y=\"30\" font-size=\"{TITLE_SIZE}\" \
             text-anchor=\"middle\">{}</text>\n",
            width / 2.0,
            esc(title)
        );
        if !note.is_empty() {
            w!(
                self.s,
                "<text x=\"{:.1}\" y=\"50\" font-size=\"{TICK_SIZE}\" fill=\"#555555\" \
                 text-anchor=\"middle\">{}</text>\n",
                width / 2.0,
                esc(note)
            );
        }
    }

    fn finish(mut self) -> String {
        self.s.push_str("</svg>\n");
        self.s
    }
}

/// One axis: values `lo..hi` onto pixels `a..b` (`a` at `lo`), linear or
/// logarithmic.
#[derive(Debug, Clone, Copy)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    a: f64,
    b: f64,
}

impl Axis {
    fn px(&self, v: f64) -> f64 {
        let t = if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        };
        self.a + t * (self.b - self.a)
    }

    /// Labelled ticks, and unlabelled minor ones (the 2…9 of a log axis's
    /// decades).
    fn ticks(&self) -> (Vec<f64>, Vec<f64>) {
        if !self.log {
            return (linear_ticks(self.lo, self.hi, 6), Vec::new());
        }
        let decades = (self.hi / self.lo).log10();
        let mults: &[f64] = if decades > 2.5 {
            &[1.0]
        } else if decades > 1.0 {
            &[1.0, 2.0, 5.0]
        } else {
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
        };
        let step = if decades > 10.0 {
            (decades / 8.0).ceil() as i32
        } else {
            1
        };
        let first = self.lo.log10().floor() as i32;
        let last = self.hi.log10().ceil() as i32;
        let inside = |v: f64| v >= self.lo * (1.0 - 1e-9) && v <= self.hi * (1.0 + 1e-9);
        let mut major = Vec::new();
        let mut minor = Vec::new();
        for d in first..=last {
            let base = 10f64.powi(d);
            for &m in mults {
                let v = m * base;
                if inside(v) && (m != 1.0 || d.rem_euclid(step) == 0) {
                    major.push(v);
                }
            }
            if mults.len() == 1 && step == 1 {
                minor.extend((2..10).map(|m| f64::from(m) * base).filter(|v| inside(*v)));
            }
        }
        if major.len() < 2 {
            // Less than a decade between two labels: plain ticks read better.
            let linear = linear_ticks(self.lo, self.hi, 5);
            major = linear.into_iter().filter(|v| *v > 0.0).collect();
            minor.clear();
        }
        (major, minor)
    }
}

/// About `count` round values (1, 2 or 5 × 10ⁿ apart) in `lo..=hi`.
fn linear_ticks(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return vec![lo];
    }
    let raw = span / count.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let norm = raw / mag;
    let step = mag
        * if norm < 1.5 {
            1.0
        } else if norm < 3.0 {
            2.0
        } else if norm < 7.0 {
            5.0
        } else {
            10.0
        };
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            if v.abs() < step * 1e-9 { 0.0 } else { v }
        })
        .collect()
}

/// Tick labels that read alike along one axis: plain decimals, or `2.5e-4`
/// style where the values are large or small; at most `digits` significant
/// digits.
fn tick_labels(values: &[f64], digits: usize) -> Vec<String> {
    let biggest = values.iter().fold(0f64, |m, v| m.max(v.abs()));
    let smallest = values
        .iter()
        .filter(|v| **v != 0.0)
        .fold(f64::INFINITY, |m, v| m.min(v.abs()));
    let scientific = biggest >= 1e5 || smallest < 1e-3;
    values
        .iter()
        .map(|&v| {
            if v == 0.0 {
                "0".to_string()
            } else if scientific {
                let s = format!("{:.*e}", digits.saturating_sub(1), v);
                match s.split_once('e') {
                    Some((m, e)) if m.contains('.') => {
                        format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
                    }
                    _ => s,
                }
            } else {
                let magnitude = v.abs().log10().floor() as i64;
                let decimals = (digits as i64 - 1 - magnitude).clamp(0, 8) as usize;
                let s = format!("{v:.decimals$}");
                if s.contains('.') {
                    s.trim_end_matches('0').trim_end_matches('.').to_string()
                } else {
                    s
                }
            }
        })
        .collect()
}

/// Labels for `values`, every one kept where they fit in `room` pixels
/// along the axis, else every k-th (the others empty); `across` says the
/// labels sit side by side (an x axis), else one above another.
fn thinned_labels(values: &[f64], room: f64, across: bool) -> Vec<String> {
    let labels = tick_labels(values, 3);
    let each = if across {
        labels
            .iter()
            .map(|l| text_width(l, TICK_SIZE))
            .fold(0.0, f64::max)
            + 10.0
    } else {
        TICK_SIZE + 6.0
    };
    let fit = (room / each).floor().max(1.0) as usize;
    let k = labels.len().div_ceil(fit).max(1);
    labels
        .into_iter()
        .enumerate()
        .map(|(i, l)| if i % k == 0 { l } else { String::new() })
        .collect()
}

/// The frame of the plot area, its grid, ticks, tick labels and axis names.
/// `x_ticks`/`y_ticks` hold the labelled ticks and their labels (an empty
/// label: a tick without text), `x_minor`/`y_minor` the unlabelled ones;
/// `grid` draws light lines across the plot at the labelled ticks.
struct Frame<'a> {
    x: Axis,
    y: Axis,
    x_ticks: Vec<(f64, String)>,
    x_minor: Vec<f64>,
    y_ticks: Vec<(f64, String)>,
    y_minor: Vec<f64>,
    x_name: &'a str,
    y_name: &'a str,
    grid: bool,
}

impl Frame<'_> {
    fn left(&self) -> f64 {
        self.x.a.min(self.x.b)
    }
    fn right(&self) -> f64 {
        self.x.a.max(self.x.b)
    }
    fn top(&self) -> f64 {
        self.y.a.min(self.y.b)
    }
    fn bottom(&self) -> f64 {
        self.y.a.max(self.y.b)
    }

    /// The grid, drawn before the data.
    fn grid(&self, svg: &mut Svg) {
        if !self.grid {
            return;
        }
        let style = format!("stroke=\"{GRID}\" stroke-width=\"1\"");
        let minor = "stroke=\"#f3f3f3\" stroke-width=\"1\"";
        for &v in &self.x_minor {
            let p = self.x.px(v);
            svg.line((p, self.top()), (p, self.bottom()), minor);
        }
        for &v in &self.y_minor {
            let p = self.y.px(v);
            svg.line((self.left(), p), (self.right(), p), minor);
        }
        for (v, _) in &self.x_ticks {
            let p = self.x.px(*v);
            svg.line((p, self.top()), (p, self.bottom()), &style);
        }
        for (v, _) in &self.y_ticks {
            let p = self.y.px(*v);
            svg.line((self.left(), p), (self.right(), p), &style);
        }
    }

    /// The frame, ticks and names, drawn after the data.
    fn axes(&self, svg: &mut Svg) {
        let (l, r, t, b) = (self.left(), self.right(), self.top(), self.bottom());
        w!(
            svg.s,
            "<rect class=\"frame\" x=\"{l:.2}\" y=\"{t:.2}\" width=\"{:.2}\" \
             height=\"{:.2}\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1\"/>\n",
            r - l,
            b - t
        );
        let black = "stroke=\"#000000\" stroke-width=\"1\"";
        for &v in &self.x_minor {
            let p = self.x.px(v);
            svg.line((p, b), (p, b + 3.0), black);
        }
        for &v in &self.y_minor {
            let p = self.y.px(v);
            svg.line((l - 3.0, p), (l, p), black);
        }
        for (v, label) in &self.x_ticks {
            let p = self.x.px(*v);
            svg.line((p, b), (p, b + 6.0), black);
            if !label.is_empty() {
                svg.text(p, b + 20.0, TICK_SIZE, "middle", label);
            }
        }
        let mut widest: f64 = 0.0;
        for (v, label) in &self.y_ticks {
            let p = self.y.px(*v);
            svg.line((l - 6.0, p), (l, p), black);
            if !label.is_empty() {
                svg.text(l - 9.0, p + 4.5, TICK_SIZE, "end", label);
                widest = widest.max(text_width(label, TICK_SIZE));
            }
        }
        if !self.x_name.is_empty() {
            svg.text((l + r) / 2.0, b + 44.0, LABEL_SIZE, "middle", self.x_name);
        }
        if !self.y_name.is_empty() {
            svg.vertical_text(l - widest - 22.0, (t + b) / 2.0, LABEL_SIZE, self.y_name);
        }
    }
}

/// `(lo, hi)` of the finite values, or None.
fn finite_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for v in values {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// `lo..hi` widened by `pad` of its span each side (a factor on a log
/// axis); a single value widened to a readable span around it.
fn padded(lo: f64, hi: f64, log: bool, pad: f64) -> (f64, f64) {
    if log {
        if hi / lo < 1.0 + 1e-9 {
            return (lo / 2.0, hi * 2.0);
        }
        let f = (hi / lo).powf(pad);
        return (lo / f, hi * f);
    }
    let span = hi - lo;
    if span <= 1e-12 * lo.abs().max(hi.abs()) {
        let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - half, hi + half);
    }
    (lo - pad * span, hi + pad * span)
}

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
        svg.text(
            (frame.left() + frame.right()) / 2.0,
            (frame.top() + frame.bottom()) / 2.0,
            LABEL_SIZE,
            "middle",
            "no finite values to draw",
        );
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
        svg.text(
            (frame.left() + frame.right()) / 2.0,
            (frame.top() + frame.bottom()) / 2.0,
            LABEL_SIZE,
            "middle",
            "no finite values to draw",
        );
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
    use super::*;

    /// The document's body reads as one SVG element.
    fn assert_svg(svg: &str) {
        let body = svg.trim();
        let body = match body.strip_prefix("<?xml") {
            Some(rest) => rest.split_once("?>").unwrap().1.trim_start(),
            None => body,
        };
        assert!(body.starts_with("<svg"), "{}", &body[..body.len().min(80)]);
        assert!(body.ends_with("</svg>"));
        assert_eq!(body.matches("<svg").count(), 1);
    }

    fn count(svg: &str, what: &str) -> usize {
        svg.matches(what).count()
    }

    fn logspace(a: f64, b: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| a * (b / a).powf(k as f64 / (n - 1) as f64))
            .collect()
    }

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

    fn example_bars() -> Vec<IndexBar<'static>> {
        vec![
            IndexBar {
                name: "stiffness",
                first: 0.62,
                first_95: [0.55, 0.69],
                total: 0.71,
                total_95: [0.64, 0.79],
            },
            IndexBar {
                name: "damping",
                first: 0.18,
                first_95: [0.12, 0.25],
                total: 0.27,
                total_95: [0.2, 0.33],
            },
            IndexBar {
                name: "mass",
                first: -0.01,
                first_95: [-0.04, 0.02],
                total: 0.03,
                total_95: [0.01, 0.05],
            },
        ]
    }

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

    #[test]
    fn tick_labels_read_alike_along_an_axis() {
        assert_eq!(tick_labels(&[0.0, 0.2, 0.4], 4), ["0", "0.2", "0.4"]);
        assert_eq!(tick_labels(&[1e3, 1e4, 1e5], 3), ["1e3", "1e4", "1e5"]);
        assert_eq!(tick_labels(&[2.5e-4, 5e-4], 3), ["2.5e-4", "5e-4"]);
        assert_eq!(
            tick_labels(&[1000.0, 2000.0, 5000.0], 3),
            ["1000", "2000", "5000"]
        );
        let t = linear_ticks(0.0, 1.03, 6);
        assert_eq!(t, [0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
    }

    /// Writes one picture of each kind to the temporary folder, to look at.
    #[test]
    fn example_pictures_are_written_to_the_temporary_folder() {
        let x = logspace(1e3, 1e5, 13);
        let mut lines = Vec::new();
        let mut data = Vec::new();
        for (k, gain) in [1.0, 1.5, 2.2].iter().enumerate() {
            let mid: Vec<f64> = x
                .iter()
                .map(|x| gain * 10.0 / (1.0 + (x / 1e4).powf(1.5)) + k as f64)
                .collect();
            let mut lo: Vec<f64> = mid.iter().map(|m| m * 0.85 - 0.2).collect();
            let hi: Vec<f64> = mid.iter().map(|m| m * 1.15 + 0.2).collect();
            if k == 1 {
                lo[6] = f64::NAN;
            }
            data.push((mid, lo, hi));
        }
        let labels = ["soft fixture", "standard fixture", "stiff fixture"];
        for (k, (mid, lo, hi)) in data.iter().enumerate() {
            lines.push(BandLine {
                label: labels[k],
                x: &x,
                mid,
                lo: Some(lo),
                hi: Some(hi),
            });
        }
        let band = band_svg(
            "Overshoot against load-cell stiffness",
            "load cell stiffness (N/m)",
            "overshoot (%)",
            true,
            &lines,
        )
        .unwrap();
        let xs = logspace(1e3, 1e5, 9);
        let ys: Vec<f64> = (0..7).map(|k| 0.02 + 0.03 * k as f64).collect();
        let mut z: Vec<Vec<f64>> = ys
            .iter()
            .map(|zeta| {
                xs.iter()
                    .map(|k| {
                        100.0
                            * (-std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp()
                            * (k / 1e5).powf(0.6)
                    })
                    .collect()
            })
            .collect();
        z[3][4] = f64::NAN;
        let heat = heat_map_svg(
            "Ringing over stiffness and damping",
            "load cell stiffness (N/m)",
            "damping ratio",
            "ringing (%)",
            &xs,
            &ys,
            &z,
            true,
            false,
            Some(10.0),
        )
        .unwrap();
        let indices =
            indices_svg("Sobol indices of overshoot", "overshoot", &example_bars()).unwrap();
        let dir = std::env::temp_dir();
        for (name, svg) in [
            ("rigfit_picture_band.svg", band),
            ("rigfit_picture_heat_map.svg", heat),
            ("rigfit_picture_indices.svg", indices),
        ] {
            assert_svg(&svg);
            let path = dir.join(name);
            std::fs::write(&path, svg).unwrap();
            println!("{}", path.display());
        }
    }
}
