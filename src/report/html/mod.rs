//! report.html: one self-contained page per result folder, built from the
//! folder's files alone (result.json, the experiments' CSVs, history.csv),
//! so that a job and `rigfit report DIR` write the same bytes.
//!
//! - `input`: reading the folder, every key of result.json optional;
//! - `spectrum`: a residual's amplitude spectrum (Welch, Hann);
//! - `figures`: the figures' data, decimated for drawing;
//! - `page`: the HTML and its sections; `experiment`: an experiment's
//!   figures; `parameters`: the parameter table; `heatmap`: the correlation
//!   matrix; `style.css` and `script.js` are inlined, and the script draws
//!   the figures from the embedded data.
//!
//! The page asks for nothing outside itself: no links but `#anchors`, no
//! fonts, no requests; without JavaScript its tables still read.

use std::path::{Path, PathBuf};

mod experiment;
pub mod figures;
mod heatmap;
pub mod input;
pub(crate) mod page;
mod parameters;
pub mod spectrum;

/// The file name a result folder's report has.
pub const REPORT_FILE: &str = "report.html";

/// What every page rigfit writes carries near its start, and what
/// [`is_rigfit_report`] looks for before a page is replaced.
pub const GENERATOR: &str = r#"<meta name="generator" content="rigfit report">"#;

/// Why a report could not be built or written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be read or written.
    #[error("{}: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// What failed.
        source: std::io::Error,
    },
    /// result.json does not read.
    #[error("{}: at {path}: {message}", file.display())]
    Json {
        /// The file.
        file: PathBuf,
        /// The JSON path.
        path: String,
        /// What was expected.
        message: String,
    },
    /// A CSV does not read.
    #[error("{}: line {line}: expected {expected}", file.display())]
    Csv {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// What was expected.
        expected: String,
    },
    /// The folder holds nothing to report.
    #[error("{}: expected a result folder (result.json, or experiment CSVs with measured_ and model_ columns), found neither", dir.display())]
    Empty {
        /// The folder.
        dir: PathBuf,
    },
    /// The target exists and is not a page rigfit wrote (or is a link).
    #[error("{}: exists and is not a report rigfit wrote; expected a new file or an earlier report (refusing to replace it)", file.display())]
    Foreign {
        /// The file.
        file: PathBuf,
    },
}

/// The page for the result folder `dir`, as text.
pub fn build_report(dir: &Path) -> Result<String, ReportError> {
    page::build(dir)
}

/// The page of one record against the model alone (what `rigfit simulate`
/// writes): `csv` in an experiment CSV's columns, and the rig's natural
/// frequencies (Hz) to mark on the residual's spectrum.
pub fn build_record_report(
    name: &str,
    csv: input::FitCsv,
    natural_frequencies_hz: &[f64],
) -> String {
    let result = input::ResultFile {
        natural_frequencies_hz: vec![input::NaturalFrequencies {
            experiment: name.to_string(),
            hz: natural_frequencies_hz.to_vec(),
        }],
        ..Default::default()
    };
    let shown = [experiment::Shown {
        name: name.to_string(),
        csv,
    }];
    page::render(&result, false, None, &shown, &[], name)
}

/// Builds the page for `dir` and writes it as `dir/report.html`.
pub fn write_report(dir: &Path) -> Result<PathBuf, ReportError> {
    write_report_to(dir, &dir.join(REPORT_FILE))
}

/// Builds the page for `dir` and writes it to `out` (atomically), unless
/// `out` exists and is not a page rigfit wrote, or is a link.
pub fn write_report_to(dir: &Path, out: &Path) -> Result<PathBuf, ReportError> {
    let html = build_report(dir)?;
    if out.symlink_metadata().is_ok() && !is_rigfit_report(out) {
        return Err(ReportError::Foreign {
            file: out.to_path_buf(),
        });
    }
    crate::base::fsutil::atomic_write(out, html.as_bytes()).map_err(|source| ReportError::Io {
        file: out.to_path_buf(),
        source,
    })?;
    Ok(out.to_path_buf())
}

/// Whether `path` is a regular file (not a link) that starts as a page rigfit
/// wrote: [`GENERATOR`] within its first kilobyte.
pub fn is_rigfit_report(path: &Path) -> bool {
    use std::io::Read as _;
    let Ok(meta) = path.symlink_metadata() else {
        return false;
    };
    if !meta.file_type().is_file() {
        return false;
    }
    let mut head = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(1024).read_to_end(&mut head));
    read.is_ok() && String::from_utf8_lossy(&head).contains(GENERATOR)
}
