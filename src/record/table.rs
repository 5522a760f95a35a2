//! The in-memory record every reader produces, and the error a reader gives.

use std::fmt;

/// A file format rigfit reads records from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// Comma-, semicolon- or tab-separated text.
    Csv,
    /// NI LabVIEW / DIAdem TDMS.
    Tdms,
    /// HDF5 (and MATLAB v7.3, which is HDF5 underneath).
    Hdf5,
    /// MATLAB MAT-file, level 5 (v5, v6, v7).
    Mat,
    /// Universal file format, dataset 58 (ASCII or binary 58b).
    Uff,
    /// Arrays a caller holds in memory (the Python package's DataFrames),
    /// lent to a campaign without a file ([`super::lent`]).
    Memory,
}

/// Sample timing a file states for a channel: sample `k` is at
/// `start + k · increment` seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waveform {
    /// Time of the first sample (s).
    pub start: f64,
    /// Sample interval (s).
    pub increment: f64,
}

/// One channel (column) of a record.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// The name a campaign's column keys use (see each reader for its form:
    /// `group/channel` in TDMS, `/group/dataset` in HDF5, `variable` or
    /// `struct.field` in a MAT-file).
    pub name: String,
    /// The unit the file records for it (`N`, `kN`, `mV`, `s`), if any.
    pub unit: Option<String>,
    /// The samples, converted to `f64`.
    pub values: Vec<f64>,
    /// The channel's own sample timing, where the file gives one.
    pub timing: Option<Waveform>,
}

/// A record read from a file: its format and its channels in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// The format it was read from.
    pub format: Format,
    /// The channels, in the order the file holds them.
    pub channels: Vec<Channel>,
}

/// Why a file could not be read as its format: where in the file, what was
/// expected there, what was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{format} {at}: expected {expected}, found {found}")]
pub struct FormatError {
    /// The format being read.
    pub format: Format,
    /// Where: `byte 1234`, `segment 3`, `dataset /run1/force`, `variable s.f`.
    pub at: String,
    /// What the reader expected there.
    pub expected: String,
    /// What it found.
    pub found: String,
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Csv => "CSV",
            Format::Tdms => "TDMS",
            Format::Hdf5 => "HDF5",
            Format::Mat => "MAT-file",
            Format::Uff => "UFF 58",
            Format::Memory => "record in memory",
        })
    }
}
