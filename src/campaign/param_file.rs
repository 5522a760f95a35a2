//! Parameter files for `rigfit simulate --params FILE`: fixed values that
//! replace genes or fixed parameters of a loaded campaign.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::error::{invalid, parse_json};
use super::raw::RawSubsteps;
use super::resolve::unknown_param;
use super::stability::choose;
use super::{Campaign, CampaignError, Source};
use crate::base::ParamScope;
use crate::model::param_index;

/// `{"params": {...}}`; other keys (a `result.json`'s) are ignored.
#[derive(Debug, Deserialize)]
struct ParamFile {
    #[serde(deserialize_with = "super::raw::unique_keys")]
    params: BTreeMap<String, Option<f64>>,
}

/// What one key of the file sets.
enum Key {
    /// A model parameter in every experiment that takes the top-level value.
    Shared(usize),
    /// A parameter of one experiment.
    Own(usize, usize),
    /// One experiment's offset.
    Offset(usize),
}

/// Applies the file at `path` to `c` (see [`Campaign::apply_param_file`]).
pub(crate) fn apply(campaign: &mut Campaign, path: &Path) -> Result<(), CampaignError> {
    // Work on a copy so that a refused file leaves the campaign as it was.
    let mut next = campaign.clone();
    let c = &mut next;
    let text = std::fs::read_to_string(path).map_err(|e| CampaignError::Io {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let file: ParamFile = parse_json(&text, path)?;
    let model = c.model;
    for (key, &value) in &file.params {
        // `null` is +∞, as in a campaign (a result.json writes it for a
        // specimen that never breaks).
        let value = value.unwrap_or(f64::INFINITY);
        let at = format!("params.{key}");
        let target = match key.split_once('.') {
            None => {
                let i =
                    param_index(model, key).ok_or_else(|| unknown_param(path, &at, model, key))?;
                Key::Shared(i)
            }
            Some((exp, name)) => {
                let e = c.experiment_index(exp).map_err(|names| {
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
        match target {
            Key::Shared(i) => {
                for (base, src) in c.base.iter_mut().zip(&c.sources) {
                    if src[i] != Source::Own {
                        base[i] = value;
                    }
                }
            }
            Key::Own(e, i) => c.base[e][i] = value,
            Key::Offset(e) => c.base_offsets[e] = value,
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
                return Err(invalid(path, "params", expected, v[i].to_string()));
            }
        }
    }
    let requested = if c.solver.auto {
        RawSubsteps::Auto
    } else {
        RawSubsteps::Count(c.solver.substeps as u64)
    };
    let offset = |e: usize| super::build::latest_offset(c.base_offsets[e], &c.genes, e);
    let (substeps, auto, note) = choose(
        model,
        &c.problem.experiments,
        |e| c.bounds(e),
        offset,
        requested,
    )
    .map_err(|message| CampaignError::Unstable {
        file: path.to_path_buf(),
        path: "params".into(),
        message,
    })?;
    c.solver.substeps = substeps;
    c.solver.auto = auto;
    c.solver.note = note;
    c.problem.substeps = substeps;
    *campaign = next;
    Ok(())
}
