//! `rigfit validate`: a finished job's fitted values tried on records it
//! did not fit. The records are simulated (f64 CPU reference) at the values
//! in RESULT_DIR/result.json and scored as the job scores its validation
//! records; their CSVs and result.json's `validation` key (with its warnings
//! and verdict flags) are written into the job's folder, and its report.html
//! is rebuilt.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result};
use clap::Args;

use super::exit::BadInput;
use super::output::Output;
use rigfit::campaign::Campaign;
use rigfit::job::{
    FLAG_PREFIX, FolderMode, OutputFolder, RESULT_FILE, WARNING_PREFIX, reopen, replace_flags,
    update_result_keys,
};

/// `rigfit validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// A finished job's folder (what `rigfit run` wrote: result.json and the
    /// rest).
    pub result_dir: PathBuf,
    /// A campaign file for the same rig: its "validation" records, or, in a
    /// file without "validation", its "experiments", are simulated at the
    /// job's fitted values (never fitted).
    pub campaign: PathBuf,
}

/// Simulates the records at the fitted values, writes their CSVs and the
/// `validation` key, and prints one line per record and the warnings.
pub fn validate(args: &ValidateArgs, out: &Output) -> Result<()> {
    let job = reopen(&args.result_dir).map_err(|e| BadInput(e.to_string()))?;
    let v = Campaign::load_validation(&args.campaign)?;
    for w in &v.warnings {
        out.note(&format!("warning: {w}"));
    }
    if v.model.id() != job.rig {
        return Err(BadInput(format!(
            "{}: rig '{}' is not the job's: {} was fitted with rig '{}'; validate with a \
             campaign of the same rig",
            args.campaign.display(),
            v.model.id(),
            args.result_dir.join(RESULT_FILE).display(),
            job.rig
        ))
        .into());
    }
    let genome = v
        .validation_genome(&|name| job.param(name))
        .map_err(|name| {
            BadInput(format!(
                "{}: params.{name}: not in {}: the records take `{name}` from the top-level \
             params, and the job has no value of that name (it fitted it per experiment, or \
             its campaign did not have it); set it in the records' own params",
                args.campaign.display(),
                args.result_dir.join(RESULT_FILE).display()
            ))
        })?;
    let csvs: Vec<String> = v
        .problem
        .experiments
        .iter()
        .map(|e| rigfit::job::validation_csv_name(&e.name))
        .collect();
    let mut files = vec![RESULT_FILE.to_string()];
    files.extend(csvs);
    // Held until result.json is written: no job runs in the folder meanwhile.
    let folder = OutputFolder::open(&args.result_dir, &files, &v.inputs, FolderMode::Overwrite)
        .map_err(|e| BadInput(e.to_string()))?;
    let never = AtomicBool::new(false);
    let fits = rigfit::job::simulate_validation(&v, &genome, &never)
        .context("simulating the validation records")?;
    let mut list = Vec::new();
    for (fit, text) in fits {
        let path = folder.path().join(&fit.csv);
        super::output::write_file(&path, text.as_bytes())?;
        list.push(fit);
    }
    let estimation: Vec<Option<f64>> = job.json["experiments"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|x| x["cost_over_noise_floor"].as_f64())
                .collect()
        })
        .unwrap_or_default();
    let (summary, new_warnings, flags) = rigfit::job::summarise_validation(list, &estimation);
    let mut warnings: Vec<String> = job.json["warnings"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|w| w.as_str().map(String::from))
                .filter(|w| !w.starts_with(WARNING_PREFIX))
                .collect()
        })
        .unwrap_or_default();
    warnings.extend(new_warnings.iter().cloned());
    let mut verdict = job.json["verdict"].clone();
    let mut entries = vec![
        (
            "validation".to_string(),
            serde_json::to_value(&summary).context("the validation summary")?,
        ),
        ("warnings".to_string(), warnings.into()),
    ];
    if verdict.is_object() {
        replace_flags(&mut verdict, FLAG_PREFIX, &flags);
        entries.push(("verdict".to_string(), verdict));
    }
    update_result_keys(folder.path(), entries)?;
    drop(folder);
    let report = rigfit::report::html::write_report(&args.result_dir);

    out.json(&summary)?;
    out.say(|| {
        let mut t = String::new();
        for e in &summary.experiments {
            t.push_str(&e.line());
            t.push('\n');
        }
        match summary.estimation_cost_over_noise_floor {
            Some(k) => t.push_str(&format!(
                "estimation records: at most {k:.2}× their noise floor; a record beyond {}× \
                 that is flagged",
                summary.factor
            )),
            None => t.push_str("estimation records: noise floor unknown"),
        }
        t
    });
    for w in &new_warnings {
        out.note(&format!("warning: {w}"));
    }
    match report {
        Ok(p) => out.note(&format!("report rebuilt: {}", p.display())),
        Err(e) => out.note(&format!("warning: report.html not rebuilt: {e}")),
    }
    Ok(())
}
