//! What a finished (or interrupted) job writes into its output folder.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::JobError;
use crate::base::fsutil::atomic_write;
use crate::campaign::{Campaign, GeneTarget, file_stem};
use crate::eval::{Batch, Evaluator, History, score_one};
use crate::report::plots;
use crate::search::{
    AtBound, GeneSpec, PolishOutcome, PolishStop, SearchOutcome, StartReport, TerminationReason,
    Uncertainty, write_history_csv,
};

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

/// The content of `result.json`.
#[derive(Debug, Clone, Serialize)]
pub struct JobSummary {
    /// rigfit version that wrote the file.
    pub rigfit_version: String,
    /// The verdict in one line: at the noise floor or not, parameters
    /// determined, what is flagged.
    pub verdict: super::Verdict,
    /// Campaign name.
    pub campaign: String,
    /// Campaign file.
    pub campaign_file: String,
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
    pub backend_trial: Option<super::backend::BackendTrial>,
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
    /// Runs that blew up over the whole search.
    pub diverged_runs: usize,
    /// Whether the record is predictable at the fitted values (after a
    /// polish): see [`super::sensitivity`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<super::sensitivity::Sensitivity>,
    /// Notes: search warnings, CPU fallback.
    pub warnings: Vec<String>,
    /// Peak resident memory of the process up to writing this file (MiB),
    /// where the system tells it (Linux).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_memory_mib: Option<f64>,
}

/// Writes result.json, one CSV and one plot per experiment, history.csv and
/// fitness.svg for the best candidate: the polish's where it has one, else the
/// GA's. Returns the summary.
pub fn write_outputs(
    campaign: &Campaign,
    evaluator: &mut dyn Evaluator,
    outcome: &SearchOutcome,
    genes: &[GeneSpec],
    out: &Path,
    fallback: Option<String>,
    backend_trial: Option<super::backend::BackendTrial>,
) -> Result<JobSummary, JobError> {
    let never = std::sync::atomic::AtomicBool::new(false);
    write_outputs_watched(
        campaign,
        evaluator,
        outcome,
        genes,
        out,
        fallback,
        backend_trial,
        &never,
    )
}

