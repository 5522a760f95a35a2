//! The one way every pre-calibration and identification command ends: draw
//! the figure (`--svg`), write the campaign fragment (`--out`), then report
//! what was found, as JSON or as text.

use std::path::Path;

use anyhow::Result;

use super::exit::BadInput;
use super::output::{Output, check_out_files, write_file};
use rigfit::identify::plot::{Panel, panels_svg};

/// Where a command's files go.
#[derive(Debug, Clone, Copy)]
pub struct Files<'a> {
    /// `--out`: the campaign fragment (else it is printed after the report).
    pub fragment: Option<&'a Path>,
    /// `--svg`: the figure.
    pub figure: Option<&'a Path>,
}

impl Files<'_> {
    /// Refuses, before any work, the fragment, the figure and a command's
    /// `more` files (each with its flag) where one is an input, exists
    /// without `overwrite`, is a folder or lies in a missing folder
    /// ([`check_out_files`]).
    pub fn check(
        &self,
        more: &[(&str, Option<&Path>)],
        inputs: &[&Path],
        overwrite: bool,
    ) -> Result<(), BadInput> {
        let outs: Vec<(&str, &Path)> = [("--out", self.fragment), ("--svg", self.figure)]
            .iter()
            .chain(more)
            .filter_map(|&(flag, path)| path.map(|p| (flag, p)))
            .collect();
        check_out_files(&outs, inputs, overwrite)
    }
}

/// A figure: a title over panels laid out in columns. The panels are drawn
/// only when the figure is asked for.
pub struct Figure<P> {
    /// The title above every panel.
    pub title: String,
    /// The panels, left to right, then top to bottom.
    pub panels: P,
    /// How many panels a row holds.
    pub columns: usize,
}

/// What a command found: its JSON report, its campaign fragment and the text
/// a person reads.
pub struct Findings<T> {
    /// The report `--json` prints, the fragment added as "fragment".
    pub report: serde_json::Value,
    /// The campaign fragment `{"params": {…}}`.
    pub fragment: serde_json::Value,
    /// The human report, built only when printed; where the fragment went
    /// follows it.
    pub text: T,
}

impl<T: FnOnce() -> String> Findings<T> {
    /// Draws `figure` when `files` asks for it, then delivers the findings.
    pub fn deliver_with<P>(self, out: &Output, files: Files<'_>, figure: Figure<P>) -> Result<()>
    where
        P: FnOnce() -> Vec<Panel>,
    {
        if let Some(path) = files.figure {
            let svg = panels_svg(&figure.title, &(figure.panels)(), figure.columns)?;
            write_file(path, svg.as_bytes())?;
        }
        self.deliver(out, files.fragment)
    }

    /// Writes the fragment (to `path`, when given), then prints the report as
    /// JSON (with `--json`) or as text followed by where the fragment went.
    pub fn deliver(self, out: &Output, path: Option<&Path>) -> Result<()> {
        let Self {
            mut report,
            fragment,
            text,
        } = self;
        if let Some(path) = path {
            let json = serde_json::to_string_pretty(&fragment)? + "\n";
            write_file(path, json.as_bytes())?;
        }
        report["fragment"] = fragment.clone();
        out.json(&report)?;
        out.say(|| {
            let mut s = text();
            match path {
                Some(p) => s += &format!("campaign fragment written to {}", p.display()),
                None => {
                    s += "campaign fragment:\n";
                    s += &serde_json::to_string_pretty(&fragment).unwrap_or_default();
                }
            }
            s
        });
        Ok(())
    }
}
