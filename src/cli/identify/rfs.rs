//! `rigfit identify rfs`: the restoring-force surface of a base-excited SDOF
//! rig and its terms by direct parameter estimation.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::common::Common;
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::Output;
use crate::cli::record::Record;
use rigfit::identify::dpe::{self, DpeOptions, GridOptions, Term};
use rigfit::identify::rfs::{self, RfsOptions};

/// `rigfit identify rfs`.
#[derive(Debug, Args)]
pub struct RfsArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Relative displacement column (m).
    #[arg(long, default_value = "2")]
    pub x: String,
    /// Base acceleration column (m/s²).
    #[arg(long, default_value = "3")]
    pub accel: String,
    /// Mass of the moving body (kg), measured.
    #[arg(long)]
    pub mass: f64,
    /// Terms of the restoring force.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [TermArg::Linear, TermArg::Viscous])]
    pub terms: Vec<TermArg>,
    /// Fixed damping exponent α (default: searched).
    #[arg(long)]
    pub alpha: Option<f64>,
    /// Fixed stiffness exponent β (default: searched).
    #[arg(long)]
    pub beta: Option<f64>,
    /// Zero-phase low-pass on x and a before differencing (Hz).
    #[arg(long)]
    pub cutoff: Option<f64>,
    /// Order of that Butterworth filter.
    #[arg(long, default_value_t = 4)]
    pub filter_order: usize,
    #[command(flatten)]
    pub common: Common,
}

/// A restoring-force term on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TermArg {
    /// kf1·x
    Linear,
    /// kf2·x³
    Cubic,
    /// kf3·|x|^β·sgn x
    PowerStiffness,
    /// cf1·ẋ
    Viscous,
    /// cf2·ẋ³
    CubicDamping,
    /// cf3·|ẋ|^α·sgn ẋ
    PowerDamping,
    /// fc·sgn ẋ
    Coulomb,
}

impl From<TermArg> for Term {
    fn from(t: TermArg) -> Self {
        match t {
            TermArg::Linear => Term::Linear,
            TermArg::Cubic => Term::Cubic,
            TermArg::PowerStiffness => Term::PowerStiffness,
            TermArg::Viscous => Term::Viscous,
            TermArg::CubicDamping => Term::CubicDamping,
            TermArg::PowerDamping => Term::PowerDamping,
            TermArg::Coulomb => Term::Coulomb,
        }
    }
}

/// Builds the surface, estimates the terms and delivers the fragment.
pub fn rfs(a: &RfsArgs, out: &Output) -> Result<()> {
    let record = Record::read(&a.data)?;
    let t = record.column(&a.time)?;
    let x = record.column(&a.x)?;
    let acc = record.column(&a.accel)?;
    let options = RfsOptions {
        mass: a.mass,
        cutoff_hz: a.cutoff,
        filter_order: a.filter_order,
    };
    let surface = rfs::surface(t, x, acc, &options).map_err(|e| record.error(e))?;
    let opts = DpeOptions {
        terms: a.terms.iter().map(|&t| t.into()).collect(),
        alpha: a.alpha,
        beta: a.beta,
        grid: GridOptions::default(),
    };
    let r = dpe::estimate(&surface, &opts).map_err(|e| record.error(e))?;
    let figure = Figure {
        title: format!("restoring force of {}", a.data.display()),
        panels: || dpe::figure(&surface, &r),
        columns: 3,
    };
    Findings {
        report: serde_json::json!({"dpe": r}),
        fragment: r.to_campaign_fragment(a.common.fixed, &opts.grid),
        text: || report(a, &r, surface.sample_rate_hz),
    }
    .deliver_with(out, a.common.files(), figure)
}

/// The human report.
fn report(a: &RfsArgs, r: &dpe::DpeReport, sample_rate_hz: f64) -> String {
    let mut s = format!(
        "restoring-force surface of {} ({} samples at {:.0} Hz, m = {} kg)\n",
        a.data.display(),
        r.samples,
        sample_rate_hz,
        r.mass
    );
    for c in &r.coefficients {
        s += &format!(
            "  {:<4} = {:>12.5e} ± {:.2e} {}\n",
            c.param, c.value, c.std_error, c.unit
        );
    }
    if let Some(al) = r.exponents.alpha {
        s += &format!("  alpha = {al:.4}\n");
    }
    if let Some(b) = r.exponents.beta {
        s += &format!("  beta  = {b:.4}\n");
    }
    if let (Some(first), Some(last)) = (r.search.first(), r.search.last()) {
        s += &format!(
            "  exponent grid: {} levels, step {} → {}\n",
            r.search.len(),
            first.step,
            last.step
        );
    }
    s += &format!(
        "  R² = {:.6}, RMS residual {:.4e} N, largest {:.4e} N, condition {:.2e}\n",
        r.r2, r.rms_residual, r.max_residual, r.condition
    );
    s
}