/// [`write_outputs`], stopped by `stop` (Ctrl-C) between two files or
/// stages, and within the best candidate's histories where the evaluator
/// can stop a batch partway: [`JobError::OutputsInterrupted`], naming the
/// files written before it. result.json is written last.
#[expect(
    clippy::too_many_arguments,
    reason = "write_outputs' arguments and the flag that stops it"
)]
pub fn write_outputs_watched(
    campaign: &Campaign,
    evaluator: &mut dyn Evaluator,
    outcome: &SearchOutcome,
    genes: &[GeneSpec],
    out: &Path,
    fallback: Option<String>,
    backend_trial: Option<super::backend::BackendTrial>,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<JobSummary, JobError> {
    let polish = outcome.polish.as_ref();
    let written = std::cell::RefCell::new(Vec::<String>::new());
    let write = |name: &str, bytes: &[u8]| -> Result<(), JobError> {
        let path = out.join(name);
        atomic_write(&path, bytes).map_err(|source| JobError::Write { path, source })?;
        written.borrow_mut().push(name.to_string());
        Ok(())
    };
    let interrupted = || JobError::OutputsInterrupted {
        written: written.borrow().clone(),
    };
    let check = || -> Result<(), JobError> {
        if stop.load(std::sync::atomic::Ordering::SeqCst) {
            return Err(interrupted());
        }
        Ok(())
    };
    let info = evaluator.info();
    // The polish starts from the GA's best, so its result is never worse
    // (beyond the rounding of a different summation order).
    let polished = polish
        .filter(|p| p.best_cost.is_finite() && p.best_cost <= outcome.best_cost * (1.0 + 1e-9));
    let (best, fitness) = match polished {
        Some(p) => (&p.best_genome, p.best_cost),
        None => (&outcome.best_genome, outcome.best_cost),
    };
    let batch: Batch = campaign.batch(std::slice::from_ref(best));
    check()?;
    let histories = match evaluator.histories(&batch, &[0]) {
        Err(crate::eval::EvalError::Cancelled) => {
            check()?;
            return Err(crate::eval::EvalError::Cancelled.into());
        }
        other => other?.remove(0),
    };
    let full = campaign.full_params(best);
    let outputs = campaign.model.output_names();

    let mut experiments = Vec::new();
    for (e, (exp, hist)) in campaign
        .problem
        .experiments
        .iter()
        .zip(&histories)
        .enumerate()
    {
        check()?;
        let (params, offset) = &full[e];
        let r2 = r_squared(exp, hist);
        let (reference, _) = score_one(&campaign.problem, e, params, *offset);
        let stem = file_stem(&exp.name);
        let csv = format!("{stem}.csv");
        let plot = format!("fit_{stem}.svg");
        let rows = ExperimentRows::of(exp, hist, *offset);
        check()?;
        let Some(text) = experiment_csv(exp, &rows, outputs, stop) else {
            return Err(interrupted());
        };
        write(&csv, text.as_bytes())?;
        check()?;
        let n = hist.t.len().min(exp.force.len());
        let t_rec: Vec<f64> = (0..n).map(|k| exp.t_first + k as f64 * exp.dt).collect();
        let title = format!("{}: {} — R² = {:.5}", campaign.name, exp.name, r2);
        // The measured output first: the plot sets it against the record.
        let mut series: Vec<plots::Series<'_>> = outputs
            .iter()
            .zip(&hist.outputs)
            .map(|((name, unit), h)| plots::Series {
                name,
                unit,
                values: &h[..n.min(h.len())],
            })
            .collect();
        if exp.output < series.len() {
            let measured = series.remove(exp.output);
            series.insert(0, measured);
        }
        let svg = plots::fit_svg(&title, &t_rec, &exp.force[..n], &series)?;
        write(&plot, svg.as_bytes())?;
        check()?;
        let residuals = crate::eval::window_residuals(exp, hist).filter(|r| r.len() > 1);
        let residual_rms = residuals
            .as_ref()
            .map(|r| (r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64).sqrt());
        let residual_autocorrelation = residuals.as_deref().and_then(lag_one_autocorrelation);
        let noise_estimate = exp.noise_estimate();
        let cost_over_noise_floor = match (residual_rms, noise_estimate) {
            (Some(r), Some(n)) if n > 0.0 => Some((r / n).powi(2)),
            _ => None,
        };
        experiments.push(ExperimentFit {
            name: exp.name.clone(),
            r2,
            one_minus_r2: 1.0 - r2,
            r2_cpu_reference: 1.0 - reference,
            residual_rms,
            unit: outputs
                .get(exp.output)
                .map_or(String::new(), |o| o.1.clone()),
            noise_estimate,
            cost_over_noise_floor,
            residual_autocorrelation,
            integration_error: watched_integration_error(
                campaign,
                e,
                params,
                *offset,
                residual_rms,
                stop,
            )
            .ok_or_else(interrupted)?,
            weight: exp.weight,
            csv,
            plot,
            rows,
        });
    }

    check()?;
    let history_path = out.join("history.csv");
    write_history_csv(&history_path, &outcome.history, genes)?;
    written.borrow_mut().push("history.csv".into());
    let best_curve: Vec<f64> = outcome.history.iter().map(|r| r.best_cost).collect();
    let median_curve: Vec<f64> = outcome.history.iter().map(|r| r.median_cost).collect();
    let polish_curve: Vec<f64> = polish.map_or_else(Vec::new, |p| {
        p.history.iter().map(|i| i.best_cost).collect()
    });
    let svg = plots::convergence_svg(
        &format!("{}: fitness by generation, then the polish", campaign.name),
        &best_curve,
        &median_curve,
        &polish_curve,
        campaign.problem.noise_floor(),
    )?;
    write("fitness.svg", svg.as_bytes())?;

    let uncertainty = polish.and_then(|p| p.uncertainty.as_ref());
    let (params, mut parameters) = parameter_tables(campaign, outcome, best, uncertainty);
    // The intervals mean something only where the record is predictable.
    let sensitivity = uncertainty.map(|_| super::sensitivity::check(campaign, genes, best));
    let sensitive = sensitivity.as_ref().and_then(|s| s.warning());
    if let Some(s) = sensitivity.as_ref().filter(|s| s.sensitive) {
        not_determined_where_sensitive(&mut parameters, s);
    }
    let mut warnings = campaign.warnings.clone();
    warnings.extend(outcome.warnings.iter().cloned());
    let stop = polish.and_then(|p| {
        super::verdict::polish_stop_warning(p, campaign.search.polish.max_iterations)
    });
    warnings.extend(stop);
    warnings.extend(sensitive.clone());
    warnings.extend(at_bound_warnings(campaign, uncertainty));
    let search = search_warnings(outcome, polish);
    warnings.extend(search.iter().map(|(_, w)| w.clone()));
    let apart = polish
        .zip(uncertainty)
        .and_then(|(p, u)| super::verdict::starts_beyond_intervals(p, u));
    warnings.extend(apart.clone());
    warnings.extend(misfit_warnings(&experiments));
    let step = |x: &ExperimentFit| x.integration_error.warning(&x.name, &x.unit);
    warnings.extend(experiments.iter().filter_map(step));
    warnings.extend(fallback);
    let mut more: Vec<String> = sensitivity.iter().filter_map(|s| s.flag()).collect();
    if apart.is_some() {
        more.push("polish starts disagree beyond their intervals".into());
    }
    more.extend(search.iter().map(|(flag, _)| flag.to_string()));
    let flags = super::verdict::flags(polish, &parameters, &experiments, more);
    let ratio = campaign
        .problem
        .noise_floor()
        .map(|floor| fitness / floor)
        .filter(|k| k.is_finite());
    let verdict = super::Verdict::new(ratio, &parameters, uncertainty.is_some(), flags);
    let summary = JobSummary {
        rigfit_version: env!("CARGO_PKG_VERSION").into(),
        verdict,
        campaign: campaign.name.clone(),
        campaign_file: campaign.path.display().to_string(),
        rig: campaign.model.id().into(),
        seed: campaign.search.seed,
        backend: info.backend,
        device: info.device,
        backend_trial,
        precision: format!("{:?}", info.precision).to_lowercase(),
        substeps: campaign.solver.substeps,
        generations: outcome.generations,
        evaluations: outcome.evaluations,
        wall_time_s: outcome.wall_time_s,
        job_wall_time_s: outcome.wall_time_s + polish.map_or(0.0, |p| p.wall_time_s),
        stop_reason: outcome.termination.to_string(),
        fitness,
        polish: polish.map(|p| polish_summary(p, outcome.best_cost)),
        experiments,
        params,
        parameters,
        diverged_runs: outcome.history.iter().map(|r| r.diverged_runs).sum(),
        sensitivity,
        warnings,
        peak_memory_mib: super::memory::peak_resident_memory()
            .map(|b| (b / super::memory::MIB * 10.0).round() / 10.0),
    };
    let json = serde_json::to_string_pretty(&summary).expect("summary serialises");
    check()?;
    write("result.json", json.as_bytes())?;
    Ok(summary)
}

/// R² of the measured output against the measurement over the fit window.
pub fn r_squared(exp: &crate::eval::ExperimentData, hist: &History) -> f64 {
    let w = exp.window.clone();
    let n = w.len() as f64;
    let mean = exp.force[w.clone()].iter().sum::<f64>() / n;
    let mut ss_res = 0.0;
    let mut ss_tot = 0.0;
    for k in w {
        let m = hist.outputs[exp.output].get(k).copied().unwrap_or(f64::NAN);
        ss_res += (m - exp.force[k]).powi(2);
        ss_tot += (exp.force[k] - mean).powi(2);
    }
    1.0 - ss_res / ss_tot
}

/// An experiment's rows as its CSV holds them, in full precision: record
/// and model time, the measurement, every model output, the residual of the
/// measured output and whether the sample is in the fit window.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExperimentRows {
    /// Record time of each sample (s).
    pub t_record: Vec<f64>,
    /// Model time of each sample (s): record time + the clock offset.
    pub t_model: Vec<f64>,
    /// The measurement, in the measured output's unit.
    pub measured: Vec<f64>,
    /// Every model output at each sample, `[sample][output]` (NaN past a
    /// run that stopped short).
    pub model: Vec<Vec<f64>>,
    /// Measured output − measurement.
    pub residual: Vec<f64>,
    /// Whether each sample is scored.
    pub in_fit_window: Vec<bool>,
}

