//! The summary a job writes as `result.json` ([`JobSummary`]): each
//! experiment's fit, each parameter's value and interval, the polish's
//! report, and how the parameter table is built from the best candidate.

use std::collections::BTreeMap;

use serde::Serialize;

use super::ExperimentRows;
use crate::campaign::{Campaign, GeneTarget};
use crate::search::{AtBound, PolishOutcome, PolishStop, SearchOutcome, StartReport, Uncertainty};

/// Fit quality of one experiment.
#[derive(Debug, Clone, Serialize)]
pub struct ExperimentFit {
    /// Experiment name.
    pub name: String,
    /// R² of the model's measured output over the fit window (the job's evaluator).
    pub r2: f64,
    /// `1 − R²` (the fitness).
    pub one_minus_r2: f64,
    /// R² of the same parameters with the f64 CPU reference.
    pub r2_cpu_reference: f64,
    /// Root mean square of the residual (model − measurement) over the fit
    /// window, in the measured output's unit; `None` for a run that blew up.
    pub residual_rms: Option<f64>,
    /// The unit of the measured output (and of `residual_rms`).
    pub unit: String,
    /// The record's noise (standard deviation, the measured output's unit) estimated
    /// from the record itself over the fit window ([`crate::base::noise::noise_sigma`]).
    pub noise_estimate: Option<f64>,
    /// `(residual_rms / noise_estimate)²`: the fit's mean square as a multiple
    /// of the noise floor that estimate implies (about 1 at the floor).
    pub cost_over_noise_floor: Option<f64>,
    /// Lag-one autocorrelation of the residual over the fit window: about 0
    /// (within `2/√N`) for white noise, large where the misfit is systematic.
    pub residual_autocorrelation: Option<f64>,
    /// The RK4 integration error of the measured output at the job's step, estimated at
    /// the fitted parameters, and its size against the residual.
    pub integration_error: crate::campaign::IntegrationError,
    /// Weight in the joint fitness.
    pub weight: f64,
    /// CSV with the measurement, every model output and the residual.
    pub csv: String,
    /// SVG plot of the fit.
    pub plot: String,
    /// The CSV's rows in full precision (the CSV holds them to 7
    /// significant digits); not in `result.json`.
    #[serde(skip)]
    pub rows: ExperimentRows,
}

/// One model parameter (or clock offset) in the result.
#[derive(Debug, Clone, Serialize)]
pub struct ParamSummary {
    /// Name as in the campaign (`"k1"`, `"v2.k_lin"`, `"v2.offset"`).
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// Value.
    pub value: f64,
    /// Whether the search fitted it.
    pub free: bool,
    /// `"log"` for a free parameter searched on a log scale (absent: linear).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<String>,
    /// Search bounds (free parameters).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bounds: Option<[f64; 2]>,
    /// Smallest and largest value in the final elite (best 10 %): a narrow
    /// range means the data pins the parameter down.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elite_range: Option<[f64; 2]>,
    /// Width of the elite range relative to the value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elite_relative_width: Option<f64>,
    /// Standard error at the optimum (free parameters, after the polish), in
    /// the parameter's unit; log-scale parameters: value × the error of ln value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_error: Option<f64>,
    /// 95 % interval from the Gauss–Newton covariance, in the gene's scale
    /// mapped back (asymmetric for log-scale parameters).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interval_95: Option<[f64; 2]>,
    /// Whether the data determine the parameter (free parameters, after the
    /// polish): false if its 95 % interval is wider than its bounds or the
    /// Jacobian does not see it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub determined: Option<bool>,
    /// The bound the fitted value sits at (`"lower"` or `"upper"`): the data
    /// may want a value beyond it, so it is not determined and its interval
    /// is one-sided (`null` on the bound's side).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at_bound: Option<AtBound>,
    /// Why it is not determined.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uncertainty_note: Option<String>,
    /// Parameters correlated with this one beyond ±0.99.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub correlated_with: Vec<String>,
}

/// The local polish in `result.json`.
#[derive(Debug, Clone, Serialize)]
pub struct PolishSummary {
    /// Why it stopped.
    pub stop: PolishStop,
    /// Levenberg–Marquardt iterations (one batch each).
    pub iterations: usize,
    /// Candidates scored (stencils included).
    pub evaluations: u64,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Joint fitness of the GA's best, before the polish.
    pub ga_fitness: f64,
    /// Which start gave the result (0: the GA's best).
    pub best_start: usize,
    /// Per start (distinct GA candidates, best first): joint fitness before and after.
    pub starts: Vec<StartReport>,
    /// Residuals behind the covariance (fit-window samples, all experiments).
    pub residuals: usize,
    /// `s²`, the pooled residual variance in the weighted residuals' units.
    pub residual_variance: f64,
    /// `s_e²` of each experiment's weighted residuals (experiment order): the
    /// covariance gives each experiment its own.
    pub experiment_variances: Vec<f64>,
    /// Free parameters, in the order of [`Self::correlation`].
    pub genes: Vec<String>,
    /// Correlation matrix of the free parameters; `null` where undetermined.
    pub correlation: Vec<Vec<Option<f64>>>,
}

