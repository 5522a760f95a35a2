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

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde::de::{MapAccess, Visitor};

use super::DesignError;
use super::grid::{DesignGrid, RawGrid};
use super::metrics::{Metric, MetricKind};
use crate::campaign::{Campaign, SimulationGrid};

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
    /// Design variables and their grids, in the file's order.
    pub variables: Variables,
    /// The metrics computed of every run.
    pub metrics: Vec<RawMetric>,
    /// RK4 steps per sample for every point, as `rigfit simulate
    /// --substeps` takes it (default: each point's own step, as `rigfit
    /// simulate` chooses it without noise).
    #[serde(default)]
    pub substeps: Option<u64>,
}

/// `{"name": grid, …}` in the file's order; a name given twice is refused.
#[derive(Debug)]
pub struct Variables(pub Vec<(String, RawGrid)>);

impl<'de> Deserialize<'de> for Variables {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Ordered;
        impl<'de> Visitor<'de> for Ordered {
            type Value = Variables;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an object of parameter names and their grids")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Variables, A::Error> {
                let mut out: Vec<(String, RawGrid)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if out.iter().any(|(k, _)| *k == key) {
                        return Err(serde::de::Error::custom(format!(
                            "variable '{key}' given twice"
                        )));
                    }
                    let grid = map.next_value::<RawGrid>()?;
                    out.push((key, grid));
                }
                Ok(Variables(out))
            }
        }
        d.deserialize_map(Ordered)
    }
}

