//! Where a command's results go: a human summary or one JSON document on
//! stdout, notes on stderr, and files written whole or not at all.

use std::path::Path;

use anyhow::{Context, Result};

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

/// Writes a file the user asked for atomically: a reader never sees half of it.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    rigfit::base::fsutil::atomic_write(path, bytes)
        .with_context(|| format!("writing `{}`", path.display()))
}
