//! `rigfit __read-hdf5`, hidden: the child a rigfit starts to read an HDF5
//! file (`rigfit::record::hdf5_child`). The file's bytes on stdin; the record
//! or the reader's error on stdout, in the binary answer the parent decodes.

use std::io::{Read, Write};
use std::process::ExitCode;

use anyhow::{Context, Result};

/// Reads stdin as HDF5 in this process and writes the answer to stdout.
pub fn read_hdf5() -> Result<ExitCode> {
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .read_to_end(&mut bytes)
        .context("reading the HDF5 file from stdin")?;
    let answer = rigfit::record::hdf5_child::answer(&bytes);
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(&answer)
        .and_then(|()| stdout.flush())
        .context("writing the answer to stdout")?;
    Ok(ExitCode::SUCCESS)
}
