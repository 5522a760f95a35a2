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
use super::metrics::{Formula, Metric, MetricKind};
use super::points::{Drawn, Points};
use super::sample::{Distribution, Method, unit_points};
use super::sobol::saltelli_design;
use super::uncertainty::Posterior;
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

/// `"sampling"`: how points are drawn from the variables' distributions.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSampling {
    /// `"random"`, `"latin"` or `"sobol"`.
    pub method: Method,
    /// How many points (the base count `n` of Saltelli's design).
    pub points: u64,
    /// The draw's seed (default 1).
    #[serde(default = "one")]
    pub seed: u64,
    /// Sobol sensitivity indices of every metric: the points become
    /// Saltelli's design, `n (k + 2)` runs for `k` variables.
    #[serde(default)]
    pub indices: bool,
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

fn one() -> u64 {
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

/// One variable as written: a grid or a distribution.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum RawVariable {
    /// `{"values": [...]}`.
    Values(Vec<f64>),
    /// `{"linear": [from, to, n]}`.
    Linear((f64, f64, f64)),
    /// `{"log": [from, to, n]}`.
    Log((f64, f64, f64)),
    /// `{"uniform": [lo, hi]}`.
    Uniform([f64; 2]),
    /// `{"loguniform": [lo, hi]}`.
    Loguniform([f64; 2]),
    /// `{"normal": [mean, sd]}`.
    Normal([f64; 2]),
    /// `{"lognormal": [median, sigma of ln]}`.
    Lognormal([f64; 2]),
    /// `{"triangular": [lo, mode, hi]}`.
    Triangular([f64; 3]),
}

impl RawVariable {
    /// The grid or the distribution.
    pub fn split(&self) -> Result<RawGrid, Distribution> {
        match self.clone() {
            Self::Values(v) => Ok(RawGrid::Values(v)),
            Self::Linear(r) => Ok(RawGrid::Linear(r)),
            Self::Log(r) => Ok(RawGrid::Log(r)),
            Self::Uniform(r) => Err(Distribution::Uniform(r)),
            Self::Loguniform(r) => Err(Distribution::Loguniform(r)),
            Self::Normal(r) => Err(Distribution::Normal(r)),
            Self::Lognormal(r) => Err(Distribution::Lognormal(r)),
            Self::Triangular(r) => Err(Distribution::Triangular(r)),
        }
    }
}

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

/// `{"name": grid, …}` in the file's order; a name given twice is refused.
#[derive(Debug)]
pub struct Variables(pub Vec<(String, RawVariable)>);

