//! `rigfit identify nimiso`: Bendat's reverse-path nonlinear MISO analysis of
//! a force-driven rig, splitting the force into a linear and a nonlinear path.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::common::{Band, Common};
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::Output;
use crate::cli::record::Record;
use rigfit::identify::nimiso::{self, NimisoOptions, NimisoReport, Nonlinearity};

/// `rigfit identify nimiso`.
#[derive(Debug, Args)]
pub struct NimisoArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Motion column (m), the reverse path's input.
    #[arg(long, default_value = "2")]
    pub motion: String,
    /// Force column (N), the reverse path's output.
    #[arg(long, default_value = "3")]
    pub force: String,
    /// The nonlinear input v = g(x, ẋ).
    #[arg(long, value_enum, default_value_t = NonlinearArg::Cubic)]
    pub nonlinear: NonlinearArg,
    /// Samples per Welch segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    #[command(flatten)]
    pub band: Band,
    #[command(flatten)]
    pub common: Common,
}

/// The nonlinear input of the reverse path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NonlinearArg {
    /// x³ (cubic stiffness, fragment name k3).
    Cubic,
    /// sgn ẋ (Coulomb friction, fragment name f_c).
    SignVelocity,
    /// |ẋ|·ẋ (quadratic damping, fragment name c2).
    QuadraticDamping,
}

impl NonlinearArg {
    /// The library's nonlinearity and its parameter's name in the fragment.
    fn nonlinearity(self) -> (Nonlinearity, &'static str) {
        match self {
            Self::Cubic => (Nonlinearity::Cubic, "k3"),
            Self::SignVelocity => (Nonlinearity::SignVelocity, "f_c"),
            Self::QuadraticDamping => (Nonlinearity::QuadraticDamping, "c2"),
        }
    }
}

/// Runs the reverse-path analysis and delivers the fragment.
pub fn nimiso(a: &NimisoArgs, out: &Output) -> Result<()> {
    let record = Record::read(&a.data)?;
    let fs = record.time_column_rate(&a.time)?;
    let x = record.column(&a.motion)?;
    let f = record.column(&a.force)?;
    let (nonlinearity, name) = a.nonlinear.nonlinearity();
    let opts = NimisoOptions {
        sample_rate_hz: fs,
        segment_len: a.segment,
        nonlinearity,
        f_min: a.band.f_min,
        f_max: a.band.f_max,
    };
    let (path, r) = nimiso::analyse(x, f, &opts).map_err(|e| record.error(e))?;
    let figure = Figure {
        title: format!("reverse-path analysis of {}", a.data.display()),
        panels: || nimiso::figure(&path, &r, a.band.edges()),
        columns: 3,
    };
    Findings {
        report: serde_json::json!({"nimiso": r}),
        fragment: r.to_campaign_fragment(name, a.common.fixed),
        text: || report(a, &r, name),
    }
    .deliver_with(out, a.common.files(), figure)
}

/// The human report.
fn report(a: &NimisoArgs, r: &NimisoReport, name: &str) -> String {
    format!(
        "reverse-path analysis of {} ({} lines in {}…{} Hz, {} segments of {})\n  \
         m = {:.5e} kg, k = {:.5e} N/m, c = {:.5e} N·s/m\n  \
         {name} = {:.5e} (spread over the band {:.2e})\n  \
         coherence: linear path {:.4}, nonlinear path adds {:.4}\n",
        a.data.display(),
        r.lines,
        a.band.f_min,
        a.band.f_max,
        r.settings.n_segments,
        r.settings.segment_len,
        r.mass,
        r.stiffness,
        r.damping,
        r.nonlinear_coefficient,
        r.nonlinear_spread,
        r.mean_coherence_linear,
        r.mean_coherence_nonlinear
    )
}
