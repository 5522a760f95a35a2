//! `rigfit identify idim`: inverse-model least squares (IDIM-LS) for a driven
//! mass with friction, as on the EMPS benchmark.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::common::Common;
use crate::cli::exit::BadInput;
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::Output;
use crate::cli::record::Record;
use rigfit::identify::idim::{self, IdimOptions};

/// `rigfit identify idim`.
#[derive(Debug, Args)]
pub struct IdimArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Position column (m).
    #[arg(long, default_value = "1")]
    pub position: String,
    /// Force column (N, or a signal scaled by --gain).
    #[arg(long, default_value = "2")]
    pub force: String,
    /// Force per unit of the force column (e.g. EMPS gtau, N/V).
    #[arg(long, default_value_t = 1.0)]
    pub gain: f64,
    /// Time column (s); or give --sample-rate.
    #[arg(long, conflicts_with = "sample_rate")]
    pub time: Option<String>,
    /// Sample rate (Hz) when the record has no time column.
    #[arg(long)]
    pub sample_rate: Option<f64>,
    /// Cut-off of the zero-phase Butterworth low-pass (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub cutoff: f64,
    /// Order of that filter.
    #[arg(long, default_value_t = 4)]
    pub filter_order: usize,
    /// Keep every N-th row in the least squares.
    #[arg(long, default_value_t = 10)]
    pub decimation: usize,
    #[command(flatten)]
    pub common: Common,
}

/// Estimates the inverse model and delivers the fragment.
pub fn idim(a: &IdimArgs, out: &Output) -> Result<()> {
    let record = Record::read(&a.data)?;
    let q = record.column(&a.position)?;
    let tau: Vec<f64> = record
        .column(&a.force)?
        .iter()
        .map(|v| a.gain * v)
        .collect();
    let fs = match (&a.time, a.sample_rate) {
        (Some(col), _) => record.time_column_rate(col)?,
        (None, Some(fs)) => fs,
        (None, None) => anyhow::bail!(BadInput(
            "give the sample rate (--sample-rate) or a time column (--time)".into()
        )),
    };
    let opts = IdimOptions {
        sample_rate_hz: fs,
        cutoff_hz: a.cutoff,
        filter_order: a.filter_order,
        decimation: a.decimation,
        border: 49,
    };
    let r = idim::estimate(q, &tau, &opts).map_err(|e| record.error(e))?;
    let figure = Figure {
        title: format!("inverse model of {}", a.data.display()),
        panels: || idim::figure(&r),
        columns: 1,
    };
    Findings {
        report: serde_json::json!({"idim": r}),
        fragment: r.to_campaign_fragment(a.common.fixed),
        text: || {
            let mut s = format!(
                "inverse model of {} ({} rows after decimation by {})\n",
                a.data.display(),
                r.rows,
                opts.decimation
            );
            for e in &r.estimates {
                s += &format!(
                    "  {:<3} = {:>10.4} ± {:.2} % {}\n",
                    e.param, e.value, e.relative_error_percent, e.unit
                );
            }
            s += &format!("  R² = {:.5}, RMS residual {:.4} N\n", r.r2, r.rms_residual);
            s
        },
    }
    .deliver_with(out, a.common.files(), figure)
}
