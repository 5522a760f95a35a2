//! Parameter files for `rigfit simulate --params FILE`: fixed values that
//! replace genes or fixed parameters of a loaded campaign. Two shapes are
//! read: `{"params": {...}}` (a run's `result.json` is one; its other keys are
//! ignored) and a flat object of values by name, `{"k": 4.0e4, "c": 12.0}`.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::error::{invalid, parse_json};
use super::resolve::unknown_param;
use super::{Campaign, CampaignError, Source};
use crate::base::ParamScope;
use crate::model::CompiledRig;
use crate::model::param_index;

/// `{"params": {...}}`; other keys (a `result.json`'s) are ignored.
#[derive(Debug, Deserialize)]
struct ParamFile {
    #[serde(deserialize_with = "super::raw::unique_keys")]
    params: BTreeMap<String, Option<f64>>,
}

/// Only whether the file has a `"params"` object: a flat file may name a
/// parameter `params`, but its value is then a number, not an object.
#[derive(Debug, Deserialize)]
struct Shape {
    params: Option<serde_json::Value>,
}

/// A flat object of values by name; a name given twice is refused.
#[derive(Debug)]
struct FlatFile(BTreeMap<String, Option<f64>>);

impl<'de> Deserialize<'de> for FlatFile {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        super::raw::unique_keys(d).map(FlatFile)
    }
}

/// The file's values by name, and the JSON path its keys sit under
/// (`"params."` or nothing).
fn read_values(
    text: &str,
    path: &Path,
) -> Result<(BTreeMap<String, Option<f64>>, &'static str), CampaignError> {
    let shape: Shape = parse_json(text, path)?;
    if shape
        .params
        .as_ref()
        .is_some_and(serde_json::Value::is_object)
    {
        let file: ParamFile = parse_json(text, path)?;
        return Ok((file.params, "params."));
    }
    match parse_json::<FlatFile>(text, path) {
        Ok(flat) => Ok((flat.0, "")),
        Err(CampaignError::Schema {
            file,
            line,
            column,
            path,
            message,
        }) => Err(CampaignError::Schema {
            file,
            line,
            column,
            path,
            message: format!(
                "{message}; a parameter file is {{\"params\": {{name: value, …}}}} (a result.json) \
                 or a flat object {{name: value, …}} of numbers (null: never)"
            ),
        }),
        Err(e) => Err(e),
    }
}

/// What one key of the file sets.
enum Key {
    /// A model parameter in every experiment that takes the top-level value.
    Shared(usize),
    /// A parameter of one experiment (its runs: one, or one per channel).
    Own(Vec<usize>, usize),
    /// One experiment's offset (its runs).
    Offset(Vec<usize>),
}

/// Applies the file at `path` to `c` (see [`Campaign::apply_param_file`]).
pub(crate) fn apply(campaign: &mut Campaign, path: &Path) -> Result<(), CampaignError> {
    let text = crate::base::fsutil::read_description(path).map_err(|e| CampaignError::Io {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let (values, under) = read_values(&text, path)?;
    apply_values(campaign, &values, path, under, true)
}

/// Applies `values` (by name, as a parameter file holds them; `None`: +∞)
/// to `campaign` as [`apply`] applies a file's: messages name `path` and the
/// JSON path `under` + name (see [`Campaign::apply_values`]); the step is
/// chosen again when `choose_step`.
pub(crate) fn apply_values(
    campaign: &mut Campaign,
    values: &BTreeMap<String, Option<f64>>,
    path: &Path,
    under: &str,
    choose_step: bool,
) -> Result<(), CampaignError> {
    // Work on a copy so that refused values leave the campaign as it was.
    let mut next = campaign.clone();
    let c = &mut next;
    let top = if under.is_empty() {
        "(top level)"
    } else {
        under.trim_end_matches('.')
    };
    let rig = c.model.clone();
    let model: &CompiledRig = &rig;
    for (key, &value) in values {
        // `null` is +∞, as in a campaign (a result.json writes it for a
        // specimen that never breaks).
        let value = value.unwrap_or(f64::INFINITY);
        let at = format!("{under}{key}");
        let target = match key.split_once('.') {
            None => {
                let i =
                    param_index(model, key).ok_or_else(|| unknown_param(path, &at, model, key))?;
                Key::Shared(i)
            }
            Some((exp, name)) => {
                let e = c.runs_of(exp).map_err(|names| {
                    let expected = format!("an experiment of the campaign ({names})");
                    invalid(path, &at, expected, format!("'{exp}'"))
                })?;
                if name == "offset" {
                    Key::Offset(e)
                } else {
                    let i = param_index(model, name)
                        .ok_or_else(|| unknown_param(path, &at, model, name))?;
                    if model.params()[i].scope == ParamScope::Rig {
                        return Err(CampaignError::RigParamInExperiment {
                            file: path.to_path_buf(),
                            path: at,
                            name: name.to_string(),
                        });
                    }
                    Key::Own(e, i)
                }
            }
        };
        match &target {
            Key::Shared(i) | Key::Own(_, i) => {
                let name = model.params()[*i].name.as_str();
                super::resolve::domain_of_value(path, &at, model, name, value)?;
            }
            Key::Offset(_) => {}
        }
        match target {
            Key::Shared(i) => {
                for (base, src) in c.base.iter_mut().zip(&c.sources) {
                    if src[i] != Source::Own {
                        base[i] = value;
                    }
                }
            }
            Key::Own(runs, i) => runs.iter().for_each(|&e| c.base[e][i] = value),
            Key::Offset(runs) => runs.iter().for_each(|&e| c.base_offsets[e] = value),
        }
        c.genes.retain(|g| g.name != *key);
    }
    for e in 0..c.base.len() {
        let (lo, hi) = c.bounds(e);
        for v in [&c.base[e], &lo, &hi] {
            if let Err((name, expected)) = model.check(v) {
                let i = param_index(model, name).unwrap_or(0);
                let exp = &c.problem.experiments[e].name;
                let expected = format!("{name}: {expected} (experiment '{exp}')");
                return Err(invalid(path, top, expected, v[i].to_string()));
            }
        }
    }
    if choose_step {
        c.choose_step_again(c.solver.tolerance, path, top)?;
    }
    *campaign = next;
    Ok(())
}
