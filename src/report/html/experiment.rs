//! An experiment's part of the page (or a validation record's): the fit
//! table's row, and the frames of its fit, residual and spectrum figures
//! (the time figures with their zoom buttons and visible range).

use std::fmt::Write as _;

use super::input::{FitCsv, ResultFile};
use super::page::{esc, num, opt};

/// What the page shows of one experiment (or validation record).
pub(super) struct Shown {
    pub(super) name: String,
    pub(super) csv: FitCsv,
}

/// A time figure's frame: zoom buttons, the SVG the script draws into, the caption.
fn time_figure(
    h: &mut String,
    src: &str,
    i: usize,
    kind: &str,
    label: &str,
    caption: &str,
    t: [f64; 2],
) {
    let _ = write!(
        h,
        "<figure class=\"time\" data-from=\"{src}\" data-index=\"{i}\" data-kind=\"{kind}\" data-t0=\"{}\" data-t1=\"{}\">\n\
         <div class=\"zoom\" role=\"group\" aria-label=\"time axis\"><button type=\"button\" data-zoom=\"in\">Zoom in</button>\
         <button type=\"button\" data-zoom=\"out\">Zoom out</button><button type=\"button\" data-zoom=\"reset\">Whole record</button></div>\n\
         <svg role=\"img\" aria-label=\"{}\" viewBox=\"0 0 900 300\"></svg>\n<figcaption>{caption}</figcaption>\n</figure>\n",
        t[0],
        t[1],
        esc(label)
    );
}

pub(super) fn experiments(
    h: &mut String,
    r: &ResultFile,
    shown: &[Shown],
    id: &str,
    heading: &str,
    modes: &dyn Fn(&str) -> Vec<f64>,
) {
    let src = if id == "experiments" {
        "experiments"
    } else {
        "validation"
    };
    let prefix = if id == "experiments" { "exp" } else { "val" };
    if id == "experiments" {
        let _ = writeln!(h, "<section id=\"{id}\">\n<h2>{heading}</h2>");
        h.push_str("<table class=\"data\"><thead><tr><th>Experiment</th><th class=\"num\">Samples</th><th class=\"num\">R²</th><th class=\"num\">1 − R²</th>\
                    <th class=\"num\">Residual RMS</th><th class=\"num\">Noise estimate</th><th class=\"num\">Cost / noise floor</th></tr></thead><tbody>\n");
        for s in shown {
            let e = r.experiments.iter().find(|e| e.name == s.name);
            let (r2, rms) = fit_numbers(&s.csv);
            let unit = s
                .csv
                .of_kind("measured")
                .next()
                .map_or("", |c| c.unit.as_str());
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                 <td class=\"num\">{} {}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
                esc(&s.name),
                s.csv.t.len(),
                num(e.and_then(|e| e.r2).unwrap_or(r2)),
                num(e.and_then(|e| e.one_minus_r2).unwrap_or(1.0 - r2)),
                num(e.and_then(|e| e.residual_rms).unwrap_or(rms)),
                esc(unit),
                opt(e.and_then(|e| e.noise_estimate)),
                opt(e.and_then(|e| e.cost_over_noise_floor)),
            );
        }
        h.push_str("</tbody></table>\n");
    }
    for (i, s) in shown.iter().enumerate() {
        let unit = s
            .csv
            .of_kind("measured")
            .next()
            .map_or("", |c| c.unit.as_str());
        let measured = s
            .csv
            .of_kind("measured")
            .next()
            .map_or("", |c| c.name.as_str());
        let t = [
            s.csv.t.first().copied().unwrap_or(0.0),
            s.csv.t.last().copied().unwrap_or(1.0),
        ];
        let _ = writeln!(
            h,
            "<section class=\"experiment\" id=\"{prefix}-{i}\">\n<h3>{}</h3>",
            esc(&s.name)
        );
        let name = esc(&s.name);
        time_figure(
            h,
            src,
            i,
            "fit",
            &format!("{name}: measured {measured} and the model's outputs in {unit} against time"),
            &format!(
                "<b>{name}</b>: the measured {} and the model ({unit}); the shaded span is the fit window. \
                      Wheel to zoom, drag to pan.",
                esc(measured)
            ),
            t,
        );
        time_figure(
            h,
            src,
            i,
            "residual",
            &format!("{name}: residual (model − measured) in {unit} against time"),
            &format!(
                "<b>{name}</b>: residual, model − measured ({unit}), on the same time range as the fit."
            ),
            t,
        );
        let hz = modes(&s.name);
        let listed: Vec<String> = hz.iter().map(|f| format!("{} Hz", num(*f))).collect();
        let _ = write!(
            h,
            "<figure class=\"spectrum\" data-from=\"{src}\" data-index=\"{i}\" data-kind=\"spectrum\">\n\
             <svg role=\"img\" aria-label=\"{name}: amplitude spectrum of the residual over the fit window, with the rig's natural frequencies marked\" viewBox=\"0 0 900 260\"></svg>\n\
             <figcaption><b>{name}</b>: amplitude spectrum of the residual over the fit window ({unit}; Welch, Hann window). \
             Dashed: the rig's undamped natural frequencies at the fitted values{}.</figcaption>\n</figure>\n",
            if listed.is_empty() {
                " (none in result.json)".to_string()
            } else {
                format!(": {}", listed.join(", "))
            }
        );
        h.push_str("</section>\n");
    }
    if id == "experiments" {
        h.push_str("</section>\n");
    }
}

/// R² and the residual's RMS over the fit window, from the full CSV.
fn fit_numbers(csv: &FitCsv) -> (f64, f64) {
    let (Some(m), Some(res)) = (
        csv.of_kind("measured").next(),
        csv.of_kind("residual").next(),
    ) else {
        return (f64::NAN, f64::NAN);
    };
    let scored = |v: &'_ [f64]| -> Vec<f64> {
        v.iter()
            .zip(&csv.in_fit_window)
            .filter(|(_, w)| **w)
            .map(|(x, _)| *x)
            .collect()
    };
    let (m, res) = (scored(&m.values), scored(&res.values));
    let n = m.len() as f64;
    let mean = m.iter().sum::<f64>() / n;
    let ss_tot: f64 = m.iter().map(|x| (x - mean).powi(2)).sum();
    let ss_res: f64 = res.iter().map(|x| x * x).sum();
    (1.0 - ss_res / ss_tot, (ss_res / n).sqrt())
}
