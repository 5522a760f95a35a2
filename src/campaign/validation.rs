//! A campaign's `"validation"` records: experiments in the form of
//! `"experiments"`, never fitted. They are built as a campaign of their own
//! ([`Campaign::validation`]) from the same file, so that the fitted
//! [`crate::eval::Problem`] never sees them; their genes are the shared free
//! parameters, set to the fitted values ([`Campaign::validation_genome`]).

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::build::build;
use super::error::invalid;
use super::simulation::Reading;
use super::{Campaign, CampaignError, GeneTarget};
use crate::record::lent::Lent;

/// [`build`] for a fit, with the file's `validation` records built as
/// [`Campaign::validation`]; their files join the campaign's inputs.
pub(super) fn build_fit(
    text: &str,
    dir: &Path,
    file: &Path,
    lent: &Lent,
) -> Result<Campaign, CampaignError> {
    let mut campaign = build(text, dir, file, Reading::Fit, lent)?;
    // The records against the rig, before any search.
    let heard = super::plausible::check(&campaign)?;
    campaign.warnings.extend(heard);
    let mut json = as_json(text);
    let Some(records) = json.as_object_mut().and_then(|o| o.remove("validation")) else {
        return Ok(campaign);
    };
    if records.as_array().is_some_and(Vec::is_empty) {
        return Err(invalid(
            file,
            "validation",
            "at least one record, in the form of \"experiments\" (or no \"validation\" key)",
            "an empty list",
        ));
    }
    let v = build_as(json, records, (dir, lent), file, "validation")?;
    let more: Vec<PathBuf> = v.inputs.iter().skip(1).cloned().collect();
    for p in more {
        if !campaign.inputs.contains(&p) {
            campaign.inputs.push(p);
        }
    }
    campaign.validation = Some(Box::new(v));
    Ok(campaign)
}

/// The campaign file at `path` read for validation only
/// ([`Campaign::load_validation`]).
fn load(path: &Path) -> Result<Campaign, CampaignError> {
    let text = crate::base::fsutil::read_description(path).map_err(|e| CampaignError::Io {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    // Every key checked as for a fit; the records' data read below only.
    let _: super::raw::RawCampaign = super::error::parse_json(&text, path)?;
    let mut json = as_json(&text);
    match json.as_object_mut().and_then(|o| o.remove("validation")) {
        Some(records) => build_as(json, records, (dir, &Lent::none()), path, "validation"),
        None => {
            let records = json["experiments"].clone();
            build_as(json, records, (dir, &Lent::none()), path, "experiments")
        }
    }
}

/// Campaign text that [`build`] has accepted, as a JSON value.
fn as_json(text: &str) -> Value {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).unwrap_or(Value::Null)
}

/// `records` built as the experiments of the campaign `json` (its rig and
/// shared parameters), their JSON paths under `at` (`validation` or
/// `experiments`); a free value of a record's own is refused.
fn build_as(
    mut json: Value,
    records: Value,
    (dir, lent): (&Path, &Lent),
    file: &Path,
    at: &str,
) -> Result<Campaign, CampaignError> {
    json["experiments"] = records.clone();
    let text = json.to_string();
    let mut v = build(&text, dir, file, Reading::Fit, lent).map_err(|e| at_validation(e, at))?;
    // A free parameter of the records' own has no fitted value.
    if let Some(g) = v.genes.iter().find(|g| g.experiment.is_some()) {
        let e = g.experiment.unwrap_or_default();
        let (path, what) = match g.target {
            GeneTarget::Offset => (format!("{at}[{e}].offset"), "offset".to_string()),
            GeneTarget::Param(i) => {
                let name = &v.model.params()[i].name;
                let key = if records[e]["params"].get(name.as_str()).is_some() {
                    "params"
                } else {
                    "initial"
                };
                (format!("{at}[{e}].{key}.{name}"), name.to_string())
            }
        };
        return Err(invalid(
            file,
            path,
            format!(
                "a number: a validation record is simulated at the fitted values, never \
                 fitted, so nothing would fit its own {what}; give it a fixed value in this \
                 entry (or leave it to the top-level params)"
            ),
            "a range {\"min\", \"max\"} (a free parameter)",
        ));
    }
    // Shared ranges the records override are fitted all the same.
    v.warnings.retain(|w| !w.contains("it is not searched"));
    let to = format!("{at}[");
    for w in &mut v.warnings {
        *w = w.replace("experiments[", &to);
    }
    // The records' text is the file's own; its digest is not.
    v.raw_json = String::new();
    Ok(v)
}

/// `e` with its JSON path (and a message naming an experiment) under `at`
/// rather than `experiments`.
fn at_validation(mut e: CampaignError, at: &str) -> CampaignError {
    let to = format!("{at}[");
    let rename = |s: &mut String| *s = s.replace("experiments[", &to);
    match &mut e {
        CampaignError::Invalid {
            path,
            expected,
            found,
            ..
        } => {
            rename(path);
            rename(expected);
            rename(found);
        }
        CampaignError::Unstable { path, message, .. }
        | CampaignError::TooLong { path, message, .. } => {
            rename(path);
            rename(message);
        }
        CampaignError::Schema { path, .. }
        | CampaignError::UnknownParam { path, .. }
        | CampaignError::MissingParams { path, .. }
        | CampaignError::RigParamInExperiment { path, .. }
        | CampaignError::Data { path, .. } => rename(path),
        _ => {}
    }
    if let CampaignError::Invalid { path, .. } = &mut e
        && path == "experiments"
    {
        *path = at.into();
    }
    e
}

impl Campaign {
    /// Reads a campaign file for `rigfit validate`: its `validation` records,
    /// or, in a file without that key, its `experiments`, as a validation
    /// campaign ([`Campaign::validation`]); a free parameter of a record's
    /// own is refused, naming its JSON path.
    pub fn load_validation(path: &Path) -> Result<Campaign, CampaignError> {
        load(path)
    }

    /// The genome of a validation campaign ([`Campaign::validation`]): each
    /// gene (a shared free parameter) at `fitted(name)`, the fitted value of
    /// that name. `Err` names a gene without a fitted value (the fit took it
    /// per experiment, or the campaign changed since).
    pub fn validation_genome(
        &self,
        fitted: &dyn Fn(&str) -> Option<f64>,
    ) -> Result<Vec<f64>, String> {
        self.genes
            .iter()
            .map(|g| fitted(&g.name).ok_or_else(|| g.name.clone()))
            .collect()
    }
}
