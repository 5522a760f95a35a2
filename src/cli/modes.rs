//! `rigfit modes`: the natural frequencies and mode shapes of the linearised
//! rig, one set per experiment.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::campaign_file::load;
use super::exit::BadInput;
use super::output::Output;
use rigfit::model::modes::{ModeReport, ModesError};

/// `rigfit modes`.
#[derive(Debug, Args)]
pub struct ModesArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Parameter file (e.g. a result.json) whose "params" replace the campaign's values.
    #[arg(long)]
    pub params: Option<PathBuf>,
}

/// Prints the natural frequencies and mode shapes of the linearised rig.
pub fn modes(args: &ModesArgs, out: &Output) -> Result<()> {
    let c = load(&args.campaign, args.params.as_deref())?;
    let mut reports = Vec::new();
    for (e, exp) in c.problem.experiments.iter().enumerate() {
        let lin = c.model.linearise(&c.base[e], &exp.drive);
        let report = ModeReport::new(&lin).map_err(|e| match e {
            // The rig's laws, not the program, are at fault: bad input.
            ModesError::NotFinite { .. } => anyhow::Error::new(BadInput(format!(
                "{}: experiment {:?}: {e}",
                args.campaign.display(),
                exp.name
            ))),
            other => anyhow::Error::new(other).context("modal analysis"),
        })?;
        reports.push((exp.name.clone(), report));
    }
    let about = c.model.linearisation_point();
    out.json(&serde_json::json!(
        reports
            .iter()
            .map(|(n, r)| serde_json::json!({"experiment": n, "linearised": about, "modes": r}))
            .collect::<Vec<_>>()
    ))?;
    out.say(|| {
        let mut s = String::new();
        for (name, r) in &reports {
            let _ = writeln!(s, "experiment {name}: {about}");
            let _ = writeln!(s, "{r}");
        }
        s.trim_end().to_string()
    });
    Ok(())
}
