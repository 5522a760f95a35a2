//! The sweep file, read and validated into a [`Sweep`] before any run.
//!
//! ```json
//! {
//!   "campaign": "aa2024_t3_synthetic.json",
//!   "params": "results/aa2024/result.json",
//!   "experiment": "v2",
//!   "variables": {"c4": {"log": [1e3, 1e5, 5]}, "m1": {"values": [6.0, 7.9]}},
//!   "metrics": [
//!     {"name": "ring", "metric": "ringing", "output": "load_cell_force", "against": "specimen_force"},
//!     {"name": "peak_F", "metric": "peak", "output": "load_cell_force"}
//!   ]
//! }
//! ```
//!
//! Paths are relative to the sweep file's folder. `params` (optional) is a
//! parameter file as `rigfit simulate --params` takes it; `experiment`
//! defaults to the campaign's first.

mod metrics;
mod variables;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::DesignError;
use super::metrics::Metric;
use super::points::Points;
use super::uncertainty::Posterior;
use crate::campaign::{Campaign, SimulationGrid};

use metrics::read_metrics;
pub use metrics::{RawGate, RawMetric};
use variables::design_points;
pub use variables::{RawSampling, RawVariable, Variables};

/// The sweep file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSweep {
    /// The campaign file, relative to the sweep file.
    pub campaign: PathBuf,
    /// A parameter file whose values replace the campaign's.
    #[serde(default)]
    pub params: Option<PathBuf>,
    /// The experiment simulated (default: the campaign's first).
    #[serde(default)]
    pub experiment: Option<String>,
    /// Design variables and their grids or distributions, in the file's
    /// order.
    pub variables: Variables,
    /// How points are drawn from the variables' distributions.
    #[serde(default)]
    pub sampling: Option<RawSampling>,
    /// The calibration's uncertainty carried into every point.
    #[serde(default)]
    pub uncertainty: Option<RawUncertainty>,
    /// The metrics computed of every run.
    pub metrics: Vec<RawMetric>,
    /// The step: RK4 steps per sample for every point, as `rigfit simulate
    /// --substeps` takes it, `"each"` (each point's own, as `rigfit
    /// simulate` chooses it without noise) or `"shared"` (one chosen at the
    /// design's corners).
    #[serde(default)]
    pub substeps: Option<RawStep>,
}

/// `"substeps"`: a count, `"each"` or `"shared"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum RawStep {
    /// RK4 steps per sample.
    Count(u64),
    /// `"each"` or `"shared"`.
    Named(String),
}

/// `"uncertainty"`: draws of the fitted parameters run at every point.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawUncertainty {
    /// Draws per point (default [`DEFAULT_DRAWS`]).
    #[serde(default = "default_draws")]
    pub samples: u64,
    /// The draws' seed (default 1).
    #[serde(default = "one")]
    pub seed: u64,
}

pub(super) fn one() -> u64 {
    1
}

fn default_draws() -> u64 {
    DEFAULT_DRAWS as u64
}

/// Draws of the fitted parameters per design point by default.
pub const DEFAULT_DRAWS: usize = 64;

/// Most draws per point.
pub const MAX_DRAWS: usize = 100_000;

/// The level of the uncertainty's bands.
pub const BAND_LEVEL: f64 = 0.95;

/// How a sweep chooses its step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Each point's own, as `rigfit simulate --params` chooses it.
    Each,
    /// One step for every point: the finest the step rule chooses at the
    /// design's corners, held at each point to the stability rule's count.
    Shared,
    /// The count given, as `rigfit simulate --substeps` runs it.
    Fixed(usize),
}

/// The calibration's uncertainty as the sweep carries it.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncertainty {
    /// The fitted parameters the draws set (those the design does not).
    pub names: Vec<String>,
    /// The draws, each a value per name.
    pub draws: Vec<Vec<f64>>,
    /// The bands' level.
    pub level: f64,
}

/// A validated sweep: the campaign as every design point starts from, the
/// experiment, the design grid and the metrics.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The sweep file.
    pub file: PathBuf,
    /// The campaign read for a simulation on its records, the parameter file
    /// applied.
    pub campaign: Campaign,
    /// The problem experiment simulated (the experiment's first run).
    pub experiment: usize,
    /// The experiment's runs (one, or one per channel): the step is chosen
    /// for all of them, as `rigfit simulate` chooses it.
    pub runs: Vec<usize>,
    /// The variables' names, in the file's order.
    pub variables: Vec<String>,
    /// The design points.
    pub points: Points,
    /// The metrics, in the file's order.
    pub metrics: Vec<Metric>,
    /// Every file read: the sweep file, the campaign's, the parameter file.
    pub inputs: Vec<PathBuf>,
    /// How the step is chosen.
    pub step: Step,
    /// The calibration's uncertainty, where the file asks for it.
    pub uncertainty: Option<Uncertainty>,
}

/// Most design points one sweep may have.
pub const MAX_POINTS: usize = 100_000_000;

