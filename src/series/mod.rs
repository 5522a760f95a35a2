//! A lab's test series: one campaign and a table of tests, or a list of
//! campaigns, calibrated as one piece of work, here or as a Slurm job array.
//!
//! A series file names what to run ([`SeriesFile`]). Preparing it
//! ([`prepare`]) writes the series' folder: a manifest of its tests
//! ([`Manifest`]: each test's campaign, seed, covariates and output folder),
//! and each test's campaign as a file of its own, so that every test is a
//! job `rigfit run` would run and write exactly so. The tests then run in one
//! process, several side by side on one device ([`local`]), or as the tasks
//! of a Slurm array ([`slurm`]), each task taking the GPU the scheduler gave
//! it ([`scheduler_gpu`]). Each test leaves a status file; the summary
//! ([`summary`]) reads them with the tests' `result.json` files, listing the
//! failed and missing tests with their error.
//!
//! The folder of a series:
//!
//! ```text
//! series.json            the manifest (tests, tasks, what was asked)
//! campaigns/<test>.json  each test's campaign (its record, seed and overrides)
//! tests/<test>/          each test's job folder, as `rigfit run` writes it
//! status/<test>.json     how each test ended (done, failed, interrupted)
//! slurm/                 the plan's scripts (with --slurm)
//! summary.csv, summary.html
//! ```

mod error;
mod file;
pub mod local;
mod manifest;
mod prepare;
pub mod scheduler_gpu;
pub mod slurm;
pub mod summary;
mod table;

pub use error::SeriesError;
pub use file::{SeriesFile, SeriesSource};
pub use manifest::{
    CAMPAIGNS_DIR, GENERATOR, MANIFEST_FILE, Manifest, STATUS_DIR, SUMMARY_CSV, SUMMARY_HTML,
    TESTS_DIR, TestEntry, TestState, TestStatus,
};
pub use prepare::prepare;
pub use table::{Overrides, TestRow};
