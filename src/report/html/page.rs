//! The page: its sections in the order a reader asks (verdict, summary,
//! experiments, parameters, correlation, convergence, profiles,
//! validation), each with the tables that hold its numbers, and the figures'
//! frames the inline script draws into.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::json;

use super::experiment::{Shown, experiments};
use super::input::{self, ResultFile};
use super::parameters::parameters;
use super::{GENERATOR, ReportError, figures, heatmap};

/// The report's stylesheet, which the series' summary page shares.
pub(crate) const STYLE: &str = include_str!("style.css");
const SCRIPT: &str = include_str!("script.js");

/// `s` with `& < > "` escaped for HTML text and attributes.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number as a table shows it: 6 significant digits, powers of ten
/// written out beyond `[1e-3, 1e6)`; `—` when not finite.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "—".into();
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if (1e-3..1e6).contains(&a) {
        let decimals = (5 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        return s.replace('-', "−");
    }
    let s = format!("{v:.5e}");
    let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.')
    } else {
        m
    };
    format!(
        "{}&#8239;×&#8239;10<sup>{}</sup>",
        m.replace('-', "−"),
        e.replace('-', "−")
    )
}

pub(super) fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "—".into(), num)
}

pub(super) fn interval(i: Option<[Option<f64>; 2]>) -> String {
    match i {
        Some([lo, hi]) => format!("[{}, {}]", opt(lo), opt(hi)),
        None => "—".into(),
    }
}

pub(super) fn build(dir: &Path) -> Result<String, ReportError> {
    let result = input::read_result(dir)?;
    let history = input::read_history(dir)?;
    let none = ResultFile::default();
    let r = result.as_ref().unwrap_or(&none);
    let mut shown = Vec::new();
    if result.is_some() {
        for e in r.experiments.iter().filter(|e| !e.csv.is_empty()) {
            let csv = input::read_fit_csv(&dir.join(&e.csv))?;
            shown.push(Shown {
                name: e.name.clone(),
                csv,
            });
        }
    } else {
        for file in input::csv_files(dir)? {
            // A CSV that is not an experiment's (no measured column) is not shown.
            match input::read_fit_csv(&file) {
                Ok(csv) => shown.push(Shown {
                    name: file
                        .file_stem()
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                    csv,
                }),
                Err(ReportError::Csv { line: 1, .. }) => {}
                Err(e) => return Err(e),
            }
        }
        if shown.is_empty() {
            return Err(ReportError::Empty {
                dir: dir.to_path_buf(),
            });
        }
    }
    let mut validation = Vec::new();
    for v in r.validation.iter().flat_map(|v| &v.experiments) {
        let file = dir.join(&v.csv);
        if !v.csv.is_empty() && file.is_file() {
            validation.push(Shown {
                name: v.name.clone(),
                csv: input::read_fit_csv(&file)?,
            });
        }
    }
    let name = dir
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    Ok(render(
        r,
        result.is_some(),
        history.as_ref(),
        &shown,
        &validation,
        &name,
    ))
}

