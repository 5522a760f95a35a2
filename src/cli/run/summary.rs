//! The one-screen summary a calibration job prints at its end.

use std::fmt::Write as _;
use std::path::Path;

use rigfit::job::JobSummary;

/// The one-screen summary at the end of a job.
pub fn summary_text(s: &JobSummary, dir: &Path, steps: f64) -> String {
    let mut t = String::new();
    let rate = s.evaluations as f64 * steps / s.wall_time_s.max(1e-9);
    let _ = writeln!(t, "\nverdict: {}", s.verdict.line);
    let _ = writeln!(
        t,
        "{} — {}{}",
        s.campaign,
        s.stop_reason,
        integration_error(s)
    );
    let _ = writeln!(
        t,
        "  {} generations, {} evaluations in {:.1} s on {} ({}, {}): {:.3e} candidate-steps/s",
        s.generations, s.evaluations, s.wall_time_s, s.backend, s.device, s.precision, rate
    );
    for e in &s.experiments {
        let rms = e.residual_rms.map_or_else(String::new, |r| {
            format!("; residual RMS {r:.4e} {}", e.unit)
        });
        let rms = match (e.noise_estimate, e.cost_over_noise_floor) {
            (Some(n), Some(k)) => {
                format!(
                    "{rms}, record noise ≈ {n:.3e} {}: {k:.2}× the floor",
                    e.unit
                )
            }
            _ => rms,
        };
        let _ = writeln!(
            t,
            "  {}: R² = {:.6} (1 − R² = {:.3e}; f64 CPU reference R² = {:.6}{rms})",
            e.name, e.r2, e.one_minus_r2, e.r2_cpu_reference
        );
    }
    for v in s.validation.iter().flat_map(|v| &v.experiments) {
        let _ = writeln!(t, "  {}", v.line());
    }
    let method: rigfit::search::Method = s
        .search_method
        .as_deref()
        .and_then(|m| m.parse().ok())
        .unwrap_or_default();
    if let Some(p) = &s.polish {
        let _ = writeln!(
            t,
            "  polish: 1 − R² {:.4e} ({}) → {:.4e} in {} iterations, {} evaluations, {:.1} s{}",
            p.ga_fitness,
            method.label(),
            s.fitness,
            p.iterations,
            p.evaluations,
            p.wall_time_s,
            if p.stop.short() {
                format!(" — {} (see the warnings)", p.stop)
            } else {
                String::new()
            }
        );
    }
    let _ = writeln!(
        t,
        "  fitted parameters (95 % interval from the covariance at the optimum, relative \
         to the value; elite width: spread of the {}'s best 10 % relative to the value):",
        method.label()
    );
    let _ = writeln!(
        t,
        "    {:<18} {:>14} {:<7} {:>25} {:>25} {:>12}",
        "name", "value", "unit", "bounds", "95 % interval", "elite width"
    );
    let sensitive_job = s.sensitivity.as_ref().is_some_and(|x| x.sensitive);
    for p in s.parameters.iter().filter(|p| p.free) {
        let bounds = p
            .bounds
            .map(|[lo, hi]| format!("[{lo:.3e}, {hi:.3e}]"))
            .unwrap_or_default();
        // A response sensitive to tiny changes: the covariance's interval
        // (often ±0.000 %) says nothing for any parameter the polish gave one.
        let sensitive = sensitive_job && p.determined.is_some();
        let interval = p
            .interval_95
            .filter(|_| !sensitive)
            .map(|[lo, hi]| {
                // Relative to the value: a log-scale interval is asymmetric;
                // a gene at a bound has a one-sided interval, open there.
                let rel = |x: f64| {
                    let r = 100.0 * (x / p.value - 1.0);
                    if r.is_finite() {
                        format!("{r:+.3} %")
                    } else {
                        "open".into()
                    }
                };
                format!("{} / {}", rel(lo), rel(hi))
            })
            .unwrap_or_else(|| {
                if sensitive {
                    "not meaningful".into()
                } else if p.determined.is_some() {
                    "—".into()
                } else {
                    String::new()
                }
            });
        let width = p
            .elite_relative_width
            .map(|w| format!("{:.2} %", 100.0 * w))
            .unwrap_or_default();
        let mut flags = String::new();
        match p.at_bound {
            Some(b) => {
                let _ = write!(flags, "  at its {} bound", format!("{b:?}").to_lowercase());
            }
            None if p.determined == Some(false) => {
                flags += if sensitive {
                    "  not determined: the response is sensitive to tiny changes"
                } else {
                    "  not determined by the data"
                }
            }
            None => {}
        }
        if !p.correlated_with.is_empty() {
            let _ = write!(
                flags,
                "  |corr| > 0.99 with {}",
                p.correlated_with.join(", ")
            );
        }
        let _ = writeln!(
            t,
            "    {:<18} {:>14.6e} {:<7} {:>25} {:>25} {:>12}{flags}",
            p.name, p.value, p.unit, bounds, interval, width
        );
    }
    if let Some(profiles) = &s.profiles {
        profile_lines(&mut t, profiles);
    }
    for w in &s.warnings {
        let _ = writeln!(t, "  warning: {w}");
    }
    let mut files = vec!["result.json".to_string()];
    for e in &s.experiments {
        files.push(e.csv.clone());
        files.push(e.plot.clone());
    }
    files.push("history.csv".into());
    files.push("fitness.svg".into());
    if dir.join(rigfit::report::html::REPORT_FILE).is_file() {
        files.push(rigfit::report::html::REPORT_FILE.into());
    }
    let _ = write!(t, "  results in {}: {}", dir.display(), files.join(", "));
    t
}

