//! `rigfit fit-specimen` and `rigfit ringdown`.

use std::path::Path;

use anyhow::{Context, Result};

use super::args::{FitSpecimenArgs, RingdownArgs};
use super::{BadInput, Output, write_fragment};
use rigfit::identify::csv_input::read_two_columns;
use rigfit::identify::ringdown::{self, RingdownOptions};
use rigfit::identify::specimen::{self, SpecimenFitOptions};

/// Fits the specimen law and prints or writes the campaign fragment.
pub fn fit_specimen(args: &FitSpecimenArgs, out: &Output) -> Result<()> {
    let data = read_two_columns(&args.data).map_err(|e| in_file(&args.data, e))?;
    let opts = SpecimenFitOptions {
        degree: args.degree,
        ..SpecimenFitOptions::default()
    };
    let fit = specimen::fit(&data.x, &data.y, &opts).map_err(|e| in_file(&args.data, e))?;
    let fragment = fit.to_campaign_fragment();
    deliver(
        out,
        args.out.as_deref(),
        serde_json::json!({"fit": fit}),
        &fragment,
        || {
            let mut s = format!(
                "specimen law from {} ({} elastic + {} plastic points, degree {})\n",
                args.data.display(),
                fit.n_elastic,
                fit.n_plastic,
                fit.degree
            );
            s += &format!("  k_lin    = {:.6e} N/m\n", fit.k_lin);
            s += &format!(
                "  e_yield  = {:.6e} m  (chosen by best total fit)\n",
                fit.e_yield
            );
            for (i, a) in fit.coefficients.iter().enumerate() {
                s += &format!("  a{i}       = {a:.6e}\n");
            }
            s += &format!(
                "  R²: elastic {:.6}, plastic {:.6}, overall {:.6}; jump at e_yield {:.3} N\n",
                fit.r2_elastic, fit.r2_plastic, fit.r2_total, fit.jump_at_yield
            );
            s
        },
    )
}

/// Analyses a ringdown and prints or writes the campaign fragment.
pub fn ringdown_cmd(args: &RingdownArgs, out: &Output) -> Result<()> {
    let data = read_two_columns(&args.data).map_err(|e| in_file(&args.data, e))?;
    let opts = RingdownOptions {
        m1: args.m1,
        k1: args.k1,
        start: args.start,
        ..RingdownOptions::default()
    };
    let r = ringdown::analyse(&data.x, &data.y, &opts).map_err(|e| in_file(&args.data, e))?;
    if let Some(path) = &args.svg {
        let svg = rigfit::identify::plot::panels_svg(
            &format!("ringdown of {}", args.data.display()),
            &ringdown::figure(&r, &data.x, &data.y),
            2,
        )?;
        rigfit::base::fsutil::atomic_write(path, svg.as_bytes())
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    let fragment = r.to_campaign_fragment();
    deliver(
        out,
        args.out.as_deref(),
        serde_json::json!({"ringdown": r}),
        &fragment,
        || {
            let mut s = format!(
                "ringdown of {} (sampled at {:.0} Hz, free ringing from {:.6e} s)\n",
                args.data.display(),
                r.sample_rate_hz,
                r.start.time
            );
            s += &format!(
                "  PSD ({} window, {} samples × {} segments, resolution {:.1} Hz): peak {:.1} Hz\n",
                r.psd.window,
                r.psd.segment_len,
                r.psd.n_segments,
                r.psd.resolution_hz,
                r.psd.peak_hz
            );
            s += &format!(
                "  log decrement over {} peaks: ζ = {:.5} (spread {:.2e}, {:.5}..{:.5})\n",
                r.decrement.n_peaks,
                r.decrement.zeta_mean,
                r.decrement.zeta_std,
                r.decrement.zeta_min,
                r.decrement.zeta_max
            );
            s += &format!(
                "  damped-oscillator fit: f_n = {:.2} Hz, ζ = {:.6}, R² = {:.5}\n",
                r.natural_frequency_hz, r.fit.zeta, r.fit.r2
            );
            if let Some(e) = &r.envelope {
                s += &format!(
                    "  analytic-signal envelope in {:.1}…{:.1} Hz: ζ = {:.6} (R² = {:.5})\n",
                    e.band_hz.0, e.band_hz.1, e.zeta, e.r2
                );
            }
            let g = &r.agreement;
            s += &format!(
                "  the damping estimates {} (spread {:.1} %, {:.1} samples per cycle)\n",
                if g.agree { "agree" } else { "DISAGREE" },
                100.0 * g.relative_spread,
                g.samples_per_cycle
            );
            for w in &g.warnings {
                s += &format!("  warning: {w}\n");
            }
            if let (true, Some(k1)) = (r.k1_from_frequency, r.k1) {
                s += &format!("  k1 from frequency and m1 = {k1:.6e} N/m\n");
            }
            if let Some(c) = r.c1_post {
                s += &format!("  c1_post = {c:.6e} N·s/m\n");
            }
            s
        },
    )
}

/// Writes the fragment (with `--out`), then prints the report as JSON (with
/// `--json`, the fragment added) or as text followed by where the fragment went.
pub(super) fn deliver(
    out: &Output,
    path: Option<&Path>,
    mut report: serde_json::Value,
    fragment: &serde_json::Value,
    text: impl FnOnce() -> String,
) -> Result<()> {
    if let Some(path) = path {
        write_fragment(path, fragment)?;
    }
    report["fragment"] = fragment.clone();
    out.json(&report)?;
    out.say(|| {
        let mut s = text();
        match path {
            Some(p) => s += &format!("campaign fragment written to {}", p.display()),
            None => {
                s += "campaign fragment:\n";
                s += &serde_json::to_string_pretty(fragment).unwrap_or_default();
            }
        }
        s
    });
    Ok(())
}

/// A pre-calibration error as one line that names the input file.
pub(super) fn in_file(path: &Path, e: rigfit::identify::PrecalError) -> anyhow::Error {
    BadInput(format!("{}: {e}", path.display())).into()
}
