//! `FitResult.save`: a result's files written into a folder by the rules of
//! a job's own outputs (`rigfit::job::save_files`): never through a link,
//! never over a file rigfit did not write, all or nothing.

use std::path::PathBuf;

use pyo3::exceptions::{PyFileExistsError, PyOSError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors;
use rigfit::job::{FolderMode, JobError};

/// Writes `files` (name, bytes) into `folder`. A folder that already holds a
/// result (without `overwrite`), a file rigfit did not write, a link or a
/// folder locked by a running job raise `FileExistsError`; a failed write
/// raises `OSError`, the folder left as it was.
#[pyfunction]
pub fn save_result(
    py: Python<'_>,
    folder: PathBuf,
    files: Vec<(String, Bound<'_, PyBytes>)>,
    overwrite: bool,
) -> PyResult<()> {
    errors::guard(|| {
        let files: Vec<(String, Vec<u8>)> = files
            .iter()
            .map(|(n, b)| (n.clone(), b.as_bytes().to_vec()))
            .collect();
        let mode = if overwrite {
            FolderMode::Overwrite
        } else {
            FolderMode::New
        };
        py.allow_threads(|| rigfit::job::save_files(&folder, &files, mode))
            .map_err(|e| match e {
                JobError::OutputInUse { path, found } => PyFileExistsError::new_err(format!(
                    "{} already holds a result ({found}); pass overwrite=True to replace \
                     rigfit's own files there, or choose another folder",
                    path.display()
                )),
                JobError::Write { .. } => PyOSError::new_err(errors::chain(&e)),
                _ => PyFileExistsError::new_err(errors::chain(&e)),
            })
    })
}
