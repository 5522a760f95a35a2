//! `rigfit identify frf`: the H1/H2 frequency response of a record, its
//! coherence, and a modal fit.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::common::Common;
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::{Output, write_file};
use crate::cli::record::Record;
use rigfit::identify::frf::{self, Frf};
use rigfit::identify::modal::{self, ModalFit, ModalOptions, Response};

/// `rigfit identify frf`.
#[derive(Debug, Args)]
pub struct FrfArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Input (force) column.
    #[arg(long, default_value = "2")]
    pub input: String,
    /// Output (response) column.
    #[arg(long, default_value = "3")]
    pub output: String,
    /// What the output measures.
    #[arg(long, value_enum, default_value_t = ResponseArg::Displacement)]
    pub response: ResponseArg,
    /// Samples per Welch segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    /// Modes to fit in the band (0: no modal fit).
    #[arg(long, default_value_t = 1)]
    pub modes: usize,
    /// Lower edge of the fitted band (Hz).
    #[arg(long)]
    pub f_min: Option<f64>,
    /// Upper edge of the fitted band (Hz).
    #[arg(long)]
    pub f_max: Option<f64>,
    /// Lines with a lower coherence are left out of the fit.
    #[arg(long, default_value_t = 0.8)]
    pub min_coherence: f64,
    /// Campaign names of the SDOF mass, stiffness and damping (one mode).
    #[arg(long, value_delimiter = ',', default_values_t = ["m".to_string(), "k".to_string(), "c".to_string()])]
    pub names: Vec<String>,
    /// Write the FRF table (frequency, H1, H2, coherence, fit) here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
}

/// What the FRF's output column measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ResponseArg {
    /// Displacement (m).
    Displacement,
    /// Velocity (m/s).
    Velocity,
    /// Acceleration (m/s²).
    Acceleration,
}

impl From<ResponseArg> for Response {
    fn from(r: ResponseArg) -> Self {
        match r {
            ResponseArg::Displacement => Response::Displacement,
            ResponseArg::Velocity => Response::Velocity,
            ResponseArg::Acceleration => Response::Acceleration,
        }
    }
}

/// Estimates the frequency response, fits the modes and delivers the fragment.
pub fn frf(a: &FrfArgs, out: &Output) -> Result<()> {
    let record = Record::read(&a.data)?;
    let fs = record.time_column_rate(&a.time)?;
    let u = record.column(&a.input)?;
    let y = record.column(&a.output)?;
    let est = frf::estimate(u, y, fs, a.segment).map_err(|e| record.error(e))?;
    let response = Response::from(a.response);
    let fit = if a.modes > 0 {
        let opts = ModalOptions {
            modes: a.modes,
            f_min: a.f_min.unwrap_or(est.settings.resolution_hz),
            f_max: a.f_max.unwrap_or(fs / 2.0),
            response,
            min_coherence: a.min_coherence,
            iterations: 10,
        };
        let fit = modal::fit(&est.freqs, &est.h1, &est.coherence, &opts);
        Some(fit.map_err(|e| record.error(e))?)
    } else {
        None
    };
    if let Some(path) = &a.csv {
        write_file(path, table(&est, fit.as_ref(), response).as_bytes())?;
    }
    let figure = Figure {
        title: format!("frequency response of {}", a.data.display()),
        panels: || modal::figure(&est, fit.as_ref(), response),
        columns: 1,
    };
    Findings {
        report: serde_json::json!({
            "welch": est.settings, "modal": fit,
            "assumes": fit.as_ref().map(|_| frf::FORCE_INPUT),
            "warnings": fit.as_ref().map_or(&[][..], |m| &m.warnings[..]),
        }),
        fragment: match &fit {
            Some(m) => m.to_campaign_fragment(&a.names, a.common.fixed),
            None => serde_json::json!({"params": {}}),
        },
        text: || report(a, &est, fit.as_ref(), u.len(), fs),
    }
    .deliver_with(out, a.common.files(), figure)
}

/// The `--csv` table: one line per frequency.
fn table(est: &Frf, fit: Option<&ModalFit>, response: Response) -> String {
    let mut text = String::from(
        "frequency_Hz,h1_re,h1_im,h1_abs,h1_phase_rad,h2_abs,h2_phase_rad,coherence,fit_abs,fit_phase_rad\n",
    );
    for k in 0..est.freqs.len() {
        let f = est.freqs[k];
        let fitted = fit
            .map(|m| m.response(f, response))
            .unwrap_or(f64::NAN.into());
        text += &format!(
            "{f},{},{},{},{},{},{},{},{},{}\n",
            est.h1[k].re,
            est.h1[k].im,
            est.h1[k].norm(),
            est.h1[k].arg(),
            est.h2[k].norm(),
            est.h2[k].arg(),
            est.coherence[k],
            fitted.norm(),
            fitted.arg()
        );
    }
    text
}

/// The human report.
fn report(a: &FrfArgs, est: &Frf, fit: Option<&ModalFit>, n: usize, fs: f64) -> String {
    let w = &est.settings;
    let mut s = format!(
        "frequency response of {} ({} samples at {:.1} Hz)\n  Welch: {} window, {} samples × {} segments, resolution {:.4} Hz\n",
        a.data.display(),
        n,
        fs,
        w.window,
        w.segment_len,
        w.n_segments,
        w.resolution_hz
    );
    if let Some(m) = fit {
        for (i, md) in m.modes.iter().enumerate() {
            s += &format!(
                "  mode {}: f_n = {:.4} Hz, ζ = {:.5}, modal m = {:.5e} kg, k = {:.5e} N/m, c = {:.5e} N·s/m\n",
                i + 1,
                md.natural_frequency_hz,
                md.damping_ratio,
                md.mass,
                md.stiffness,
                md.damping
            );
        }
        s += &format!(
            "  fit over {} lines: relative RMS error {:.4}\n  note: {}\n",
            m.lines,
            m.relative_error,
            frf::FORCE_INPUT
        );
        for w in &m.warnings {
            s += &format!("  warning: {w}\n");
        }
    }
    s
}