impl ExperimentRows {
    /// The rows of `exp` against the run `hist` at clock offset `offset`.
    pub fn of(exp: &crate::eval::ExperimentData, hist: &History, offset: f64) -> Self {
        let n = hist.t.len().min(exp.force.len());
        let value = |o: usize, k: usize| {
            hist.outputs
                .get(o)
                .and_then(|h| h.get(k))
                .copied()
                .unwrap_or(f64::NAN)
        };
        let t_record: Vec<f64> = (0..n).map(|k| exp.t_first + k as f64 * exp.dt).collect();
        Self {
            t_model: t_record.iter().map(|t| t + offset).collect(),
            t_record,
            measured: exp.force[..n].to_vec(),
            model: (0..n)
                .map(|k| (0..hist.outputs.len()).map(|o| value(o, k)).collect())
                .collect(),
            residual: (0..n)
                .map(|k| value(exp.output, k) - exp.force[k])
                .collect(),
            in_fit_window: (0..n).map(|k| exp.window.contains(&k)).collect(),
        }
    }
}

/// Records at least this long have their integration error estimated on a
/// thread of its own, so that an interrupt is honoured while it runs (its
/// step doubling runs the record three times, at up to four times the steps:
/// about ten seconds on a 2-million-sample record).
const WATCHED_ERROR_FROM_SAMPLES: usize = 100_000;

