//! Options the identification methods share: where the fragment and the
//! figure go, whether the fragment holds fixed values, and the fitted band.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::exit::BadInput;
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
    /// Replace the --out, --svg (and --csv) files when they exist (never the
    /// input records).
    #[arg(long)]
    pub overwrite: bool,
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

    /// Refuses the files this method would write, before any work, where
    /// one is one of the `inputs`, exists without `--overwrite`, is a folder
    /// or lies in a missing folder; `more` are the method's own outputs.
    pub fn check_files(
        &self,
        more: &[(&str, Option<&Path>)],
        inputs: &[&Path],
    ) -> Result<(), BadInput> {
        self.files().check(more, inputs, self.overwrite)
    }
}
