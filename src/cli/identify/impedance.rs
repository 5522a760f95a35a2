//! `rigfit identify impedance`: the 2 × 2 impedance and receptance matrices of
//! a point mass from an impact in x and one in y, with K, C and M fitted.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::common::{Band, Common};
use crate::cli::exit::BadInput;
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::Output;
use crate::cli::record::Record;
use rigfit::identify::impedance::{self, ImpactRecord, ImpedanceFit};

/// `rigfit identify impedance`.
#[derive(Debug, Args)]
pub struct ImpedanceArgs {
    /// CSV record of the impact in x.
    pub x_test: PathBuf,
    /// CSV record of the impact in y.
    pub y_test: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Hammer force column (N).
    #[arg(long, default_value = "2")]
    pub force: String,
    /// x displacement column (m).
    #[arg(long, default_value = "3")]
    pub x: String,
    /// y displacement column (m).
    #[arg(long, default_value = "4")]
    pub y: String,
    /// The mass (kg), if known (default: fitted).
    #[arg(long)]
    pub mass: Option<f64>,
    #[command(flatten)]
    pub band: Band,
    #[command(flatten)]
    pub common: Common,
}

/// Builds the matrices from the two impacts, fits K, C and M and delivers the
/// fragment.
pub fn impedance(a: &ImpedanceArgs, out: &Output) -> Result<()> {
    let x_test = Record::read(&a.x_test)?;
    let fsx = x_test.time_column_rate(&a.time)?;
    let y_test = Record::read(&a.y_test)?;
    let fsy = y_test.time_column_rate(&a.time)?;
    if ((fsx - fsy) / fsx).abs() > 1e-6 {
        anyhow::bail!(BadInput(format!(
            "the two records have different sample rates ({fsx} Hz and {fsy} Hz)"
        )));
    }
    let x_impact = impact(a, &x_test)?;
    let y_impact = impact(a, &y_test)?;
    let mats = impedance::matrices(x_impact, y_impact, fsx).map_err(|e| x_test.error(e))?;
    let fit = impedance::fit(&mats, a.band.edges(), a.mass).map_err(|e| x_test.error(e))?;
    let figure = Figure {
        title: format!(
            "impedance from {} and {}",
            a.x_test.display(),
            a.y_test.display()
        ),
        panels: || impedance::figure(&mats, &fit),
        columns: 4,
    };
    Findings {
        report: serde_json::json!({"impedance": fit}),
        fragment: fit.to_campaign_fragment(a.common.fixed),
        text: || report(a, &fit),
    }
    .deliver_with(out, a.common.files(), figure)
}

/// One impact's force and x and y displacements.
fn impact<'r>(a: &ImpedanceArgs, record: &'r Record<'_>) -> Result<ImpactRecord<'r>> {
    Ok(ImpactRecord {
        force: record.column(&a.force)?,
        x: record.column(&a.x)?,
        y: record.column(&a.y)?,
    })
}

/// The human report.
fn report(a: &ImpedanceArgs, fit: &ImpedanceFit) -> String {
    let (k, c) = (&fit.stiffness, &fit.damping);
    let mut s = format!(
        "impedance from {} (x impact) and {} (y impact), {} lines in {}…{} Hz\n  \
         M = {:.5e} kg{}\n  \
         K = [[{:.5e}, {:.5e}], [{:.5e}, {:.5e}]] N/m\n  \
         C = [[{:.5e}, {:.5e}], [{:.5e}, {:.5e}]] N·s/m\n  \
         R² of Re Z: xx {:.5}, yy {:.5}; of Im Z: xx {:.5}, xy {:.5}, yx {:.5}, yy {:.5}\n  \
         as bearing_2dof:",
        a.x_test.display(),
        a.y_test.display(),
        fit.lines,
        a.band.f_min,
        a.band.f_max,
        fit.mass,
        if fit.mass_given { " (given)" } else { "" },
        k[0][0],
        k[0][1],
        k[1][0],
        k[1][1],
        c[0][0],
        c[0][1],
        c[1][0],
        c[1][1],
        fit.r2_real[0][0],
        fit.r2_real[1][1],
        fit.r2_imag[0][0],
        fit.r2_imag[0][1],
        fit.r2_imag[1][0],
        fit.r2_imag[1][1]
    );
    for (name, v) in fit.bearing_params() {
        s += &format!(" {name} = {v:.5e}");
    }
    s + "\n"
}
