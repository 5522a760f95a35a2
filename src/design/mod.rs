//! Model-based design: the calibrated rig run over a grid of design changes
//! (`rigfit sweep`), every run reduced to named metrics.
//!
//! A sweep file ([`mod@file`]) names a campaign, optionally a parameter file of
//! calibrated values, the design variables with their grids ([`grid`]) and the
//! metrics ([`metrics`]), or their distributions ([`sample`]) drawn as
//! random, Latin hypercube or Sobol points ([`points`]), laid out as
//! Saltelli's design where Sobol indices ([`mod@sobol`]) are asked. Every design
//! point is simulated as `rigfit simulate --params` would simulate it, on the
//! experiment's record grid; the points run together on the CPU lanes or a
//! GPU ([`device`]) in chunks of bounded memory, and each run's metrics are
//! computed as its chunk finishes ([`run`]). With a calibration's
//! `result.json`, each point also runs at draws of the fitted parameters from
//! the polish's covariance ([`uncertainty`]), giving each metric a median and
//! a 95 % band. Pictures of the table are drawn as SVG ([`picture`]).

pub mod device;
pub mod figures;
pub mod file;
pub mod grid;
pub mod metrics;
pub mod picture;
pub mod points;
pub mod prediction;
pub mod run;
pub mod sample;
pub mod sensitivity;
pub mod sobol;
pub mod uncertainty;

use std::path::PathBuf;

use crate::campaign::CampaignError;

pub use device::GpuRuns;
pub use file::{Step, Sweep, point_values};
pub use grid::{DesignGrid, RawGrid};
pub use metrics::{Metric, MetricKind};
pub use points::Points;
pub use run::{Band, Engine, Row, RunOptions, Table, run_sweep};

/// Why a sweep was refused or could not run. Every message names the sweep
/// file and the JSON path, or the campaign's own file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// The sweep file could not be read.
    #[error("{}: cannot read: {message}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// The system's reason.
        message: String,
    },
    /// Not JSON, or JSON of the wrong shape: a wrong type, an unknown or
    /// missing key.
    #[error("{}:{line}:{column}: {path}: {message}", file.display())]
    Schema {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// JSON path of the offending value (`metrics[0].metric`).
        path: String,
        /// serde's description (names the expected type or keys).
        message: String,
    },
    /// A well-formed value that is out of range or inconsistent.
    #[error("{}: {path}: expected {expected}, found {found}", file.display())]
    Invalid {
        /// The file.
        file: PathBuf,
        /// JSON path of the offending value.
        path: String,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// The campaign, its parameter file, or a design point's values applied
    /// to it (those name the sweep file and `variables.<name>`).
    #[error(transparent)]
    Campaign(Box<CampaignError>),
    /// A design point the campaign refuses (a value its checks reject, a run
    /// too long).
    #[error("design point {point} ({values}): {source}")]
    Point {
        /// The point's number (its row).
        point: usize,
        /// Its values, `name = value, …`.
        values: String,
        /// The campaign's refusal.
        source: Box<CampaignError>,
    },
    /// The GPU could not run the sweep's runs.
    #[error("GPU: {0}")]
    Device(String),
    /// The histories of one chunk would not fit in memory.
    #[error(
        "the sweep needs about {needed_mib:.0} MiB for the histories of {points} run(s) at once \
         ({per_run_kib:.0} KiB each), more than {limit_mib:.0} MiB ({limit_from}); shorten the \
         record or give more memory"
    )]
    Memory {
        /// Runs held at once.
        points: usize,
        /// One run's history (KiB).
        per_run_kib: f64,
        /// What they need (MiB).
        needed_mib: f64,
        /// The limit (MiB).
        limit_mib: f64,
        /// Where the limit comes from.
        limit_from: String,
    },
}

impl From<CampaignError> for DesignError {
    fn from(e: CampaignError) -> Self {
        Self::Campaign(Box::new(e))
    }
}