impl<'de> Deserialize<'de> for Variables {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Ordered;
        impl<'de> Visitor<'de> for Ordered {
            type Value = Variables;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an object of parameter names and their grids")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Variables, A::Error> {
                let mut out: Vec<(String, RawVariable)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if out.iter().any(|(k, _)| *k == key) {
                        return Err(serde::de::Error::custom(format!(
                            "variable '{key}' given twice"
                        )));
                    }
                    let grid = map.next_value::<RawVariable>()?;
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
    /// The rig output it reads (not for an expression).
    #[serde(default)]
    pub output: Option<String>,
    /// The formula of an `"expression"` metric.
    #[serde(default)]
    pub expression: Option<String>,
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
    /// Read only the span where another output is near its largest (the
    /// plateau).
    #[serde(default)]
    pub gate: Option<RawGate>,
}

/// `"gate": {"output": name, "above": fraction}`: the span from the first to
/// the last sample where the output's magnitude is at least `above` times
/// its largest.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawGate {
    /// The output that opens the gate.
    pub output: String,
    /// The fraction of its largest magnitude, in (0, 1].
    pub above: f64,
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
            if m.metric == MetricKind::Expression {
                metrics.push(formula_metric(m, i, &metrics, &variables, &invalid)?);
                continue;
            }
            if m.expression.is_some() {
                return Err(invalid(
                    at("expression"),
                    "an expression only with \"metric\": \"expression\"".into(),
                    "an expression".into(),
                ));
            }
            let Some(output_name) = &m.output else {
                return Err(invalid(
                    at("output"),
                    format!(
                        "the output it reads, of rig {} ({})",
                        c.model.id(),
                        outputs.join(", ")
                    ),
                    "none".into(),
                ));
            };
            let output = output_of("output", output_name)?;
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
            let gate = match &m.gate {
                None => None,
                Some(g) => {
                    if !(g.above > 0.0 && g.above <= 1.0) {
                        return Err(invalid(
                            at("gate.above"),
                            "a fraction in (0, 1] of the gate output's largest magnitude".into(),
                            g.above.to_string(),
                        ));
                    }
                    Some((output_of("gate.output", &g.output)?, g.above))
                }
            };
            metrics.push(Metric {
                name: m.name.clone(),
                kind: m.metric,
                output,
                against,
                window_samples,
                threshold,
                gate,
                formula: None,
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

/// An `"expression"` metric (`metrics[i]`): its formula parsed, every name
/// it reads one of the metrics before it or a design variable.
fn formula_metric(
    m: &RawMetric,
    i: usize,
    before: &[Metric],
    variables: &[String],
    invalid: &dyn Fn(String, String, String) -> DesignError,
) -> Result<Metric, DesignError> {
    let at = |key: &str| format!("metrics[{i}].{key}");
    for (key, given) in [
        ("output", m.output.is_some()),
        ("against", m.against.is_some()),
        ("window_s", m.window_s.is_some()),
        ("threshold", m.threshold.is_some()),
        ("gate", m.gate.is_some()),
    ] {
        if given {
            return Err(invalid(
                at(key),
                format!("no \"{key}\": an expression reads the metrics before it"),
                format!("\"{key}\""),
            ));
        }
    }
    let Some(text) = &m.expression else {
        return Err(invalid(
            at("expression"),
            "a formula of the metrics before it (\"100 * ring / peak\")".into(),
            "none".into(),
        ));
    };
    let expr = crate::compile::front::expr::parse(text).map_err(|e| {
        invalid(
            at("expression"),
            format!("a formula ({} at character {})", e.message, e.column),
            crate::base::text::echo(text),
        )
    })?;
    let mut used = Vec::new();
    expr.names(&mut used);
    let mut names = Vec::new();
    for (n, column) in used {
        let found = match before.iter().position(|x| x.name == n) {
            Some(k) => Ok(k),
            None => match variables.iter().position(|v| *v == n) {
                Some(j) => Err(j),
                None => {
                    let mut known: Vec<&str> = before.iter().map(|x| x.name.as_str()).collect();
                    known.extend(variables.iter().map(String::as_str));
                    return Err(invalid(
                        at("expression"),
                        format!(
                            "names of the metrics before it or of design variables ({})",
                            known.join(", ")
                        ),
                        format!("'{n}' at character {column}"),
                    ));
                }
            },
        };
        names.push((n, found));
    }
    Ok(Metric {
        name: m.name.clone(),
        kind: MetricKind::Expression,
        output: 0,
        against: None,
        window_samples: None,
        threshold: None,
        gate: None,
        formula: Some(Formula { expr, names }),
    })
}

/// The design points the file asks for: the product of grids, or points
/// drawn from distributions as `"sampling"` says.
fn design_points(
    raw: &RawSweep,
    invalid: &dyn Fn(String, String, String) -> DesignError,
) -> Result<Points, DesignError> {
    if raw.variables.0.is_empty() {
        return Err(invalid(
            "variables".into(),
            "at least one design variable {\"name\": grid or distribution}".into(),
            "{}".into(),
        ));
    }
    let split: Vec<(&String, Result<RawGrid, Distribution>)> = raw
        .variables
        .0
        .iter()
        .map(|(n, v)| (n, v.split()))
        .collect();
    let drawn = split.iter().filter(|(_, v)| v.is_err()).count();
    if drawn > 0 && drawn < split.len() {
        let (name, _) = split.iter().find(|(_, v)| v.is_ok()).expect("a grid");
        return Err(invalid(
            format!("variables.{name}"),
            "every variable a distribution (the others are) or every one a grid".into(),
            "a grid".into(),
        ));
    }
    if drawn == 0 {
        if raw.sampling.is_some() {
            return Err(invalid(
                "sampling".into(),
                "no \"sampling\" for a grid: it draws from distributions \
                 ({\"uniform\": [lo, hi]}, …)"
                    .into(),
                "\"sampling\"".into(),
            ));
        }
        let mut axes = Vec::new();
        for (name, g) in &split {
            let g = g.as_ref().expect("a grid");
            let values = g
                .values()
                .map_err(|(e, f)| invalid(format!("variables.{name}"), e, f))?;
            axes.push(values);
        }
        let grid = DesignGrid { axes };
        grid.points().filter(|&n| n <= MAX_POINTS).ok_or_else(|| {
            invalid(
                "variables".into(),
                format!("at most {MAX_POINTS} design points"),
                "more".into(),
            )
        })?;
        return Ok(Points::Grid(grid));
    }
    let Some(sampling) = &raw.sampling else {
        return Err(invalid(
            "sampling".into(),
            "{\"method\": \"random\", \"latin\" or \"sobol\", \"points\": n}: how to draw \
             the variables' distributions"
                .into(),
            "none".into(),
        ));
    };
    let mut distributions = Vec::new();
    for (name, d) in &split {
        let d = *d.as_ref().expect_err("a distribution");
        d.check()
            .map_err(|(e, f)| invalid(format!("variables.{name}"), e, f))?;
        distributions.push(d);
    }
    let k = distributions.len();
    let n = sampling.points;
    let rows = if sampling.indices {
        n.checked_mul(k as u64 + 2)
    } else {
        Some(n)
    };
    if n < 2 || rows.is_none_or(|r| r > MAX_POINTS as u64) {
        return Err(invalid(
            "sampling.points".into(),
            format!(
                "from 2 to {} points{}",
                if sampling.indices {
                    MAX_POINTS / (k + 2)
                } else {
                    MAX_POINTS
                },
                if sampling.indices {
                    " (Saltelli's design runs n (k + 2))"
                } else {
                    ""
                }
            ),
            n.to_string(),
        ));
    }
    let n = n as usize;
    let unit = if sampling.indices {
        saltelli_design(sampling.method, n, k, sampling.seed)
    } else {
        unit_points(sampling.method, n, k, sampling.seed)
    }
    .map_err(|why| invalid("sampling".into(), why, format!("{k} variables")))?;
    let values = unit
        .iter()
        .map(|u| {
            u.iter()
                .zip(&distributions)
                .map(|(&u, d)| d.quantile(u))
                .collect()
        })
        .collect();
    Ok(Points::Drawn(Drawn {
        method: sampling.method,
        base: n,
        seed: sampling.seed,
        distributions,
        values,
        indices: sampling.indices,
    }))
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
