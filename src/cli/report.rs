//! `rigfit report`: rebuilds a result folder's report.html from the folder's
//! files, the page a job writes.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::exit::BadInput;
use super::output::Output;
use rigfit::report::html::{REPORT_FILE, ReportError, write_report_to};

/// `rigfit report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Result folder (what `rigfit run` wrote: result.json, the experiments'
    /// CSVs, history.csv), or a folder of experiment CSVs alone.
    pub dir: PathBuf,
    /// The page to write (default: DIR/report.html). An existing file is
    /// replaced only if it is a report rigfit wrote.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Builds the page and writes it.
pub fn report(args: &ReportArgs, out: &Output) -> Result<()> {
    let target = args
        .out
        .clone()
        .unwrap_or_else(|| args.dir.join(REPORT_FILE));
    let written = write_report_to(&args.dir, &target).map_err(|e| match e {
        // The folder's files or the target are at fault: bad input.
        ReportError::Io { .. } => anyhow::Error::new(e).context("writing the report"),
        other => anyhow::Error::new(BadInput(other.to_string())),
    })?;
    out.json(&serde_json::json!({ "report": written.display().to_string() }))?;
    out.say(|| format!("report written: {}", written.display()));
    Ok(())
}