/// One file a campaign was read from, in `result.json`'s `inputs`.
#[derive(Debug, Clone, Serialize)]
pub struct InputDigest {
    /// The path as the campaign names it (relative to the campaign's folder
    /// where it lies inside it).
    pub path: String,
    /// SHA-256 of its bytes, lowercase hex.
    pub sha256: String,
}

/// What one experiment read of its record file, in `result.json`'s
/// `records`: the file (as `inputs` names it) with its SHA-256, its format,
/// the channels read with the units the file records, and the rig output
/// they were fitted to.
#[derive(Debug, Clone, Serialize)]
pub struct RecordDigest {
    /// The record file, as in `inputs`.
    pub path: String,
    /// SHA-256 of its bytes (a record lent from memory: of its names and
    /// values), lowercase hex.
    pub sha256: String,
    /// What was read of it: the experiment, the format, the channels with
    /// the units the file records, the rig output fitted and its unit.
    #[serde(flatten)]
    pub read: crate::campaign::record_file::RecordUse,
}

/// One experiment's natural frequencies, in `result.json`'s
/// `natural_frequencies_hz`.
#[derive(Debug, Clone, Serialize)]
pub struct NaturalFrequencies {
    /// The experiment (as in `experiments[].name`).
    pub experiment: String,
    /// Undamped natural frequencies (Hz), lowest first.
    pub hz: Vec<f64>,
}

/// The content of `result.json`.
#[derive(Debug, Clone, Serialize)]
pub struct JobSummary {
    /// rigfit version that wrote the file.
    pub rigfit_version: String,
    /// The verdict in one line: at the noise floor or not, parameters
    /// determined, what is flagged.
    pub verdict: crate::job::Verdict,
    /// Campaign name.
    pub campaign: String,
    /// Campaign file.
    pub campaign_file: String,
    /// Every file the campaign was read from (the campaign file, its rig
    /// file if it names one, each data file), with its SHA-256 when the
    /// outputs were written.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub inputs: Vec<InputDigest>,
    /// What each experiment read of its record (format, channels, units).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub records: Vec<RecordDigest>,
    /// The rig's id.
    pub rig: String,
    /// Search seed.
    pub seed: u64,
    /// `"gpu"` or `"cpu"`.
    pub backend: String,
    /// Device description.
    pub device: String,
    /// What `auto` measured on each path and chose (absent when the path was
    /// forced, or `auto` had one path only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backend_trial: Option<crate::job::backend::BackendTrial>,
    /// `"f32"` or `"f64"`.
    pub precision: String,
    /// RK4 steps per sample.
    pub substeps: usize,
    /// Generations run.
    pub generations: usize,
    /// Candidate evaluations.
    pub evaluations: u64,
    /// The GA's wall time (s), across resumes: what the candidate-steps/s
    /// rate is measured over.
    pub wall_time_s: f64,
    /// The GA's and the polish's wall time together (s): the job's search.
    pub job_wall_time_s: f64,
    /// Why the search stopped.
    pub stop_reason: String,
    /// The search method (absent for the genetic algorithm, the default).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_method: Option<String>,
    /// What the method learned, beside the polish's covariance (CMA-ES: its
    /// mean, step, per-gene spread and correlation in scale space; absent for
    /// the genetic algorithm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_summary: Option<serde_json::Value>,
    /// Best joint fitness (weighted mean of `1 − R²`), after the polish.
    pub fitness: f64,
    /// The local polish and the uncertainty estimate (absent when disabled).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polish: Option<PolishSummary>,
    /// Per experiment.
    pub experiments: Vec<ExperimentFit>,
    /// Every parameter value, by name: feed this file to
    /// `rigfit simulate --params`.
    pub params: BTreeMap<String, f64>,
    /// Every parameter with unit, bounds and elite spread.
    pub parameters: Vec<ParamSummary>,
    /// The rig's undamped natural frequencies (Hz) at the fitted values, per
    /// experiment (linearised as `rigfit modes` does); an experiment whose
    /// linearisation fails has none, and none at all leaves the key out.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub natural_frequencies_hz: Vec<NaturalFrequencies>,
    /// Runs that blew up over the whole search.
    pub diverged_runs: usize,
    /// Whether the record is predictable at the fitted values (after a
    /// polish): see [`crate::job::sensitivity`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<crate::job::sensitivity::Sensitivity>,
    /// The campaign's validation records at the fitted values (absent
    /// without them): see [`super::ValidationSummary`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub validation: Option<super::ValidationSummary>,
    /// Profile likelihoods of the free parameters (absent unless the
    /// campaign asks for them, `"search": {"profiles": …}`, or `rigfit
    /// profile` added them): see [`crate::search::Profiles`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profiles: Option<crate::search::ProfileOutcome>,
    /// Notes: search warnings, CPU fallback.
    pub warnings: Vec<String>,
    /// Peak resident memory of the process up to writing this file (MiB),
    /// where the system tells it (Linux).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_memory_mib: Option<f64>,
}