impl Sweep {
    /// Reads and validates the sweep file at `path`: the campaign is read and
    /// the first design point applied to it (so that an unknown variable is
    /// refused before any run).
    pub fn load(path: &Path) -> Result<Sweep, DesignError> {
        let text = crate::base::fsutil::read_description(path).map_err(|e| DesignError::Io {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Self::from_text(&text, path)
    }

    /// [`Sweep::load`] of a sweep file's text, as if read from `path`: its
    /// paths are relative to `path`'s folder and its messages name `path`
    /// (the Python package's sweep given as a dict).
    pub fn from_text(text: &str, path: &Path) -> Result<Sweep, DesignError> {
        let raw: RawSweep = parse(text, path)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let invalid = |at: String, expected: String, found: String| DesignError::Invalid {
            file: path.to_path_buf(),
            path: at,
            expected,
            found,
        };
        let campaign_file = dir.join(&raw.campaign);
        let mut c = Campaign::load_for_simulation(&campaign_file, &SimulationGrid::Record)?;
        let mut inputs = vec![path.to_path_buf()];
        inputs.extend(c.inputs.iter().cloned());
        if let Some(p) = &raw.params {
            let p = dir.join(p);
            c.apply_param_file(&p)?;
            inputs.push(p);
        }
        let runs = match &raw.experiment {
            None => c.runs_of(c.experiment_names()[0]),
            Some(name) => c.runs_of(name),
        }
        .map_err(|names| {
            invalid(
                "experiment".into(),
                format!("an experiment of the campaign ({names})"),
                format!("'{}'", raw.experiment.clone().unwrap_or_default()),
            )
        })?;
        let experiment = runs[0];
        let variables: Vec<String> = raw.variables.0.iter().map(|(n, _)| n.clone()).collect();
        let points = design_points(&raw, &invalid)?;
        let count = points.len();
        debug_assert!(count >= 1);
        // The first point, applied on a copy: unknown names and values the
        // model refuses are refused here, naming the sweep file.
        let first = point_values(&variables, &points.point(0));
        c.clone().apply_values(&first, path, "variables.")?;
        let most = crate::campaign::MAX_AUTO_SUBSTEPS;
        let step = match &raw.substeps {
            Some(RawStep::Count(n)) if *n == 0 || *n as usize > most => {
                return Err(invalid(
                    "substeps".into(),
                    format!("RK4 steps per sample from 1 to {most}, \"each\" or \"shared\""),
                    n.to_string(),
                ));
            }
            Some(RawStep::Count(n)) => Step::Fixed(*n as usize),
            Some(RawStep::Named(s)) if s == "each" => Step::Each,
            Some(RawStep::Named(s)) if s == "shared" => Step::Shared,
            Some(RawStep::Named(s)) => {
                return Err(invalid(
                    "substeps".into(),
                    format!("RK4 steps per sample from 1 to {most}, \"each\" or \"shared\""),
                    format!("\"{s}\""),
                ));
            }
            // A plain grid runs as `rigfit simulate --params` runs each
            // point; drawn points and uncertainty's draws share one step.
            None if matches!(points, Points::Grid(_)) && raw.uncertainty.is_none() => Step::Each,
            None => Step::Shared,
        };
        let uncertainty = match &raw.uncertainty {
            None => None,
            Some(u) => {
                let Some(result) = &raw.params else {
                    return Err(invalid(
                        "params".into(),
                        "a calibration's result.json: \"uncertainty\" draws its fitted \
                         parameters from the covariance there"
                            .into(),
                        "no \"params\"".into(),
                    ));
                };
                if u.samples < 2 || u.samples as usize > MAX_DRAWS {
                    return Err(invalid(
                        "uncertainty.samples".into(),
                        format!("from 2 to {MAX_DRAWS} draws per point"),
                        u.samples.to_string(),
                    ));
                }
                let posterior = Posterior::from_result(&dir.join(result))
                    .map_err(|why| {
                        invalid(
                            "params".into(),
                            "a result.json with a polish's covariance".into(),
                            why,
                        )
                    })?
                    .without(&variables);
                let draws = posterior.draws(u.samples as usize, u.seed);
                let names = posterior.names;
                if !names.is_empty() {
                    let first_draw = point_values(&names, &draws[0]);
                    c.clone().set_values(&first_draw, path, "uncertainty.")?;
                }
                Some(Uncertainty {
                    names,
                    draws,
                    level: BAND_LEVEL,
                })
            }
        };
        let runs_total =
            count.saturating_mul(1 + uncertainty.as_ref().map_or(0, |u| u.draws.len()));
        if runs_total > MAX_POINTS {
            return Err(invalid(
                "variables".into(),
                format!("at most {MAX_POINTS} runs (design points × (1 + draws))"),
                runs_total.to_string(),
            ));
        }
        let dt = c.problem.experiments[experiment].dt;
        let metrics = read_metrics(&raw.metrics, &c, &variables, dt, &invalid)?;
        Ok(Sweep {
            file: path.to_path_buf(),
            campaign: c,
            experiment,
            runs,
            variables,
            points,
            metrics,
            inputs,
            step,
            uncertainty,
        })
    }

    /// The number of design points.
    pub fn points(&self) -> usize {
        self.points.len()
    }

    /// Runs per design point: the point itself, and one per draw of the
    /// calibration's uncertainty.
    pub fn runs_per_point(&self) -> usize {
        1 + self.uncertainty.as_ref().map_or(0, |u| u.draws.len())
    }
}

/// A design point's values by variable name, as the campaign takes them.
pub fn point_values(names: &[String], values: &[f64]) -> BTreeMap<String, Option<f64>> {
    names
        .iter()
        .cloned()
        .zip(values.iter().map(|&v| Some(v)))
        .collect()
}

/// The sweep file's text parsed, errors naming the JSON path.
fn parse(text: &str, file: &Path) -> Result<RawSweep, DesignError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let de = &mut serde_json::Deserializer::from_str(text);
    let raw = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        DesignError::Schema {
            file: file.to_path_buf(),
            line: inner.line(),
            column: inner.column(),
            path: if path == "." {
                "(top level)".into()
            } else {
                path
            },
            message: inner.to_string(),
        }
    })?;
    de.end().map_err(|e| DesignError::Schema {
        file: file.to_path_buf(),
        line: e.line(),
        column: e.column(),
        path: "(top level)".into(),
        message: e.to_string(),
    })?;
    Ok(raw)
}
