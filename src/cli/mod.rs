//! The binary's commands: arguments in, library calls, human or JSON output.

pub mod args;
mod campaign_cmds;
mod devices;
pub mod identify;
mod precal;
mod run;

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};

use args::{Cli, Command};

/// Exit code of a job that failed after its input was accepted.
pub const EXIT_FAILED: u8 = 1;
/// Exit code of bad input or usage.
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code of a job stopped by Ctrl-C / SIGTERM (checkpoint written).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Where results go: a human summary on stdout unless `--quiet`, or one JSON
/// document on stdout with `--json`.
#[derive(Debug, Clone, Copy)]
pub struct Output {
    /// `--quiet`.
    pub quiet: bool,
    /// `--json`.
    pub json: bool,
}

impl Output {
    /// Prints the human text (built lazily) unless quiet or JSON.
    pub fn say(&self, text: impl FnOnce() -> String) {
        if !self.quiet && !self.json {
            print_stdout(&text());
        }
    }

    /// Prints `value` as JSON when `--json`.
    pub fn json(&self, value: &impl serde::Serialize) -> Result<()> {
        if self.json {
            print_stdout(&serde_json::to_string_pretty(value)?);
        }
        Ok(())
    }

    /// A note on stderr (not in quiet mode).
    pub fn note(&self, text: &str) {
        if !self.quiet {
            eprintln!("rigfit: {text}");
        }
    }
}

/// Writes one line to stdout. A reader that has gone away (`rigfit … | head`)
/// is no error: there is nobody left to tell, and the job's files are written
/// either way.
pub fn print_stdout(text: &str) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{text}").and_then(|()| out.flush());
}

/// Writes a campaign fragment atomically.
pub fn write_fragment(path: &Path, fragment: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(fragment)? + "\n";
    rigfit::base::fsutil::atomic_write(path, text.as_bytes())
        .with_context(|| format!("writing `{}`", path.display()))
}

/// Runs the parsed command line.
pub fn dispatch(cli: Cli) -> Result<ExitCode> {
    let out = Output {
        quiet: cli.quiet,
        json: cli.json,
    };
    match &cli.command {
        Command::Run(a) => return run::run(a, &out),
        Command::Simulate(a) => campaign_cmds::simulate(a, &out)?,
        Command::Modes(a) => campaign_cmds::modes(a, &out)?,
        Command::Check(a) => campaign_cmds::check(a, &out)?,
        Command::Devices => devices::devices(&out)?,
        Command::FitSpecimen(a) => precal::fit_specimen(a, &out)?,
        Command::Ringdown(a) => precal::ringdown_cmd(a, &out)?,
        Command::Identify(a) => identify::identify(a, &out)?,
    }
    Ok(ExitCode::SUCCESS)
}

/// Exit code for an error: 2 when the input was at fault, 1 otherwise.
pub fn exit_code(err: &anyhow::Error) -> u8 {
    let bad_input = err.chain().any(|e| {
        e.is::<rigfit::campaign::CampaignError>()
            || e.is::<rigfit::base::data::DataError>()
            || e.is::<rigfit::identify::PrecalError>()
            || e.is::<BadInput>()
            || matches!(
                e.downcast_ref::<rigfit::job::JobError>(),
                Some(
                    rigfit::job::JobError::OutputInUse { .. }
                        | rigfit::job::JobError::NoCheckpoint { .. }
                        | rigfit::job::JobError::OutputPath { .. }
                        | rigfit::job::JobError::ForeignFile { .. }
                        | rigfit::job::JobError::OutputLocked { .. }
                )
            )
            || matches!(
                e.downcast_ref::<rigfit::search::SearchError>(),
                Some(
                    rigfit::search::SearchError::FingerprintMismatch { .. }
                        | rigfit::search::SearchError::CheckpointFormat { .. }
                        | rigfit::search::SearchError::InvalidGene { .. }
                        | rigfit::search::SearchError::InvalidSettings { .. }
                )
            )
    });
    if bad_input {
        EXIT_BAD_INPUT
    } else {
        EXIT_FAILED
    }
}

/// An input error found by the binary itself.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);