/// [`Campaign::integration_error`], `None` once `stop` is raised while it
/// runs on a long record (the estimate is then left to finish unread).
fn watched_integration_error(
    campaign: &Campaign,
    e: usize,
    params: &[f64],
    offset: f64,
    residual_rms: Option<f64>,
    stop: &std::sync::atomic::AtomicBool,
) -> Option<crate::campaign::IntegrationError> {
    use std::sync::atomic::Ordering;
    if campaign.problem.experiments[e].window.end < WATCHED_ERROR_FROM_SAMPLES {
        return Some(campaign.integration_error(e, params, offset, residual_rms));
    }
    let (own, params) = (campaign.clone(), params.to_vec());
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(own.integration_error(e, &params, offset, residual_rms));
    });
    loop {
        match rx.recv_timeout(std::time::Duration::from_millis(50)) {
            Ok(v) => return Some(v),
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                // The estimate panicked: as the caller's own call would.
                panic!("the integration error's estimate failed");
            }
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                if stop.load(Ordering::SeqCst) {
                    return None;
                }
            }
        }
    }
}

/// The experiment's CSV ([`ExperimentRows`]), the model outputs named
/// `model_<name>_<unit>` from the rig.
fn experiment_csv(
    exp: &crate::eval::ExperimentData,
    rows: &ExperimentRows,
    outputs: &[(String, String)],
    stop: &std::sync::atomic::AtomicBool,
) -> Option<String> {
    let (name0, unit0) = &outputs[exp.output];
    let mut s = format!("t_record_s,t_model_s,measured_{name0}_{unit0}");
    for (name, unit) in outputs {
        let _ = write!(s, ",model_{name}_{unit}");
    }
    let _ = writeln!(s, ",residual_{unit0},in_fit_window");
    for k in 0..rows.t_record.len() {
        // A record of millions of rows takes seconds: an interrupt is
        // honoured every 65 536 of them.
        if k % 65_536 == 0 && stop.load(std::sync::atomic::Ordering::SeqCst) {
            return None;
        }
        let _ = write!(
            s,
            "{:.9e},{:.9e},{:.6e}",
            rows.t_record[k], rows.t_model[k], rows.measured[k]
        );
        for o in 0..outputs.len() {
            let v = rows.model[k].get(o).copied().unwrap_or(f64::NAN);
            let _ = write!(s, ",{v:.6e}");
        }
        let _ = writeln!(
            s,
            ",{:.6e},{}",
            rows.residual[k],
            u8::from(rows.in_fit_window[k]),
        );
    }
    Some(s)
}