/// The profiles' 95 % intervals beside the covariance's, relative to the
/// value, with each parameter's flag.
fn profile_lines(t: &mut String, profiles: &rigfit::search::ProfileOutcome) {
    let _ = writeln!(
        t,
        "  profile likelihoods ({} iterations, {} evaluations, {:.1} s): 95 % interval where \
         Δχ² ≤ {:.2}, relative to the value:",
        profiles.iterations,
        profiles.evaluations,
        profiles.wall_time_s,
        profiles.parameters.first().map_or(0.0, |p| p.threshold)
    );
    for p in &profiles.parameters {
        let rel = |x: Option<f64>| {
            x.map(|x| 100.0 * (x / p.value - 1.0))
                .filter(|r| r.is_finite())
                .map_or("open".to_string(), |r| format!("{r:+.3} %"))
        };
        let interval = p.interval.map_or("open / open".to_string(), |[lo, hi]| {
            format!("{} / {}", rel(lo), rel(hi))
        });
        let flag = p
            .flag
            .map(|f| format!("  {}", f.as_str()))
            .unwrap_or_default();
        let _ = writeln!(t, "    {:<18} {:>25}{flag}", p.name, interval);
    }
}

/// `; RK4 integration error ≈ 1.2e-3 N, 0.01 % of the residual RMS (1 RK4
/// step per sample)` for the experiment where it is the largest part of the
/// residual; empty where none was estimated.
fn integration_error(s: &JobSummary) -> String {
    let worst = s
        .experiments
        .iter()
        .filter_map(|e| Some((e, e.integration_error.estimate?)))
        .max_by(|a, b| {
            let f = |x: &(&rigfit::job::ExperimentFit, f64)| {
                x.0.integration_error
                    .fraction_of_residual_rms
                    .unwrap_or(0.0)
            };
            f(a).total_cmp(&f(b)).then(a.1.total_cmp(&b.1))
        });
    let Some((e, est)) = worst else {
        return String::new();
    };
    let frac = e
        .integration_error
        .fraction_of_residual_rms
        .map_or_else(String::new, |f| {
            format!(", {:.2} % of the residual RMS", 100.0 * f)
        });
    let within = if s.experiments.len() > 1 {
        format!(" in '{}'", e.name)
    } else {
        String::new()
    };
    format!(
        "; RK4 integration error ≈ {est:.2e} {}{frac}{within} ({})",
        e.unit,
        rigfit::base::text::steps_per_sample(e.integration_error.substeps)
    )
}