/// The page of what [`build`] read: `r` (result.json, or what stands in
/// for it when `has_result` is false: CSVs alone), `history`, the
/// experiments and validation records `shown`, and `name` (the title
/// without a campaign).
pub(super) fn render(
    r: &ResultFile,
    has_result: bool,
    history: Option<&input::History>,
    shown: &[Shown],
    validation: &[Shown],
    name: &str,
) -> String {
    let modes = |name: &str| -> Vec<f64> {
        let nf = &r.natural_frequencies_hz;
        nf.iter()
            .find(|n| n.experiment == name)
            .or_else(|| {
                nf.iter()
                    .find(|n| name.split('.').next() == Some(&n.experiment))
            })
            .or(if nf.len() == 1 { nf.first() } else { None })
            .map_or_else(Vec::new, |n| n.hz.clone())
    };
    let floor = r
        .fitness
        .zip(r.verdict.as_ref().and_then(|v| v.cost_over_noise_floor))
        .map(|(f, k)| f / k)
        .filter(|f| f.is_finite() && *f > 0.0);
    let data = json!({
        "experiments": shown.iter().enumerate()
            .map(|(i, s)| figures::experiment(&format!("exp-{i}"), &s.csv, &modes(&s.name)))
            .collect::<Vec<_>>(),
        "validation": validation.iter().enumerate()
            .map(|(i, s)| figures::experiment(&format!("val-{i}"), &s.csv, &modes(&s.name)))
            .collect::<Vec<_>>(),
        "convergence": figures::convergence(history, floor),
        "profiles": r.profiles.iter().flat_map(|p| &p.parameters).map(figures::profile).collect::<Vec<_>>(),
    });

    let title = if r.campaign.is_empty() {
        format!("rigfit: {name}")
    } else {
        format!("rigfit: {}", r.campaign)
    };
    let mut h = String::with_capacity(1 << 20);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n{GENERATOR}\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n<header><h1>{}</h1><p class=\"sub\">{}</p>\n",
        esc(&title),
        esc(&title),
        esc(&subtitle(r, has_result))
    );
    h.push_str(
        "<nav><a href=\"#verdict\">Verdict</a> <a href=\"#summary\">Summary</a> \
         <a href=\"#experiments\">Experiments</a> <a href=\"#parameters-section\">Parameters</a> \
         <a href=\"#correlation\">Correlation</a> <a href=\"#convergence\">Convergence</a> \
         <a href=\"#profiles\">Profiles</a> <a href=\"#validation\">Validation</a></nav>\n</header>\n<main>\n",
    );
    verdict(&mut h, r, has_result);
    summary(&mut h, r, has_result);
    experiments(&mut h, r, shown, "experiments", "Experiments", &modes);
    parameters(&mut h, r);
    correlation(&mut h, r);
    convergence(&mut h, r, history, floor);
    profiles(&mut h, r);
    validation_section(&mut h, r, validation, &modes);
    let _ = write!(
        h,
        "</main>\n<footer>Written by rigfit {} from the files of this result folder; \
         a result folder's page is rebuilt with <code>rigfit report DIR</code>.</footer>\n",
        esc(&r.rigfit_version)
    );
    let text = serde_json::to_string(&data).unwrap_or_else(|_| "{}".into());
    let _ = write!(
        h,
        "<script type=\"application/json\" id=\"rigfit-data\">{}</script>\n<script>\n{SCRIPT}</script>\n</body>\n</html>\n",
        text.replace("</", "<\\/")
    );
    h
}

fn subtitle(r: &ResultFile, has_result: bool) -> String {
    if !has_result {
        return "the model at fixed values against the record (no calibration result)".into();
    }
    let method = r.search_method.clone().unwrap_or_else(|| "GA".into());
    format!(
        "rig {} · {} search · {} on {}",
        r.rig, method, r.precision, r.backend
    )
}

fn verdict(h: &mut String, r: &ResultFile, has_result: bool) {
    h.push_str("<section id=\"verdict\">\n<h2>Verdict</h2>\n");
    match r.verdict.as_ref().filter(|v| !v.line.is_empty()) {
        Some(v) => {
            let _ = writeln!(h, "<p class=\"verdict\">{}</p>", esc(&v.line));
        }
        None if has_result => h.push_str("<p class=\"verdict\">result.json gives no verdict.</p>\n"),
        None => h.push_str("<p class=\"verdict\">No calibration result: the page shows the model against the record.</p>\n"),
    }
    let flags = r.verdict.iter().flat_map(|v| &v.flags);
    let all: Vec<&String> = flags.chain(&r.warnings).collect();
    if all.is_empty() {
        h.push_str(if has_result {
            "<p class=\"ok\">Nothing flagged: no warning and no flag in result.json.</p>\n"
        } else {
            "<p class=\"ok\">Nothing flagged: a run at fixed values has no search to flag.</p>\n"
        });
    } else {
        h.push_str("<ul class=\"warnings\">\n");
        for w in all {
            let _ = writeln!(h, "<li>{}</li>", esc(w));
        }
        h.push_str("</ul>\n");
    }
    h.push_str("</section>\n");
}

fn row(h: &mut String, key: &str, value: &str) {
    let _ = writeln!(h, "<tr><th scope=\"row\">{key}</th><td>{value}</td></tr>");
}

