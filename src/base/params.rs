//! Parameter descriptions shared by all models.

use serde::{Deserialize, Serialize};

/// Which runs a parameter belongs to by default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ParamScope {
    /// A property of the rig, shared by every experiment of a campaign.
    Rig,
    /// A property of one experiment (specimen law, drive velocity).
    Experiment,
}

/// How the search moves through a free parameter's range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// Uniform in the value.
    #[default]
    Linear,
    /// Uniform in the logarithm of the value (range must be positive).
    Log,
}

/// One model parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamInfo {
    /// Name used in campaign and result files.
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// What it is, in a phrase.
    pub doc: String,
    /// Rig-wide or per experiment.
    pub scope: ParamScope,
    /// Value used when a campaign does not mention the parameter, if any.
    pub default: Option<f64>,
    /// Scale the search uses when the campaign does not say.
    pub scale: Scale,
}
