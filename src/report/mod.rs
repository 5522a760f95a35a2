//! What a calibration job writes: result file, per-experiment CSVs, history, plots.

pub mod html;
pub mod plots;
