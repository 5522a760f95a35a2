//! What a finished (or interrupted) job writes into its output folder:
//! result.json ([`JobSummary`], written last), one CSV and one plot per
//! experiment ([`ExperimentRows`]), history.csv and fitness.svg, all for the
//! best candidate; an interrupt stops it between two files.

use std::path::Path;

use super::JobError;
use crate::base::fsutil::atomic_write;
use crate::campaign::{Campaign, file_stem};
use crate::eval::{Batch, Evaluator, score_one};
use crate::report::plots;
use crate::search::{GeneSpec, SearchOutcome, write_history_csv};

mod provenance;
mod rows;
mod summary;
mod validation;
mod warnings;

pub use rows::{ExperimentRows, r_squared};
pub use summary::{ExperimentFit, JobSummary, ParamSummary, PolishSummary};
pub use validation::{
    FLAG_PREFIX, VALIDATION_FACTOR, ValidationFit, ValidationSummary, WARNING_PREFIX,
    simulate as simulate_validation, summarise as summarise_validation, validation_csv_name,
};
pub use warnings::{NOT_WHITE, SYSTEMATIC_MISFIT};

use rows::{ResidualFloor, experiment_csv};
use summary::{parameter_tables, polish_summary};
use warnings::{
    at_bound_warnings, lag_one_autocorrelation, misfit_warnings, not_determined_where_sensitive,
    search_warnings,
};

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
        None,
        &never,
    )
}

