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
/// value refused for itself is named without the file.
pub fn in_file(path: &Path, e: IdentifyError) -> anyhow::Error {
    // A value given on the command line is the option's fault, not the
    // record's (a column the record lacks is both: the file is named).
    if let IdentifyError::InvalidOption { name, .. } = &e
        && *name != "column"
    {
        return BadInput(e.to_string()).into();
    }
    let mut line = format!("{}: {e}", path.display());
    let mut cause = std::error::Error::source(&e);
    while let Some(c) = cause {
        line += &format!(": {c}");
        cause = c.source();
    }
    BadInput(line).into()
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
