//! `rigfit identify sensitivity`: the change of a quarter car's strut
//! stiffness between two records, by the experimental sensitivity functions.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;

use super::common::Common;
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::Output;
use crate::cli::record::{Record, in_file};
use rigfit::identify::transmissibility::{self as tr, BlockSpectra, StrutSensitivity};

/// `rigfit identify sensitivity`.
#[derive(Debug, Args)]
pub struct SensitivityArgs {
    /// CSV record before the change.
    pub base: PathBuf,
    /// CSV record after the change.
    pub changed: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Wheel-pan (tire patch) column.
    #[arg(long, default_value = "2")]
    pub wheel_pan: String,
    /// Unsprung-mass column.
    #[arg(long, default_value = "3")]
    pub unsprung: String,
    /// Sprung-mass column.
    #[arg(long, default_value = "4")]
    pub sprung: String,
    /// Tire stiffness K1 (N/m), for the input force of Eq. 10.
    #[arg(long)]
    pub k1: f64,
    /// Tire damping C1 (N·s/m).
    #[arg(long, default_value_t = 0.0)]
    pub c1: f64,
    /// Samples per segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    /// Lower edge of the band ΔK is averaged over (Hz).
    #[arg(long)]
    pub f_min: f64,
    /// Upper edge of that band (Hz).
    #[arg(long)]
    pub f_max: f64,
    /// Campaign name of the strut stiffness, for the fragment.
    #[arg(long, default_value = "k2")]
    pub name: String,
    /// The strut stiffness before the change (N/m): with it, the fragment holds
    /// the value after the change.
    #[arg(long)]
    pub base_value: Option<f64>,
    #[command(flatten)]
    pub common: Common,
}

/// Estimates the stiffness change and delivers the fragment (the value after
/// the change, when `--base-value` gives the one before).
pub fn sensitivity(a: &SensitivityArgs, out: &Output) -> Result<()> {
    let spectra = |path: &Path| -> Result<BlockSpectra> {
        let record = Record::read(path)?;
        let fs = record.time_column_rate(&a.time)?;
        let u = record.column(&a.wheel_pan)?;
        let y1 = record.column(&a.unsprung)?;
        let y2 = record.column(&a.sprung)?;
        tr::block_spectra(u, &[y1, y2], fs, a.segment).map_err(|e| record.error(e))
    };
    let (base, changed) = (spectra(&a.base)?, spectra(&a.changed)?);
    let band = (a.f_min, a.f_max);
    let r = tr::strut_sensitivity(&base, &changed, a.k1, a.c1, band)
        .map_err(|e| in_file(&a.changed, e))?;
    let figure = Figure {
        title: format!(
            "sensitivity: {} against {}",
            a.changed.display(),
            a.base.display()
        ),
        panels: || tr::sensitivity_figure(&r, band),
        columns: 2,
    };
    Findings {
        report: serde_json::json!({"welch": base.settings, "sensitivity": r}),
        fragment: r.to_campaign_fragment(&a.name, a.base_value, a.common.fixed),
        text: || report(a, &r),
    }
    .deliver_with(out, a.common.files(), figure)
}

/// The human report.
fn report(a: &SensitivityArgs, r: &StrutSensitivity) -> String {
    let mut s = format!(
        "strut stiffness change from {} to {} (Eq. 11 and 8a, tire force of Eq. 10)\n  \
         ΔK12 = {:.5e} N/m (spread {:.2e} over {} lines in {}…{} Hz)\n",
        a.base.display(),
        a.changed.display(),
        r.change.mean,
        r.change.spread,
        r.change.per_line.len(),
        a.f_min,
        a.f_max
    );
    if let Some(k) = a.base_value {
        s += &format!(
            "  {} = {:.5e} N/m after the change\n",
            a.name,
            k + r.change.mean
        );
    }
    s
}