/// The polish's report for `result.json`.
pub(super) fn polish_summary(p: &PolishOutcome, ga_fitness: f64) -> PolishSummary {
    let u = p.uncertainty.as_ref();
    PolishSummary {
        stop: p.stop,
        iterations: p.iterations,
        evaluations: p.evaluations,
        wall_time_s: p.wall_time_s,
        ga_fitness,
        best_start: p.best_start,
        starts: p.starts.clone(),
        residuals: u.map_or(0, |u| u.residuals),
        residual_variance: u.map_or(f64::NAN, |u| u.residual_variance),
        experiment_variances: u.map_or_else(Vec::new, |u| u.block_variances.clone()),
        genes: u.map_or_else(Vec::new, |u| {
            u.genes.iter().map(|g| g.name.clone()).collect()
        }),
        correlation: u.map_or_else(Vec::new, |u| u.correlation.clone()),
    }
}

/// The parameters of `best` by name, and their rows for `result.json`:
/// one per rig parameter, or one per experiment where they differ, and
/// each experiment's clock offset.
pub(super) fn parameter_tables(
    campaign: &Campaign,
    outcome: &SearchOutcome,
    best: &[f64],
    uncertainty: Option<&Uncertainty>,
) -> (BTreeMap<String, f64>, Vec<ParamSummary>) {
    let full = campaign.full_params(best);
    let model = &campaign.model;
    // Each campaign experiment once, by its first run (its channels share
    // its parameters).
    let experiments: Vec<(usize, &str)> = campaign
        .experiment_names()
        .into_iter()
        .enumerate()
        .filter_map(|(o, name)| Some((campaign.owners.iter().position(|&x| x == o)?, name)))
        .collect();
    let mut params = BTreeMap::new();
    let mut rows = Vec::new();
    let gene_of = |name: &str| campaign.genes.iter().position(|g| g.name == name);
    let mut row = |name: String, unit: &str, value: f64| {
        let g = gene_of(&name);
        let spread = g.and_then(|i| outcome.elite_spread.get(i));
        let u = g.and_then(|i| uncertainty.and_then(|u| u.genes.get(i)));
        params.insert(name.clone(), value);
        rows.push(ParamSummary {
            unit: unit.to_string(),
            value,
            free: g.is_some(),
            scale: g
                .filter(|&i| campaign.genes[i].scale == crate::base::Scale::Log)
                .map(|_| "log".to_string()),
            bounds: g.map(|i| [campaign.genes[i].lower, campaign.genes[i].upper]),
            elite_range: spread.map(|s| [s.min, s.max]),
            elite_relative_width: spread.map(|s| s.relative_width),
            std_error: u.and_then(|u| u.std_error),
            interval_95: u.and_then(|u| u.interval_95),
            determined: u.map(|u| u.determined),
            at_bound: u.and_then(|u| u.at_bound),
            uncertainty_note: u.and_then(|u| u.note.clone()),
            correlated_with: u.map_or_else(Vec::new, |u| u.correlated_with.clone()),
            name,
        });
    };
    for (i, info) in model.params().iter().enumerate() {
        let first = full[0].0[i];
        let per_experiment = campaign
            .genes
            .iter()
            .any(|g| g.target == GeneTarget::Param(i) && g.experiment.is_some());
        if !per_experiment && full.iter().all(|(p, _)| p[i] == first) {
            row(info.name.to_string(), &info.unit, first);
        } else {
            for &(e, name) in &experiments {
                row(format!("{name}.{}", info.name), &info.unit, full[e].0[i]);
            }
        }
    }
    for &(e, name) in &experiments {
        row(format!("{name}.offset"), "s", full[e].1);
    }
    (params, rows)
}