/// [`write_outputs`], stopped by `stop` (Ctrl-C) between two files or
/// stages, and within the best candidate's histories where the evaluator
/// can stop a batch partway: [`JobError::OutputsInterrupted`], naming the
/// files written before it. result.json is written last.
#[expect(
    clippy::too_many_arguments,
    reason = "write_outputs' arguments, the profiles and the flag that stops it"
)]
pub fn write_outputs_watched(
    campaign: &Campaign,
    evaluator: &mut dyn Evaluator,
    outcome: &SearchOutcome,
    genes: &[GeneSpec],
    out: &Path,
    fallback: Option<String>,
    backend_trial: Option<super::backend::BackendTrial>,
    profiles: Option<crate::search::ProfileOutcome>,
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
        let n = hist.t.len().min(exp.measured.len());
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
        let svg = plots::fit_svg(&title, &t_rec, &exp.measured[..n], &series)?;
        write(&plot, svg.as_bytes())?;
        check()?;
        let floor = ResidualFloor::of(exp, hist);
        let residual_rms = floor.rms;
        let residual_autocorrelation = floor.residuals.as_deref().and_then(lag_one_autocorrelation);
        experiments.push(ExperimentFit {
            name: exp.name.clone(),
            r2,
            one_minus_r2: 1.0 - r2,
            r2_cpu_reference: 1.0 - reference,
            residual_rms,
            unit: outputs
                .get(exp.output)
                .map_or(String::new(), |o| o.1.clone()),
            noise_estimate: floor.noise_estimate,
            cost_over_noise_floor: floor.cost_over_noise_floor,
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

    let (validation, validation_warnings, validation_flags) =
        validate_records(campaign, best, &experiments, &write, stop)?.ok_or_else(interrupted)?;

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
        super::verdict::polish_stop_warning(
            p,
            campaign.search.polish.max_iterations,
            outcome.method,
        )
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
    warnings.extend(validation_warnings);
    let mut more: Vec<String> = sensitivity.iter().filter_map(|s| s.flag()).collect();
    if apart.is_some() {
        more.push("polish starts disagree beyond their intervals".into());
    }
    more.extend(search.iter().map(|(flag, _)| flag.to_string()));
    let mut flags = super::verdict::flags(polish, &parameters, &experiments, more);
    // Last, as `rigfit validate` puts them.
    flags.extend(validation_flags);
    let ratio = campaign
        .problem
        .noise_floor()
        .map(|floor| fitness / floor)
        .filter(|k| k.is_finite());
    let inputs = provenance::input_digests(campaign);
    let verdict = super::Verdict::new(ratio, &parameters, uncertainty.is_some(), flags);
    let mut summary = JobSummary {
        rigfit_version: env!("CARGO_PKG_VERSION").into(),
        verdict,
        campaign: campaign.name.clone(),
        campaign_file: campaign.path.display().to_string(),
        records: provenance::record_digests(campaign),
        inputs,
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
        search_method: (outcome.method != crate::search::Method::Ga)
            .then(|| outcome.method.to_string()),
        search_summary: outcome.method_summary.clone(),
        fitness,
        polish: polish.map(|p| polish_summary(p, outcome.best_cost)),
        experiments,
        params,
        parameters,
        natural_frequencies_hz: provenance::natural_frequencies(campaign, &full),
        diverged_runs: outcome.history.iter().map(|r| r.diverged_runs).sum(),
        sensitivity,
        validation,
        profiles: None,
        warnings,
        peak_memory_mib: super::memory::peak_resident_memory()
            .map(|b| (b / super::memory::MIB * 10.0).round() / 10.0),
    };
    if let Some(profiles) = profiles {
        summary.warnings = super::verdict::replace_profile_warnings(&summary.warnings, &profiles);
        summary
            .verdict
            .replace_flags(super::verdict::PROFILE_FLAG_PREFIX, &profiles.flags());
        summary.profiles = Some(profiles);
    }
    let json = serde_json::to_string_pretty(&summary).expect("summary serialises");
    check()?;
    write("result.json", json.as_bytes())?;
    write_report(out, write);
    Ok(summary)
}

/// Writes report.html, built from the files just written
/// ([`crate::report::html::build_report`]). A report that cannot be built or
/// written is a warning on stderr, not a failed job: the numbers are
/// already written, and `rigfit report DIR` can build it again.
fn write_report(out: &Path, write: impl Fn(&str, &[u8]) -> Result<(), JobError>) {
    use crate::report::html::{REPORT_FILE, build_report};
    let failed = match build_report(out) {
        Ok(html) => write(REPORT_FILE, html.as_bytes())
            .err()
            .map(|e| e.to_string()),
        Err(e) => Some(e.to_string()),
    };
    if let Some(e) = failed {
        let note = format!("{REPORT_FILE} was not written: {e}");
        log::warn!("{note}");
        eprintln!("rigfit: warning: {note}");
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

/// The campaign's validation records ([`Campaign::validation`]) simulated
/// at `best` and written as `validation_<stem>.csv`: their summary for
/// `result.json`, its warnings and flags (none without validation records);
/// `None` once `stop` is raised.
#[expect(clippy::type_complexity, reason = "the three parts, used apart")]
fn validate_records(
    campaign: &Campaign,
    best: &[f64],
    experiments: &[ExperimentFit],
    write: &dyn Fn(&str, &[u8]) -> Result<(), JobError>,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<Option<(Option<ValidationSummary>, Vec<String>, Vec<String>)>, JobError> {
    let Some(v) = campaign.validation.as_deref() else {
        return Ok(Some((None, Vec::new(), Vec::new())));
    };
    let fitted = |name: &str| {
        let g = campaign.genes.iter().position(|g| g.name == name)?;
        best.get(g).copied()
    };
    let genome = match v.validation_genome(&fitted) {
        Ok(g) => g,
        Err(name) => {
            let w = format!(
                "{WARNING_PREFIX}simulation skipped: the validation records take `{name}` from \
                 the top-level params, but the fit did not search it (every estimation record \
                 sets its own)"
            );
            return Ok(Some((None, vec![w], Vec::new())));
        }
    };
    let Some(fits) = validation::simulate(v, &genome, stop) else {
        return Ok(None);
    };
    let mut list = Vec::new();
    for (fit, text) in fits {
        write(&fit.csv, text.as_bytes())?;
        list.push(fit);
    }
    let estimation: Vec<Option<f64>> = experiments
        .iter()
        .map(|x| x.cost_over_noise_floor)
        .collect();
    let (summary, mut warnings, flags) = validation::summarise(list, &estimation);
    warnings.splice(0..0, v.warnings.iter().cloned());
    Ok(Some((Some(summary), warnings, flags)))
}
