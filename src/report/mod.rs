//! What a calibration job writes: result file, per-experiment CSVs, history, plots.

pub mod plots;
