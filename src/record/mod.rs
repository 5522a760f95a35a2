//! Record files as data-acquisition software writes them — CSV, NI TDMS,
//! HDF5, MATLAB MAT-files (v5 and v7.3) and the universal file format's
//! dataset 58 — each read into one in-memory [`Record`]: named channels with
//! their values, their units where the file records one, and their sample
//! timing where the file gives it as a waveform (start and increment).

mod bits;
pub(crate) mod bytes;
pub mod csv;
pub mod detect;
pub mod hdf5;
pub mod hdf5_child;
pub mod lent;
pub mod mat;
pub mod select;
mod table;
pub mod tdms;
pub mod uff;
pub mod units;

pub use table::{Channel, Format, FormatError, Record, Waveform};
