//! Where a command's results go: a human summary or one JSON document on
//! stdout, notes on stderr, and files written whole or not at all.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::exit::BadInput;

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

/// Refuses, before any work, the files a command was asked to write when
/// one of them is one of its inputs (even with `--overwrite`: rigfit never
/// writes over its inputs), exists without `--overwrite`, is a folder or
/// anything but a plain file, lies in a folder that does not exist, or is
/// named by two flags. `outs` pairs each flag (`--out`) with its path.
pub fn check_out_files(
    outs: &[(&str, &Path)],
    inputs: &[&Path],
    overwrite: bool,
) -> Result<(), BadInput> {
    let mut seen: Vec<(&str, &Path, PathBuf)> = Vec::new();
    for &(flag, out) in outs {
        let bad = |why: String| {
            let sep = if why.starts_with("is ") || why.starts_with("exists") {
                " "
            } else {
                ": "
            };
            BadInput(format!("{flag} `{}`{sep}{why}", out.display()))
        };
        if out.as_os_str().as_encoded_bytes().contains(&0) {
            return Err(bad("a path cannot hold a NUL character".into()));
        }
        let (Some(name), Some(parent)) = (out.file_name(), out.parent()) else {
            return Err(bad("expected a file name, found a folder".into()));
        };
        let parent = if parent.as_os_str().is_empty() {
            Path::new(".")
        } else {
            parent
        };
        match std::fs::metadata(parent) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => {
                return Err(bad(format!(
                    "expected a file in a folder, but `{}` is not a folder",
                    parent.display()
                )));
            }
            Err(_) => {
                return Err(bad(format!(
                    "the folder `{}` does not exist; create it first",
                    parent.display()
                )));
            }
        }
        let key = parent
            .canonicalize()
            .unwrap_or_else(|_| parent.to_path_buf())
            .join(name);
        if let Some((other, _, _)) = seen.iter().find(|(_, _, k)| *k == key) {
            return Err(bad(format!(
                "{other} names the same file; each output needs a file of its own"
            )));
        }
        seen.push((flag, out, key));
        let Ok(link) = std::fs::symlink_metadata(out) else {
            continue;
        };
        if let Some(input) = inputs.iter().find(|i| same_file(out, i)) {
            return Err(bad(format!(
                "is the input file `{}`; rigfit never writes over its inputs",
                input.display()
            )));
        }
        let meta = std::fs::metadata(out).unwrap_or(link);
        if meta.is_dir() {
            return Err(bad("expected a file name, found an existing folder".into()));
        }
        if !meta.is_file() && !meta.is_symlink() {
            return Err(bad(
                "expected a file name, found an existing device, FIFO or socket".into(),
            ));
        }
        if !overwrite {
            return Err(bad("exists; pass --overwrite to replace it".into()));
        }
    }
    Ok(())
}

/// Whether `a` and `b` are one file (through links, `..` or a hard link).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        a.canonicalize()
            .ok()
            .is_some_and(|x| b.canonicalize().ok() == Some(x))
    }
}
