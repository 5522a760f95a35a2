//! The parameter table: each free parameter's value, bounds, intervals
//! (covariance and profile), whether determined, and a bar showing where the
//! value sits inside its bounds.

use std::fmt::Write as _;

use super::input::{Parameter, ResultFile};
use super::page::{esc, interval, num, opt};

/// Where `value` sits in `bounds`, 0..1 (on the log axis for a log scale).
fn position(p: &Parameter, v: f64) -> Option<f64> {
    let [Some(lo), Some(hi)] = p.bounds? else {
        return None;
    };
    let log = p.scale.as_deref() == Some("log") && lo > 0.0 && v > 0.0;
    let x = if log {
        (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
    } else {
        (v - lo) / (hi - lo)
    };
    x.is_finite().then_some(x.clamp(0.0, 1.0))
}

fn bar(p: &Parameter) -> String {
    let Some(x) = p.value.and_then(|v| position(p, v)) else {
        return String::new();
    };
    let mut s = String::from(
        "<svg class=\"bar\" width=\"100\" height=\"14\" aria-hidden=\"true\"><rect x=\"0\" y=\"5\" width=\"100\" height=\"4\" rx=\"2\" class=\"track\"/>",
    );
    if let Some([lo, hi]) = p.interval_95 {
        let a = lo.and_then(|v| position(p, v)).unwrap_or(0.0);
        let b = hi.and_then(|v| position(p, v)).unwrap_or(1.0);
        let _ = write!(
            s,
            "<rect x=\"{:.1}\" y=\"3\" width=\"{:.1}\" height=\"8\" class=\"ci\"/>",
            a * 100.0,
            ((b - a) * 100.0).max(1.0)
        );
    }
    let _ = write!(
        s,
        "<rect x=\"{:.1}\" y=\"1\" width=\"2\" height=\"12\" class=\"mark\"/></svg>",
        x * 98.0
    );
    s
}

pub(super) fn parameters(h: &mut String, r: &ResultFile) {
    h.push_str("<section id=\"parameters-section\">\n<h2>Parameters</h2>\n");
    let free: Vec<&Parameter> = r.parameters.iter().filter(|p| p.free).collect();
    let profile = |name: &str| {
        let p = r
            .profiles
            .as_ref()?
            .parameters
            .iter()
            .find(|p| p.name == name)?;
        Some(interval(p.interval))
    };
    h.push_str("<table id=\"parameters\" class=\"data\"><thead><tr><th>Name</th><th class=\"num\">Value</th><th>Unit</th><th>Bounds</th>\
                <th class=\"num\">Std. error</th><th class=\"num\">95 % (covariance)</th><th class=\"num\">95 % (profile)</th><th>Determined</th><th class=\"num\">Elite width</th>\
                <th>In bounds</th></tr></thead><tbody>\n");
    for p in &free {
        let determined = match (p.determined, p.at_bound.as_deref()) {
            (_, Some(b)) => format!("at {b} bound"),
            (Some(true), _) => "yes".into(),
            (Some(false), _) => "no".into(),
            (None, _) => "—".into(),
        };
        let note = p
            .uncertainty_note
            .as_deref()
            .map_or_else(String::new, |n| format!(" title=\"{}\"", esc(n)));
        let _ = writeln!(
            h,
            "<tr><th scope=\"row\">{}</th><td class=\"num\" data-value=\"{}\">{}</td><td>{}</td><td class=\"num iv\">{}</td>\
             <td class=\"num\">{}</td><td class=\"num iv\">{}</td><td class=\"num iv\">{}</td><td{note}>{determined}</td>\
             <td class=\"num\">{}</td><td>{}</td></tr>",
            esc(&p.name),
            p.value.map_or_else(String::new, |v| v.to_string()),
            opt(p.value),
            esc(&p.unit),
            p.bounds.map_or_else(|| "—".into(), |b| interval(Some(b))),
            opt(p.std_error),
            interval(p.interval_95),
            profile(&p.name).unwrap_or_else(|| "—".into()),
            p.elite_relative_width
                .map_or_else(|| "—".into(), |w| format!("{} %", num(100.0 * w))),
            bar(p),
        );
    }
    h.push_str("</tbody></table>\n");
    let fixed: Vec<String> = r
        .parameters
        .iter()
        .filter(|p| !p.free)
        .map(|p| format!("{} = {} {}", esc(&p.name), opt(p.value), esc(&p.unit)))
        .collect();
    if !fixed.is_empty() {
        let _ = writeln!(
            h,
            "<details><summary>Fixed parameters ({})</summary><p class=\"fixed\">{}</p></details>",
            fixed.len(),
            fixed.join(" · ")
        );
    }
    h.push_str("<p class=\"note\">The bar shows where the value sits between its bounds (on a log axis for log-scale parameters), the shaded part its 95 % covariance interval.</p>\n</section>\n");
}
