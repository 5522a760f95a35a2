//! Options the identification methods share: where the fragment and the
//! figure go, whether the fragment holds fixed values, and the fitted band.

use std::path::PathBuf;

use clap::Args;

use crate::cli::fragment::Files;

/// The band a method fits over (`--f-min`, `--f-max`).
#[derive(Debug, Args)]
pub struct Band {
    /// Lower edge of the fitted band (Hz).
    #[arg(long)]
    pub f_min: f64,
    /// Upper edge of the fitted band (Hz).
    #[arg(long)]
    pub f_max: f64,
}

impl Band {
    /// The band as (lower, upper) edges (Hz).
    pub fn edges(&self) -> (f64, f64) {
        (self.f_min, self.f_max)
    }
}

/// Options every method shares.
#[derive(Debug, Args)]
pub struct Common {
    /// Write the campaign fragment (JSON) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the figure (SVG) here.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write fixed values instead of free parameters with bounds and an init seed.
    #[arg(long)]
    pub fixed: bool,
}

impl Common {
    /// Where `--out` and `--svg` send the fragment and the figure.
    pub fn files(&self) -> Files<'_> {
        Files {
            fragment: self.out.as_deref(),
            figure: self.svg.as_deref(),
        }
    }
}
