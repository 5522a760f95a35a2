//! A campaign read for a simulation (`rigfit simulate`) rather than a fit:
//! nothing is scored, so a record need not vary, may be continued past its
//! end, or need not exist at all (a synthetic record is made on a grid of the
//! user's own).

use std::path::{Path, PathBuf};

use super::CampaignError;
use super::error::invalid;
use crate::base::PiecewiseLinear;
use crate::base::data::Series;

/// Which samples a simulation runs on.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum SimulationGrid {
    /// Each experiment's own record up to the end of its fit window, as a fit
    /// runs it. The record is read but not scored: a constant placeholder
    /// column is accepted.
    #[default]
    Record,
    /// Each record's first sample time and interval, this many samples (fit
    /// windows ignored); past the record's end a drive column is held at its
    /// last value.
    RecordInterval {
        /// Samples to simulate (≥ 2).
        samples: usize,
    },
    /// No record is read: every experiment is sampled at `t = k·dt`,
    /// `k = 0..samples`. A drive the simulated experiment reads from a column
    /// of its data file is read from `drive_file` instead (same column, time
    /// column and scales), and resampled onto the grid, so that the drive the
    /// run takes is exactly the one written beside it. The other experiments'
    /// drive columns are not read: a zero force stands in for them.
    Uniform {
        /// Sample interval (s), finite and > 0.
        dt: f64,
        /// Samples (≥ 2).
        samples: usize,
        /// The file a drive column is read from (resolved as given, not
        /// against the campaign's folder: it is the user's own argument).
        drive_file: Option<PathBuf>,
        /// The experiment simulated, by name (`None`: the first).
        experiment: Option<String>,
    },
}

impl SimulationGrid {
    /// Whether the records are read at all.
    pub fn reads_records(&self) -> bool {
        !matches!(self, Self::Uniform { .. })
    }

    /// The samples the grid asks for, when it sets their number.
    pub fn samples(&self) -> Option<usize> {
        match self {
            Self::Record => None,
            Self::RecordInterval { samples } | Self::Uniform { samples, .. } => Some(*samples),
        }
    }
}

/// How a campaign's records are read: for a fit (scored, each must vary
/// inside its fit window) or for a simulation on `grid`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Reading<'a> {
    /// `run`, `check`, `modes`: every record read and scored.
    Fit,
    /// `simulate`.
    Simulate(&'a SimulationGrid),
}

impl<'a> Reading<'a> {
    /// Whether the records are scored (and so must vary).
    pub(crate) fn scores(self) -> bool {
        matches!(self, Self::Fit)
    }

    /// The uniform grid's interval, samples and drive file, when no record is
    /// read.
    pub(crate) fn uniform(self) -> Option<(f64, usize, Option<&'a Path>)> {
        match self {
            Self::Simulate(SimulationGrid::Uniform {
                dt,
                samples,
                drive_file,
                ..
            }) => Some((*dt, *samples, drive_file.as_deref())),
            _ => None,
        }
    }

    /// Whether experiment `e`, called `name`, is on a grid without a record
    /// but not the one simulated: its drive column is not read.
    pub(crate) fn bystander(self, e: usize, name: &str) -> bool {
        match self {
            Self::Simulate(SimulationGrid::Uniform { experiment, .. }) => match experiment {
                Some(simulated) => simulated != name,
                None => e != 0,
            },
            _ => false,
        }
    }

    /// The sample count a record is continued or cut to.
    pub(crate) fn record_samples(self) -> Option<usize> {
        match self {
            Self::Simulate(SimulationGrid::RecordInterval { samples }) => Some(*samples),
            _ => None,
        }
    }
}

/// The series of a grid without a record: times `k·dt` and a placeholder
/// measurement of zeros (never scored).
pub(crate) fn uniform_series(dt: f64, samples: usize) -> Series {
    Series {
        t: (0..samples).map(|k| k as f64 * dt).collect(),
        force: vec![0.0; samples],
        dt,
        warning: None,
    }
}

/// `table` resampled at `t` (linear between its breakpoints, held beyond its
/// ends), with a warning when the grid runs past the table's last time.
pub(crate) fn resample(
    table: &PiecewiseLinear,
    t: &[f64],
    source: &Path,
    at: &str,
    warnings: &mut Vec<String>,
) -> PiecewiseLinear {
    let (Some(&last), Some(&end)) = (table.t.last(), t.last()) else {
        return table.clone();
    };
    if end > last {
        warnings.push(format!(
            "{at}: the drive column of `{}` ends at {last} s; the simulation runs to {end} s \
             with its last value held",
            source.display()
        ));
    }
    PiecewiseLinear {
        t: t.to_vec(),
        value: t.iter().map(|&x| table.at(x)).collect(),
    }
}

/// The refusal of a drive column when no file holds it.
pub(crate) fn no_drive_file(file: &Path, at: &str) -> CampaignError {
    invalid(
        file,
        format!("{at}.column"),
        "a file to read the drive column from: without a record (--dt) rigfit simulate \
         reads it from --drive FILE",
        "no --drive file",
    )
}
