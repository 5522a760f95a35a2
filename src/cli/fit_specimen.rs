//! `rigfit fit-specimen`, a pre-calibration command: the specimen law of the
//! tensile rig, fitted to quasi-static force–elongation data before the rig is
//! searched.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::fragment::{Files, Findings};
use super::output::Output;
use super::record::{in_file, read_two_columns};
use rigfit::identify::specimen::{self, SpecimenFitOptions};

/// `rigfit fit-specimen`.
#[derive(Debug, Args)]
pub struct FitSpecimenArgs {
    /// CSV of elongation (m) and force (N).
    pub data: PathBuf,
    /// Degree of the plastic polynomial (3 for aluminium, 5 for carbon/epoxy; at most 5).
    #[arg(long, default_value_t = 3)]
    pub degree: usize,
    /// Write the campaign fragment (JSON) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the --out file when it exists (never the data file).
    #[arg(long)]
    pub overwrite: bool,
}

/// Fits the specimen law and prints or writes the campaign fragment.
pub fn fit_specimen(args: &FitSpecimenArgs, out: &Output) -> Result<()> {
    let files = Files {
        fragment: args.out.as_deref(),
        figure: None,
    };
    files.check(&[], &[&args.data], args.overwrite)?;
    let data = read_two_columns(&args.data)?;
    let opts = SpecimenFitOptions {
        degree: args.degree,
        ..SpecimenFitOptions::default()
    };
    let fit = specimen::fit(&data.x, &data.y, &opts).map_err(|e| in_file(&args.data, e))?;
    Findings {
        report: serde_json::json!({"fit": fit}),
        fragment: fit.to_campaign_fragment(),
        text: || {
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
    }
    .deliver(out, args.out.as_deref())
}
