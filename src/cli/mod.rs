//! The binary's commands: arguments in, library calls, human or JSON output.
//!
//! One module per command, each owning its arguments next to its code:
//! `run` (the calibration job), `validate` (a job's fitted values on records
//! it did not fit), `simulate`, `sweep` (design points' metrics), `modes`,
//! `check`, `devices`, `inspect` (what a record file holds), the
//! pre-calibration commands `fit_specimen` and `ringdown`, and `identify` (one
//! file per method), and the hidden `__read-hdf5` (`read_hdf5`: HDF5 read
//! for a parent rigfit). `args` gathers them into the command line. The helpers
//! below are shared; no command imports another.
//! - `output`: stdout, stderr and the files a command writes;
//! - `exit`: exit codes, the binary's input error and the error report;
//! - `interrupt`: Ctrl-C, SIGTERM and SIGUSR1 as a flag the work checks;
//! - `options`: options several commands share;
//! - `campaign_file`: loading a campaign for the commands that do not search;
//! - `record`: the CSV records of pre-calibration and identification;
//! - `fragment`: how those commands end (figure, campaign fragment, report).

pub mod args;
mod campaign_file;
mod check;
mod devices;
pub mod exit;
mod fit_specimen;
mod fragment;
mod identify;
mod inspect;
mod interrupt;
mod modes;
mod options;
mod output;
mod profile;
mod read_hdf5;
mod record;
mod report;
mod ringdown;
mod run;
mod series;
mod simulate;
mod sweep;
mod validate;

use std::process::ExitCode;

use anyhow::Result;

use args::{Cli, Command};
use output::Output;

/// Runs the parsed command line.
pub fn dispatch(cli: Cli) -> Result<ExitCode> {
    let out = Output {
        quiet: cli.quiet,
        json: cli.json,
    };
    match &cli.command {
        Command::Run(a) => return run::run(a, &out),
        Command::Profile(a) => return profile::profile(a, &out),
        Command::Series(a) => return series::series(a, &out),
        Command::ReadHdf5 => return read_hdf5::read_hdf5(),
        Command::Simulate(a) => simulate::simulate(a, &out)?,
        Command::Sweep(a) => sweep::sweep(a, &out)?,
        Command::Modes(a) => modes::modes(a, &out)?,
        Command::Check(a) => check::check(a, &out)?,
        Command::Devices => devices::devices(&out)?,
        Command::FitSpecimen(a) => fit_specimen::fit_specimen(a, &out)?,
        Command::Ringdown(a) => ringdown::ringdown(a, &out)?,
        Command::Identify(a) => identify::identify(a, &out)?,
        Command::Inspect(a) => inspect::inspect(a, &out)?,
        Command::Report(a) => report::report(a, &out)?,
        Command::Validate(a) => validate::validate(a, &out)?,
    }
    Ok(ExitCode::SUCCESS)
}
