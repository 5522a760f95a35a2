//! The measured records the pre-calibration and identification commands read,
//! with every error naming the file it came from.

use std::path::Path;

use anyhow::Result;

use super::exit::BadInput;
use rigfit::identify::IdentifyError;
use rigfit::identify::columns::{Table, sample_interval};
use rigfit::identify::csv_input::{self, TwoColumns};

/// A pre-calibration or identification error as one line that names the
/// input file, with its causes (why the file could not be read); an option's
/// value refused for itself (a mass below 0) is named without the file; one
/// refused against the record (a force column that is 0 throughout, a band
/// past its Nyquist frequency) by its command-line flag, with the file.
pub fn in_file(path: &Path, e: IdentifyError) -> anyhow::Error {
    if let IdentifyError::InvalidOption { name, reason } = &e
        && *name != "column"
    {
        return match flag(name) {
            Some((flag, true)) => BadInput(format!("{}: invalid {flag}: {reason}", path.display())),
            Some((flag, false)) => BadInput(format!("invalid {flag}: {reason}")),
            None => BadInput(e.to_string()),
        }
        .into();
    }
    let mut line = format!("{}: {e}", path.display());
    let mut cause = std::error::Error::source(&e);
    while let Some(c) = cause {
        line += &format!(": {c}");
        cause = c.source();
    }
    if let IdentifyError::TooFewPoints { what, .. } = &e
        && *what == "coherent lines in the band"
    {
        line += "; widen the band (--f-min, --f-max), lower --min-coherence (lines below it \
                 are left out), or check that the input and output columns (--input, \
                 --output) are the rig's excitation and its response";
    }
    BadInput(line).into()
}

/// The command-line flag of a library option's name, where the commands
/// that read records have one, and whether its value is judged against the
/// record (a column, a rate, a length) rather than for itself.
fn flag(name: &str) -> Option<(&'static str, bool)> {
    Some(match name {
        "force" => ("--force", true),
        "cut-off" => ("--cutoff", true),
        "decimation" => ("--decimation", true),
        "sample rate" => ("--sample-rate", true),
        "segment length" | "segment_len" => ("--segment", true),
        "band" => ("band (--f-min, --f-max)", true),
        "output" => ("--output", true),
        "filter order" => ("--filter-order", false),
        "mass" => ("--mass", false),
        "modes" => ("--modes", false),
        "terms" => ("--terms", false),
        _ => return None,
    })
}

/// Reads a two-column CSV file (x, then y).
pub fn read_two_columns(path: &Path) -> Result<TwoColumns> {
    csv_input::read_two_columns(path).map_err(|e| in_file(path, e))
}

/// A CSV record whose columns are chosen by header name or 1-based position.
pub struct Record<'a> {
    path: &'a Path,
    table: Table,
}

impl<'a> Record<'a> {
    /// Reads the record at `path`.
    pub fn read(path: &'a Path) -> Result<Self> {
        let table = Table::read(path).map_err(|e| in_file(path, e))?;
        Ok(Self { path, table })
    }

    /// The column `which` (a header name or a 1-based position).
    pub fn column(&self, which: &str) -> Result<&[f64]> {
        self.table.column(which).map_err(|e| self.error(e))
    }

    /// The columns `which`, in order.
    pub fn columns(&self, which: &[String]) -> Result<Vec<&[f64]>> {
        which.iter().map(|c| self.column(c)).collect()
    }

    /// The sample rate (Hz) of the uniformly sampled time column `t`.
    pub fn sample_rate(&self, t: &[f64]) -> Result<f64> {
        Ok(1.0 / sample_interval(t).map_err(|e| self.error(e))?)
    }

    /// The sample rate (Hz) of the time column `time`.
    pub fn time_column_rate(&self, time: &str) -> Result<f64> {
        self.sample_rate(self.column(time)?)
    }

    /// A library error about this record, naming its file.
    pub fn error(&self, e: IdentifyError) -> anyhow::Error {
        in_file(self.path, e)
    }
}