fn summary(h: &mut String, r: &ResultFile, has_result: bool) {
    h.push_str("<section id=\"summary\">\n<h2>Summary</h2>\n");
    if !has_result {
        h.push_str("<p>No calibration result (no result.json): the model at fixed values against the record, no search.</p>\n</section>\n");
        return;
    }
    h.push_str("<table class=\"kv\"><tbody>\n");
    let count = |v: Option<u64>| v.map_or_else(|| "—".into(), |v| v.to_string());
    row(h, "Rig", &esc(&r.rig));
    row(
        h,
        "Campaign",
        &format!(
            "{} <span class=\"path\">({})</span>",
            esc(&r.campaign),
            esc(&r.campaign_file)
        ),
    );
    let inputs: Vec<String> = r
        .inputs
        .iter()
        .map(|i| {
            format!(
                "{}<br><span class=\"hash\">SHA-256 {}</span>",
                esc(&i.path),
                esc(&i.sha256)
            )
        })
        .collect();
    row(
        h,
        "Data files",
        &if inputs.is_empty() {
            "—".into()
        } else {
            inputs.join("<br>")
        },
    );
    row(h, "Backend", &esc(&r.backend));
    row(h, "Device", &esc(&r.device));
    row(h, "Precision", &esc(&r.precision));
    row(h, "Seed", &count(r.seed));
    row(
        h,
        "Search method",
        &esc(r.search_method.as_deref().unwrap_or("GA")),
    );
    row(h, "Generations", &count(r.generations));
    row(h, "Evaluations", &count(r.evaluations));
    let time = r.job_wall_time_s.or(r.wall_time_s);
    row(
        h,
        "Wall time",
        &time.map_or_else(|| "—".into(), |t| format!("{} s", num(t))),
    );
    row(h, "Stop reason", &esc(&r.stop_reason));
    row(h, "Best cost (1 − R²)", &opt(r.fitness));
    row(h, "rigfit version", &esc(&r.rigfit_version));
    h.push_str("</tbody></table>\n</section>\n");
}

fn correlation(h: &mut String, r: &ResultFile) {
    h.push_str("<section id=\"correlation\">\n<h2>Correlation</h2>\n");
    let p = r
        .polish
        .as_ref()
        .filter(|p| !p.genes.is_empty() && p.correlation.len() == p.genes.len());
    match p {
        Some(p) => {
            let _ = write!(
                h,
                "<figure class=\"heat\">\n{}\n<figcaption>Correlation of the free parameters at the optimum (the polish's covariance); hover a cell for its value.</figcaption>\n</figure>\n\
                 <table class=\"data narrow\"><caption>Strongest pairs, |r| descending</caption><thead><tr><th>Parameter</th><th>Parameter</th><th class=\"num\">r</th></tr></thead><tbody>\n{}</tbody></table>\n",
                heatmap::svg(&p.genes, &p.correlation),
                heatmap::strongest_pairs(&p.genes, &p.correlation, 5)
            );
        }
        None => h.push_str("<p>No correlation matrix in result.json (the polish was off or gave no covariance).</p>\n"),
    }
    h.push_str("</section>\n");
}

fn convergence(
    h: &mut String,
    r: &ResultFile,
    history: Option<&input::History>,
    floor: Option<f64>,
) {
    h.push_str("<section id=\"convergence\">\n<h2>Convergence</h2>\n");
    if history.is_some_and(|h| !h.best.is_empty()) {
        let _ = write!(
            h,
            "<figure class=\"convergence\" data-kind=\"convergence\">\n<svg role=\"img\" aria-label=\"Best and median cost by generation on a log axis{}\" viewBox=\"0 0 900 280\"></svg>\n\
             <figcaption>Best and median cost (1 − R²) by generation, log axis{}.</figcaption>\n</figure>\n",
            if floor.is_some() {
                ", with the noise floor"
            } else {
                ""
            },
            floor.map_or_else(String::new, |f| format!(
                "; dashed: the noise floor ({})",
                num(f)
            ))
        );
    } else {
        h.push_str("<p>No search history (history.csv) for this page.</p>\n");
    }
    if let Some(p) = &r.polish {
        let _ = writeln!(
            h,
            "<p>Polish (Levenberg–Marquardt): {} iterations, {} evaluations, {}; stopped: {}.</p>",
            p.iterations.map_or_else(|| "—".into(), |v| v.to_string()),
            p.evaluations.map_or_else(|| "—".into(), |v| v.to_string()),
            p.wall_time_s
                .map_or_else(|| "—".into(), |t| format!("{} s", num(t))),
            esc(p.stop.as_deref().unwrap_or("—"))
        );
        h.push_str("<table class=\"data narrow\"><caption>Polish starts</caption><thead><tr><th>Start</th><th class=\"num\">Initial cost</th><th class=\"num\">Polished cost</th></tr></thead><tbody>\n");
        for (i, s) in p.starts.iter().enumerate() {
            let best = if p.best_start == Some(i) {
                " class=\"best\""
            } else {
                ""
            };
            let _ = writeln!(
                h,
                "<tr{best}><td>{i}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
                opt(s.initial),
                opt(s.polished)
            );
        }
        h.push_str("</tbody></table>\n");
    }
    h.push_str("</section>\n");
}