/// One metric as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMetric {
    /// Its column in the table.
    pub name: String,
    /// What it computes.
    pub metric: MetricKind,
    /// The rig output it reads.
    pub output: String,
    /// The reference output of `ringing`, `ringing_hz`.
    #[serde(default)]
    pub against: Option<String>,
    /// The moving average's width (s) that is the reference of `ringing`,
    /// `ringing_hz` without `against`.
    #[serde(default)]
    pub window_s: Option<f64>,
    /// The level of `first_crossing` (output's unit).
    #[serde(default)]
    pub threshold: Option<f64>,
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
    /// Their values.
    pub grid: DesignGrid,
    /// The metrics, in the file's order.
    pub metrics: Vec<Metric>,
    /// Every file read: the sweep file, the campaign's, the parameter file.
    pub inputs: Vec<PathBuf>,
    /// One step (RK4 steps per sample) for every point, where the file sets
    /// it; `None`: each point's own.
    pub substeps: Option<usize>,
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
        let raw: RawSweep = parse(&text, path)?;
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
        if raw.variables.0.is_empty() {
            return Err(invalid(
                "variables".into(),
                "at least one design variable {\"name\": grid}".into(),
                "{}".into(),
            ));
        }
        let mut axes = Vec::new();
        for (name, g) in &raw.variables.0 {
            let values = g
                .values()
                .map_err(|(e, f)| invalid(format!("variables.{name}"), e, f))?;
            axes.push(values);
        }
        let grid = DesignGrid { axes };
        let points = grid.points().filter(|&n| n <= MAX_POINTS).ok_or_else(|| {
            invalid(
                "variables".into(),
                format!("at most {MAX_POINTS} design points"),
                "more".into(),
            )
        })?;
        debug_assert!(points >= 1);
        let variables: Vec<String> = raw.variables.0.iter().map(|(n, _)| n.clone()).collect();
        // The first point, applied on a copy: unknown names and values the
        // model refuses are refused here, naming the sweep file.
        let first = point_values(&variables, &grid.point(0));
        c.clone().apply_values(&first, path, "variables.")?;
        let most = crate::campaign::MAX_AUTO_SUBSTEPS;
        let substeps = match raw.substeps {
            Some(n) if n == 0 || n as usize > most => {
                return Err(invalid(
                    "substeps".into(),
                    format!("RK4 steps per sample from 1 to {most}"),
                    n.to_string(),
                ));
            }
            n => n.map(|n| n as usize),
        };
        let dt = c.problem.experiments[experiment].dt;
        let outputs: Vec<String> = c.model.output_names().iter().map(|o| o.0.clone()).collect();
        let mut metrics = Vec::new();
        let mut columns: Vec<&str> = vec!["point"];
        columns.extend(variables.iter().map(String::as_str));
        for (i, m) in raw.metrics.iter().enumerate() {
            let at = |key: &str| format!("metrics[{i}].{key}");
            if m.name.is_empty()
                || !m
                    .name
                    .chars()
                    .all(|ch| ch.is_ascii_alphanumeric() || "_.-".contains(ch))
            {
                return Err(invalid(
                    at("name"),
                    "a column name of letters, digits, '_', '.' or '-'".into(),
                    crate::base::text::echo(&m.name),
                ));
            }
            if columns.contains(&m.name.as_str()) {
                return Err(invalid(
                    at("name"),
                    "a name not yet taken by `point`, a variable or another metric".into(),
                    format!("'{}'", m.name),
                ));
            }
            columns.push(&m.name);
            let output_of = |key: &str, name: &str| {
                outputs.iter().position(|o| o == name).ok_or_else(|| {
                    invalid(
                        at(key),
                        format!("an output of rig {} ({})", c.model.id(), outputs.join(", ")),
                        format!("'{name}'"),
                    )
                })
            };
            let output = output_of("output", &m.output)?;
            let against = m
                .against
                .as_deref()
                .map(|a| output_of("against", a))
                .transpose()?;
            let reference = m.metric.uses_reference();
            if !reference && (m.against.is_some() || m.window_s.is_some()) {
                let key = if m.against.is_some() {
                    "against"
                } else {
                    "window_s"
                };
                return Err(invalid(
                    at(key),
                    "no reference: only ringing and ringing_hz compare with one".into(),
                    "a reference".into(),
                ));
            }
            let window_samples = match (reference, against, m.window_s) {
                (true, Some(_), Some(_)) => {
                    return Err(invalid(
                        at("window_s"),
                        "either \"against\" or \"window_s\", not both".into(),
                        "both".into(),
                    ));
                }
                (true, None, None) => {
                    return Err(invalid(
                        at("against"),
                        "a reference: \"against\": another output, or \"window_s\": a moving \
                         average's width (s)"
                            .into(),
                        "neither".into(),
                    ));
                }
                (true, None, Some(w)) => {
                    let n = (w / dt).round();
                    if !(n >= 3.0 && n.is_finite()) {
                        return Err(invalid(
                            at("window_s"),
                            format!(
                                "a width (s) of at least 3 samples (≥ {:e} s at dt = {dt:e} s)",
                                3.0 * dt
                            ),
                            w.to_string(),
                        ));
                    }
                    Some((n as usize) | 1)
                }
                _ => None,
            };
            let threshold = match (m.metric, m.threshold) {
                (MetricKind::FirstCrossing, Some(t)) if t.is_finite() => Some(t),
                (MetricKind::FirstCrossing, t) => {
                    return Err(invalid(
                        at("threshold"),
                        "a finite level (output's unit) that first_crossing looks for".into(),
                        t.map_or_else(|| "none".into(), |t| t.to_string()),
                    ));
                }
                (_, Some(_)) => {
                    return Err(invalid(
                        at("threshold"),
                        "no threshold: only first_crossing takes one".into(),
                        "a threshold".into(),
                    ));
                }
                (_, None) => None,
            };
            metrics.push(Metric {
                name: m.name.clone(),
                kind: m.metric,
                output,
                against,
                window_samples,
                threshold,
            });
        }
        if metrics.is_empty() {
            return Err(invalid(
                "metrics".into(),
                "at least one metric".into(),
                "[]".into(),
            ));
        }
        Ok(Sweep {
            file: path.to_path_buf(),
            campaign: c,
            experiment,
            runs,
            variables,
            grid,
            metrics,
            inputs,
            substeps,
        })
    }

    /// The number of design points.
    pub fn points(&self) -> usize {
        self.grid.points().unwrap_or(0)
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
