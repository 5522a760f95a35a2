//! The HTML report of a result folder, for `FitResult.report` when the
//! result it holds has no report.html of its own (a folder written before
//! reports were).

use std::path::PathBuf;

use pyo3::prelude::*;

use crate::errors;

/// The report.html `rigfit report FOLDER` would write, as text.
#[pyfunction]
pub fn report_html(py: Python<'_>, folder: PathBuf) -> PyResult<String> {
    py.allow_threads(|| rigfit::report::html::build_report(&folder))
        .map_err(|e| errors::raise(errors::Kind::Error, errors::chain(&e)))
}