fn polish_summary(p: &PolishOutcome, ga_fitness: f64) -> PolishSummary {
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

fn parameter_tables(
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

/// Every free parameter not determined, with the sensitivity as the reason
/// (the intervals stay, as the covariance gives them, for the record).
fn not_determined_where_sensitive(
    parameters: &mut [ParamSummary],
    s: &super::sensitivity::Sensitivity,
) {
    let Some(note) = s.note() else {
        return;
    };
    for p in parameters.iter_mut().filter(|p| p.determined.is_some()) {
        p.determined = Some(false);
        let note = note.clone();
        p.uncertainty_note = Some(match p.uncertainty_note.take() {
            Some(n) => format!("{n}; {note}"),
            None => note,
        });
    }
}

/// One warning per gene the polish left at a bound, naming the bound to widen.
fn at_bound_warnings(campaign: &Campaign, uncertainty: Option<&Uncertainty>) -> Vec<String> {
    let Some(u) = uncertainty else {
        return Vec::new();
    };
    u.genes
        .iter()
        .zip(&campaign.genes)
        .filter_map(|(g, spec)| {
            let (side, bound) = match g.at_bound? {
                AtBound::Lower => ("lower", spec.lower),
                AtBound::Upper => ("upper", spec.upper),
            };
            Some(format!(
                "{} = {:.6e} sits at its {side} bound {bound:.6e}: the record may want a value \
                 beyond it, so it is not determined and its 95 % interval is open on that side; \
                 widen its range and run again",
                g.name, g.value
            ))
        })
        .collect()
}

/// Relative fall of the GA's best cost over the last generations above which
/// a search that stopped on its generation or time limit was still improving.
pub const STILL_IMPROVING: f64 = 5e-3;

/// Relative spread of the polished starts' costs above which they found
/// different minima.
pub const STARTS_DISAGREE: f64 = 1e-2;

/// Warnings on how the search ended: stopped by a limit while the GA's best
/// was still falling, or polished starts that ended in different minima;
/// each with the verdict's short flag for it.
fn search_warnings(
    outcome: &SearchOutcome,
    polish: Option<&PolishOutcome>,
) -> Vec<(&'static str, String)> {
    let mut out = Vec::new();
    let limited = matches!(
        outcome.termination,
        TerminationReason::MaxGenerations | TerminationReason::Timeout
    );
    if limited && let Some(last) = outcome.history.last() {
        let window = (outcome.history.len() / 10).max(5);
        let then = outcome.history[outcome.history.len().saturating_sub(window + 1)].best_cost;
        let fall = 1.0 - last.best_cost / then;
        if then.is_finite() && fall > STILL_IMPROVING {
            out.push((
                "search still improving when it stopped",
                format!(
                    "the search was still improving when it stopped ({}): its best 1 − R² fell \
                     {:.2} % over the last {window} generations; more generations or a larger \
                     population may fit better, and the intervals assume the optimum was reached",
                    outcome.termination,
                    100.0 * fall
                ),
            ));
        }
    }
    if let Some(p) = polish {
        let costs: Vec<f64> = p
            .starts
            .iter()
            .map(|s| s.polished)
            .filter(|c| c.is_finite())
            .collect();
        let best = costs.iter().copied().fold(f64::INFINITY, f64::min);
        let worst = costs.iter().copied().fold(0.0, f64::max);
        if costs.len() > 1 && worst > best * (1.0 + STARTS_DISAGREE) {
            out.push((
                "polish starts ended at different costs",
                format!(
                    "the polish's {} starts ended at different costs (1 − R² from {best:.4e} to \
                     {worst:.4e}): the cost has several minima near the GA's best; the result is \
                     the lowest found, and a longer search may find a lower one",
                    costs.len()
                ),
            ));
        }
    }
    out
}

/// The fit's mean square above which, as a multiple of the noise floor the
/// record's own noise implies, the misfit is more than noise.
pub const SYSTEMATIC_MISFIT: f64 = 4.0;

/// Lag-one autocorrelation of the residual above which it is not white: the
/// misfit has a shape, whatever its size against the noise.
pub const NOT_WHITE: f64 = 0.2;

/// `Σ (r_k − r̄)(r_{k+1} − r̄) / Σ (r_k − r̄)²`; `None` for a constant residual.
fn lag_one_autocorrelation(r: &[f64]) -> Option<f64> {
    let mean = r.iter().sum::<f64>() / r.len() as f64;
    let var: f64 = r.iter().map(|x| (x - mean) * (x - mean)).sum();
    let cov: f64 = r.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum();
    (var > 0.0).then(|| cov / var)
}

/// One warning per experiment whose residual is well above the record's noise
/// or is not white.
fn misfit_warnings(experiments: &[ExperimentFit]) -> Vec<String> {
    let shaped = experiments.iter().filter_map(|e| {
        let rho = e.residual_autocorrelation.filter(|r| *r > NOT_WHITE)?;
        Some(format!(
            "{}: the residual is not white (lag-one autocorrelation {rho:.2}, about 0 for noise): \
             part of the misfit has a shape the rig does not follow, and the intervals, which \
             assume white residuals, are too narrow",
            e.name
        ))
    });
    let large = experiments
        .iter()
        .filter_map(|e| {
            let k = e.cost_over_noise_floor.filter(|k| *k > SYSTEMATIC_MISFIT)?;
            Some(format!(
                "{}: the residual's RMS ({:.3e} {unit}) is {:.1}× the record's noise ({:.3e} {unit}, \
                 estimated from the record): the misfit is more than noise (a rig that cannot \
                 follow the record, or a search that did not finish), and the intervals assume it is not",
                e.name,
                e.residual_rms.unwrap_or(f64::NAN),
                k.sqrt(),
                e.noise_estimate.unwrap_or(f64::NAN),
                unit = e.unit
            ))
        });
    large.chain(shaped).collect()
}
