//! The shared vocabulary every layer above speaks: parameters and their
//! scales, the sample grid and its walk, tables and drives, what a run reports
//! at each sample, measured records, seeded noise, how messages quote input,
//! how files are written and how a child process is tied to this one. It
//! imports nothing of the crate.

pub mod data;
mod drive;
pub mod encoding;
pub mod fsutil;
mod grid;
pub mod noise;
mod params;
mod sample;
pub mod stats;
pub(crate) mod tether;
pub mod text;

pub use drive::{Drive, PiecewiseLinear};
pub use grid::{SampleGrid, walk_grid};
pub use params::{ParamInfo, ParamScope, Scale};
pub use sample::{MeasuredSample, Report, Sample, lane_bits};