fn profiles(h: &mut String, r: &ResultFile) {
    h.push_str("<section id=\"profiles\">\n<h2>Profiles</h2>\n");
    let list = r
        .profiles
        .as_ref()
        .map(|p| p.parameters.as_slice())
        .unwrap_or_default();
    if list.is_empty() {
        h.push_str("<p>Profile likelihoods were not computed for this result. Compute them with \
                    <code>rigfit profile DIR</code>; the page then shows each parameter's profile and its interval.</p>\n");
    } else {
        h.push_str("<div class=\"profile-grid\">\n");
        for (i, p) in list.iter().enumerate() {
            let _ = write!(
                h,
                "<figure class=\"profile\" data-kind=\"profile\" data-index=\"{i}\">\n<svg role=\"img\" aria-label=\"Profile of {n}: Δχ² (or the cost) against its value, with the 95 % threshold; the table below gives the intervals\" viewBox=\"0 0 420 240\"></svg>\n\
                 <figcaption><b>{n}</b>: 95 % interval {}{} (drawn up to 10× the threshold)</figcaption>\n</figure>\n",
                interval(p.interval),
                p.flag
                    .as_deref()
                    .map_or_else(String::new, |f| format!("; {}", esc(f))),
                n = esc(&p.name)
            );
        }
        h.push_str("</div>\n");
        h.push_str(
            "<table class=\"data\"><thead><tr><th>Parameter</th><th class=\"num\">Value</th>\
             <th class=\"num\">95 % (profile)</th><th class=\"num\">95 % (covariance)</th><th>Flag</th></tr></thead><tbody>\n",
        );
        for p in list {
            let covariance = r
                .parameters
                .iter()
                .find(|x| x.name == p.name)
                .and_then(|x| x.interval_95);
            let _ = writeln!(
                h,
                "<tr><th scope=\"row\">{}</th><td class=\"num\">{} {}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td></tr>",
                esc(&p.name),
                opt(p.value),
                esc(&p.unit),
                interval(p.interval),
                interval(covariance),
                esc(p.flag.as_deref().unwrap_or("—"))
            );
        }
        h.push_str("</tbody></table>\n");
    }
    h.push_str("</section>\n");
}

fn validation_section(
    h: &mut String,
    r: &ResultFile,
    shown: &[Shown],
    modes: &dyn Fn(&str) -> Vec<f64>,
) {
    h.push_str("<section id=\"validation\">\n<h2>Validation</h2>\n");
    let list = r
        .validation
        .as_ref()
        .map(|v| v.experiments.as_slice())
        .unwrap_or_default();
    if list.is_empty() {
        h.push_str("<p>No validation record was given. Name one under <code>\"validation\"</code> in the campaign, \
                    or run <code>rigfit validate</code> on this result with a record the fit did not see.</p>\n</section>\n");
        return;
    }
    h.push_str("<table class=\"data\"><thead><tr><th>Record</th><th class=\"num\">R²</th><th class=\"num\">1 − R²</th><th class=\"num\">Residual RMS</th>\
                <th class=\"num\">Noise estimate</th><th class=\"num\">Cost / noise floor</th></tr></thead><tbody>\n");
    for v in list {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            esc(&v.name),
            opt(v.r2),
            opt(v.one_minus_r2),
            opt(v.residual_rms),
            opt(v.noise_estimate),
            opt(v.cost_over_noise_floor)
        );
    }
    h.push_str("</tbody></table>\n");
    experiments(h, r, shown, "validation", "Validation", modes);
    h.push_str("</section>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_a_table_shows_them() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1.5), "1.5");
        assert_eq!(num(-0.025), "−0.025");
        assert_eq!(
            num(8_399_893_871.844_94),
            "8.39989&#8239;×&#8239;10<sup>9</sup>"
        );
        assert_eq!(num(f64::NAN), "—");
        assert_eq!(esc("<a & \"b\">"), "&lt;a &amp; &quot;b&quot;&gt;");
    }
}
