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
    /// The note in the middle of a plot with nothing finite to draw.
    fn say_nothing_to_draw(&self, svg: &mut Svg) {
        svg.text(
            (self.left() + self.right()) / 2.0,
            (self.top() + self.bottom()) / 2.0,
            LABEL_SIZE,
            "middle",
            "no finite values to draw",
        );
    }

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

mod band;
mod heat_map;
mod indices;

pub use band::{BandLine, band_svg};
pub use heat_map::heat_map_svg;
pub use indices::{IndexBar, indices_svg};

#[cfg(test)]
mod tests {
    use super::*;

    /// The document's body reads as one SVG element.
    pub(super) fn assert_svg(svg: &str) {
        let body = svg.trim();
        let body = match body.strip_prefix("<?xml") {
            Some(rest) => rest.split_once("?>").unwrap().1.trim_start(),
            None => body,
        };
        assert!(body.starts_with("<svg"), "{}", &body[..body.len().min(80)]);
        assert!(body.ends_with("</svg>"));
        assert_eq!(body.matches("<svg").count(), 1);
    }

    pub(super) fn count(svg: &str, what: &str) -> usize {
        svg.matches(what).count()
    }

    pub(super) fn logspace(a: f64, b: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| a * (b / a).powf(k as f64 / (n - 1) as f64))
            .collect()
    }

    pub(super) fn example_bars() -> Vec<IndexBar<'static>> {
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
