//! `summary.html`: the series' table and each parameter against each
//! numeric covariate, in the report's style (its stylesheet inlined, its
//! generator tag, no script). The figures are SVG drawn here: one point per
//! done test, its 95 % interval as an error bar.

use std::fmt::Write as _;

use super::{ParamCell, Summary, SummaryParameter, SummaryRow, SummaryState};
use crate::report::html::GENERATOR;
use crate::report::html::page::{STYLE, esc, num};

/// What the series page adds to the report's style.
const EXTRA_STYLE: &str = "\
.wide { overflow-x: auto; }
table#tests td, table#tests th { padding: 4px 8px; }
tr.failed th, tr.failed td { background: #fbeeee; }
tr.missing th, tr.missing td, tr.interrupted th, tr.interrupted td { background: #fbf6e6; }
td.notes { min-width: 22em; }
td.notes.error { color: #8a1c1c; }
span.iv { color: var(--muted); font-size: 12px; }
.plots { display: grid; grid-template-columns: repeat(auto-fill, minmax(380px, 1fr)); gap: 8px 20px; }
svg .errbar { stroke: var(--accent); stroke-width: 1.4; }
svg .errbar.open { stroke-dasharray: 3 2; }
svg .pt { fill: var(--ink); }
";

/// Width and height of a figure's view box, and its plot area.
const W: f64 = 420.0;
const H: f64 = 260.0;
const LEFT: f64 = 88.0;
const RIGHT: f64 = 12.0;
const TOP: f64 = 12.0;
const BOTTOM: f64 = 44.0;

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "—".into(), num)
}

/// `s` as the path part of a relative link: characters that would end or
/// change it percent-encoded.
fn href(s: &str) -> String {
    let mut out = String::new();
    for b in s.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

pub(super) fn html(s: &Summary) -> String {
    let title = format!("rigfit series: {}", s.name);
    let mut h = String::with_capacity(1 << 16);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n{GENERATOR}\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{t}</title>\n<style>\n{STYLE}{EXTRA_STYLE}</style>\n</head>\n<body>\n<header><h1>{t}</h1><p class=\"sub\">{} tests: {}</p>\n\
         <nav><a href=\"#tests\">Tests</a> <a href=\"#figures\">Parameters against covariates</a></nav>\n</header>\n<main>\n",
        s.rows.len(),
        esc(&s.counts()),
        t = esc(&title),
    );
    tests(&mut h, s);
    figures(&mut h, s);
    let _ = write!(
        h,
        "</main>\n<footer>Written by rigfit {} from the files of this series' folder (series.json, status/, each test's result.json); \
         rebuilt with <code>rigfit series DIR --summary</code>.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}

fn tests(h: &mut String, s: &Summary) {
    h.push_str("<section id=\"tests\">\n<h2>Tests</h2>\n");
    let _ = writeln!(h, "<p class=\"verdict\">{}</p>", esc(&s.counts()));
    if s.rows.iter().any(|r| r.state != SummaryState::Done) {
        h.push_str("<p class=\"note\">Tests not done keep their row, with why: failed (the error), interrupted (running it again resumes it), missing (not run yet, still running, or run with an earlier campaign).</p>\n");
    }
    h.push_str("<div class=\"wide\"><table id=\"tests\" class=\"data\"><thead><tr><th>Test</th>");
    for c in &s.covariates {
        let _ = write!(h, "<th>{}</th>", esc(c));
    }
    h.push_str("<th>Status</th>");
    for p in &s.parameters {
        let unit = if p.unit.is_empty() {
            String::new()
        } else {
            format!(" ({})", esc(&p.unit))
        };
        let _ = write!(h, "<th class=\"num\">{}{unit}</th>", esc(&p.name));
    }
    h.push_str("<th class=\"num\">R²</th><th class=\"num\">Cost / noise floor</th><th class=\"num\">Wall time (s)</th><th>Ran on</th><th>Error or flags</th></tr></thead><tbody>\n");
    for r in &s.rows {
        row(h, s, r);
    }
    h.push_str("</tbody></table></div>\n<p class=\"note\">Each parameter's cell: its value, and below it the 95 % interval (the profile likelihood's where computed, else the covariance's; — on an open side). The test's name links to its report.</p>\n</section>\n");
}

fn row(h: &mut String, s: &Summary, r: &SummaryRow) {
    let name = match &r.report {
        Some(link) => format!("<a href=\"{}\">{}</a>", esc(&href(link)), esc(&r.id)),
        None => esc(&r.id),
    };
    let _ = write!(
        h,
        "<tr class=\"{}\"><th scope=\"row\">{name}</th>",
        r.state.as_str()
    );
    for i in 0..s.covariates.len() {
        let _ = write!(
            h,
            "<td>{}</td>",
            esc(r.covariates.get(i).map_or("", String::as_str))
        );
    }
    let _ = write!(h, "<td>{}</td>", r.state.as_str());
    for c in &r.parameters {
        let iv = match (c.interval, c.lower, c.upper) {
            (None, ..) => String::new(),
            (Some(k), lo, hi) => format!(
                "<br><span class=\"iv\" title=\"{}\">[{}, {}]</span>",
                k.as_str(),
                opt(lo),
                opt(hi)
            ),
        };
        let _ = write!(
            h,
            "<td class=\"num\">{}{iv}</td>",
            if c.value.is_some() {
                opt(c.value)
            } else {
                String::new()
            }
        );
    }
    let ran: Vec<&str> = [&r.backend, &r.device, &r.host]
        .into_iter()
        .filter_map(|v| v.as_deref())
        .collect();
    let mut note = match (r.state, &r.error) {
        (SummaryState::Done, _) => esc(&r.flags.join("; ")),
        (_, Some(e)) => esc(e),
        (_, None) => String::new(),
    };
    if !r.warnings.is_empty() {
        let items: String = r
            .warnings
            .iter()
            .map(|w| format!("<li>{}</li>", esc(w)))
            .collect();
        let _ = write!(
            note,
            "<details><summary>{} warning{}</summary><ul class=\"warnings\">{items}</ul></details>",
            r.warnings.len(),
            if r.warnings.len() == 1 { "" } else { "s" }
        );
    }
    let class = if r.state == SummaryState::Done {
        "notes"
    } else {
        "notes error"
    };
    let _ = writeln!(
        h,
        "<td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td><td class=\"{class}\">{note}</td></tr>",
        opt(r.r2),
        opt(r.noise_floor_ratio),
        opt(r.wall_time_s),
        esc(&ran.join(" · ")),
    );
}

/// The covariates whose every test's value is a finite number, with the
/// values.
fn numeric_covariates(s: &Summary) -> Vec<(usize, Vec<f64>)> {
    (0..s.covariates.len())
        .filter_map(|i| {
            let xs: Option<Vec<f64>> = s
                .rows
                .iter()
                .map(|r| {
                    r.covariates
                        .get(i)?
                        .trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                })
                .collect();
            xs.filter(|x| !x.is_empty()).map(|x| (i, x))
        })
        .collect()
}

fn figures(h: &mut String, s: &Summary) {
    h.push_str("<section id=\"figures\">\n<h2>Parameters against covariates</h2>\n");
    let numeric = numeric_covariates(s);
    if numeric.is_empty() {
        h.push_str("<p>No covariate is a number in every test, so none is plotted.</p>\n");
    } else if s.parameters.is_empty() {
        h.push_str("<p>No test is done, so there is no parameter to plot.</p>\n");
    }
    for (i, xs) in &numeric {
        if s.parameters.is_empty() {
            break;
        }
        let _ = writeln!(
            h,
            "<h3>Against {}</h3>\n<div class=\"plots\">",
            esc(&s.covariates[*i])
        );
        for (j, p) in s.parameters.iter().enumerate() {
            let points: Vec<(f64, &ParamCell)> = s
                .rows
                .iter()
                .zip(xs)
                .filter(|(r, _)| r.state == SummaryState::Done)
                .filter_map(|(r, &x)| {
                    let c = r.parameters.get(j)?;
                    c.value.filter(|v| v.is_finite()).map(|_| (x, c))
                })
                .collect();
            figure(h, &s.covariates[*i], p, &points, s.rows.len());
        }
        h.push_str("</div>\n");
    }
    h.push_str("</section>\n");
}

/// A value's position on an axis from `lo` to `hi` drawn from pixel `a` to
/// pixel `b` (on the log of the value for a log axis).
#[derive(Clone, Copy)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    a: f64,
    b: f64,
}

impl Axis {
    fn t(&self, v: f64) -> f64 {
        if self.log { v.ln() } else { v }
    }

    fn px(&self, v: f64) -> f64 {
        let (lo, hi) = (self.t(self.lo), self.t(self.hi));
        self.a + (self.t(v) - lo) / (hi - lo) * (self.b - self.a)
    }

    /// The axis over `values` (finite, and positive where `log`), padded by
    /// 5 %; a single value gets a span around it.
    fn over(values: &[f64], log: bool, a: f64, b: f64) -> Axis {
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (lo, hi) = if log {
            let (l, h) = (lo.ln(), hi.ln());
            let pad = if h > l {
                0.05 * (h - l)
            } else {
                std::f64::consts::LN_2
            };
            ((l - pad).exp(), (h + pad).exp())
        } else {
            let pad = if hi > lo {
                0.05 * (hi - lo)
            } else {
                (0.1 * lo.abs()).max(1e-12)
            };
            (lo - pad, hi + pad)
        };
        Axis { lo, hi, log, a, b }
    }

    fn ticks(&self) -> Vec<f64> {
        if self.log {
            let (a, b) = (
                self.lo.log10().ceil() as i32,
                self.hi.log10().floor() as i32,
            );
            if b - a >= 1 {
                let step = ((b - a) / 6 + 1) as usize;
                return (a..=b).step_by(step).map(|e| 10f64.powi(e)).collect();
            }
        }
        let raw = (self.hi - self.lo) / 5.0;
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * mag)
            .find(|s| *s >= raw)
            .unwrap_or(10.0 * mag);
        let mut v = (self.lo / step).ceil() * step;
        let mut out = Vec::new();
        while v <= self.hi && out.len() < 12 {
            out.push(if v.abs() < step * 1e-9 { 0.0 } else { v });
            v += step;
        }
        out
    }
}

/// A tick's label: 5 significant digits, powers of ten beyond `[1e-3, 1e6)`.
fn tick(v: f64) -> String {
    let r: f64 = format!("{v:.4e}").parse().unwrap_or(v);
    if r == 0.0 || (1e-3..1e6).contains(&r.abs()) {
        r.to_string().replace('-', "−")
    } else {
        format!("{r:e}").replace('-', "−")
    }
}

fn figure(
    h: &mut String,
    covariate: &str,
    p: &SummaryParameter,
    points: &[(f64, &ParamCell)],
    tests: usize,
) {
    let unit = if p.unit.is_empty() {
        String::new()
    } else {
        format!(" ({})", p.unit)
    };
    if points.is_empty() {
        let _ = writeln!(
            h,
            "<p class=\"note\">{}: no done test has a value to plot against {}.</p>",
            esc(&p.name),
            esc(covariate)
        );
        return;
    }
    let xs: Vec<f64> = points.iter().map(|(x, _)| *x).collect();
    let log_x = xs.iter().all(|x| *x > 0.0) && {
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, u), x| (l.min(*x), u.max(*x)));
        hi / lo >= 100.0
    };
    // The bounds (where known, widened to hold every value: a test's own
    // bounds may differ) clip the intervals, so that an undetermined one
    // does not flatten the points; its bar then runs to the edge, dashed.
    let values = points.iter().filter_map(|(_, c)| c.value);
    let (vlo, vhi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), v| {
        (l.min(v), u.max(v))
    });
    let [blo, bhi] = p.bounds.unwrap_or([None, None]);
    let (blo, bhi) = (blo.map(|b| b.min(vlo)), bhi.map(|b| b.max(vhi)));
    let clip = |v: f64| {
        let v = blo.map_or(v, |b| v.max(b));
        bhi.map_or(v, |b| v.min(b))
    };
    let mut ys: Vec<f64> = Vec::new();
    for (_, c) in points {
        ys.extend(
            [c.value, c.lower, c.upper]
                .into_iter()
                .flatten()
                .filter(|v| v.is_finite())
                .map(clip),
        );
    }
    let log_y = p.log && ys.iter().all(|y| *y > 0.0);
    let x = Axis::over(&xs, log_x, LEFT, W - RIGHT);
    let y = Axis::over(&ys, log_y, H - BOTTOM, TOP);
    let label = format!(
        "{}{unit} against {covariate}: {} of {tests} tests, each value with its 95 % interval as an error bar",
        p.name,
        points.len()
    );
    let _ = write!(
        h,
        "<figure class=\"series-plot\">\n<svg class=\"scatter\" role=\"img\" aria-label=\"{}\" viewBox=\"0 0 {W} {H}\">\n<g class=\"grid\">",
        esc(&label)
    );
    let mut labels = String::new();
    for t in x.ticks() {
        let px = x.px(t);
        let _ = write!(
            h,
            "<line x1=\"{px:.1}\" y1=\"{TOP}\" x2=\"{px:.1}\" y2=\"{:.1}\"/>",
            H - BOTTOM
        );
        let _ = write!(
            labels,
            "<text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            H - BOTTOM + 15.0,
            tick(t)
        );
    }
    for t in y.ticks() {
        let py = y.px(t);
        let _ = write!(
            h,
            "<line x1=\"{LEFT}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\"/>",
            W - RIGHT
        );
        let _ = write!(
            labels,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            LEFT - 5.0,
            py + 4.0,
            tick(t)
        );
    }
    let _ = write!(
        h,
        "</g>\n<rect class=\"box\" x=\"{LEFT}\" y=\"{TOP}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\"/>\n{labels}\n",
        W - LEFT - RIGHT,
        H - TOP - BOTTOM
    );
    h.push_str("<g class=\"bars\">");
    for (xv, c) in points {
        let px = x.px(*xv);
        let end =
            |v: Option<f64>, edge: f64| match v.filter(|v| v.is_finite() && (!log_y || *v > 0.0)) {
                Some(v) if clip(v) == v => (y.px(v), true),
                Some(v) => (y.px(clip(v)), false),
                None => (edge, false),
            };
        if c.interval.is_none() {
            continue;
        }
        let (lo, lo_closed) = end(c.lower, y.a);
        let (hi, hi_closed) = end(c.upper, y.b);
        let open = if lo_closed && hi_closed { "" } else { " open" };
        let _ = write!(
            h,
            "<line class=\"errbar{open}\" x1=\"{px:.1}\" y1=\"{lo:.1}\" x2=\"{px:.1}\" y2=\"{hi:.1}\"/>"
        );
        for (py, closed) in [(lo, lo_closed), (hi, hi_closed)] {
            if closed {
                let _ = write!(
                    h,
                    "<line class=\"errbar cap\" x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\"/>",
                    px - 4.0,
                    px + 4.0
                );
            }
        }
    }
    h.push_str("</g>\n<g class=\"points\">");
    for (xv, c) in points {
        let v = c.value.unwrap_or_default();
        let (px, py) = (x.px(*xv), y.px(v));
        let _ = write!(
            h,
            "<circle class=\"pt\" cx=\"{px:.1}\" cy=\"{py:.1}\" r=\"3.5\"><title>{} = {}: {} [{}, {}]</title></circle>",
            esc(covariate),
            tick(*xv),
            tick(v),
            c.lower.map_or_else(|| "—".into(), tick),
            c.upper.map_or_else(|| "—".into(), tick),
        );
    }
    let _ = write!(
        h,
        "</g>\n<text class=\"label\" x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}{}</text>\
         <text class=\"label\" transform=\"translate(13 {:.1}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n</svg>\n",
        (LEFT + W - RIGHT) / 2.0,
        H - 6.0,
        esc(covariate),
        if log_x { " (log axis)" } else { "" },
        (TOP + H - BOTTOM) / 2.0,
        esc(&format!("{}{unit}", p.name))
    );
    let _ = writeln!(
        h,
        "<figcaption><b>{}</b> against {}: {} of {tests} tests (the done ones); bars: 95 % intervals (profile where computed, else covariance), dashed where open or beyond the bounds{}.</figcaption>\n</figure>",
        esc(&p.name),
        esc(covariate),
        points.len(),
        if log_y { "; log axis" } else { "" }
    );
}
