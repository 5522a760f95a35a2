//! `rigfit profile`: profile likelihoods of a finished job's fitted
//! parameters, added to its result.json (and its report rebuilt).

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};

use super::exit::{BadInput, EXIT_INTERRUPTED};
use super::output::Output;
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, PrecisionChoice};
use rigfit::job::{self, CampaignCost, JobError};
use rigfit::search::{PolishSettings, PolishStop, Profiles};

/// Where the profiles' candidates are scored.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ProfileBackend {
    /// The CPU lanes (f64).
    Cpu,
    /// The GPU kernels.
    Gpu,
    /// As `run --backend auto` chooses.
    Auto,
}

/// `rigfit profile`.
#[derive(Debug, Args)]
pub struct ProfileArgs {
    /// A finished job's folder (its result.json names the campaign file).
    pub dir: PathBuf,
    /// Where to score (default: the backend the job ran on).
    #[arg(long, value_enum)]
    pub backend: Option<ProfileBackend>,
    /// Grid points per parameter besides the optimum (default: the
    /// campaign's `search.profiles.points`, else 12).
    #[arg(long)]
    pub points: Option<usize>,
    /// Grid reach on each side in covariance half-widths (default: the
    /// campaign's `search.profiles.span`, else 3).
    #[arg(long)]
    pub span: Option<f64>,
    /// CPU threads (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
}

/// Computes the profiles at the job's fitted point and writes them into its
/// result.json.
pub fn profile(a: &ProfileArgs, out: &Output) -> Result<ExitCode> {
    let reopened = job::reopen(&a.dir)?;
    let result_path = a.dir.join(job::RESULT_FILE);
    let campaign_path = reopened.campaign_path()?;
    let c = Campaign::load(&campaign_path)
        .with_context(|| format!("reading the campaign `{}`", campaign_path.display()))?;
    let mut settings = c.search.profiles.unwrap_or_default();
    if let Some(n) = a.points {
        settings.points = n;
    }
    if let Some(s) = a.span {
        settings.span = s;
    }
    if let Some((field, expected, found)) = settings.invalid() {
        return Err(BadInput(format!("--{field}: expected {expected}, found {found}")).into());
    }
    let genes = job::gene_specs(&c);
    if genes.is_empty() {
        return Err(BadInput(format!(
            "{}: the campaign has no free parameter to profile",
            campaign_path.display()
        ))
        .into());
    }
    // Held until result.json is written: no job or second profile runs in
    // the folder meanwhile.
    let files = [
        job::RESULT_FILE,
        job::PROFILE_CHECKPOINT_FILE,
        rigfit::report::html::REPORT_FILE,
    ]
    .map(String::from);
    let _folder = job::OutputFolder::open(&a.dir, &files, &c.inputs, job::FolderMode::Overwrite)
        .map_err(|e| BadInput(e.to_string()))?;
    let best = genes
        .iter()
        .map(|g| {
            reopened.param(&g.name).ok_or_else(|| JobError::ResultFile {
                path: result_path.clone(),
                json_path: format!("params.{}", g.name),
                reason: format!(
                    "missing: `{}` is a free parameter of {} but the job did not fit it (was \
                     the campaign changed since?)",
                    g.name,
                    campaign_path.display()
                ),
            })
        })
        .collect::<Result<Vec<f64>, JobError>>()?;
    let elite: Vec<Option<[f64; 2]>> = genes
        .iter()
        .map(|g| elite_range(&reopened.json, &g.name))
        .collect();
    let precision = match reopened.json["precision"].as_str() {
        Some("f32") => PrecisionChoice::F32,
        _ => PrecisionChoice::F64,
    };
    let backend = match a.backend {
        Some(ProfileBackend::Cpu) => Backend::Cpu,
        Some(ProfileBackend::Gpu) => Backend::Gpu,
        Some(ProfileBackend::Auto) => Backend::Auto,
        None if reopened.backend == "gpu" => Backend::Gpu,
        None => Backend::Cpu,
    };
    let interrupt = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupt.clone();
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(i32::from(EXIT_INTERRUPTED));
            }
            eprintln!(
                "\nrigfit: interrupted; stopping after this iteration (once more ends at once)"
            );
        });
    }
    let progress = |line: &str| out.note(line);
    let watch = job::backend::TrialWatch {
        progress: &progress,
        cancel: Some(&interrupt),
    };
    let opened = job::backend::open_job_evaluator_watched(
        &c,
        backend,
        precision,
        None,
        a.threads,
        job::backend::AutoPick::Measure,
        watch,
    )
    .map_err(|e| anyhow::Error::new(e).context("opening the evaluator"))?;
    let mut evaluator = opened.evaluator;
    evaluator.set_cancel(interrupt.clone());
    let info = evaluator.info();
    out.note(&format!(
        "profiles of {} parameters of {} on {} ({}), {} points each, span {}",
        genes.len(),
        rigfit::base::text::echo_bare(&c.name),
        info.backend,
        info.device,
        settings.points,
        settings.span
    ));
    let require_gpu = backend == Backend::Gpu;
    let mut cost =
        CampaignCost::new(&c, evaluator, require_gpu, a.threads).with_interrupt(interrupt.clone());
    // The covariance at the fitted point: a polish of no iterations.
    let at = PolishSettings {
        max_iterations: 0,
        ..PolishSettings::default()
    };
    let polish = job::polish_with(at, &genes, info.precision);
    let fit = polish.run(&mut cost, std::slice::from_ref(&best))?;
    let Some(uncertainty) = fit.uncertainty else {
        return Err(anyhow::anyhow!(
            "the fitted point of `{}` blows up on this evaluator: nothing to profile",
            result_path.display()
        ));
    };
    // A `rigfit profile` stopped by Ctrl-C goes on from here when run again.
    let checkpoint = a.dir.join(job::PROFILE_CHECKPOINT_FILE);
    let units = c.genes.iter().map(|g| g.unit.clone()).collect();
    let quiet = out.quiet || out.json;
    let profiles = Profiles::from_polish(settings, &polish)
        .units(units)
        .elite_ranges(&elite)
        .interrupt(interrupt.clone())
        .checkpoint_to(&checkpoint, true)
        .run_observed(&mut cost, &best, &uncertainty, &mut |i| {
            if !quiet {
                eprintln!("rigfit: {i}");
            }
            Ok(())
        });
    let profiles = match profiles {
        Err(rigfit::search::SearchError::Eval(rigfit::eval::EvalError::Cancelled)) => {
            out.note("interrupted: nothing was written");
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        other => other?,
    };
    if profiles.stop == PolishStop::Interrupted {
        out.note(&format!(
            "interrupted: result.json is unchanged; run the same command again to go on from {}",
            checkpoint.display()
        ));
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    let mut json = reopened.json.clone();
    job::attach_profiles(&mut json, &profiles);
    for key in ["profiles", "warnings", "verdict"] {
        job::update_result(&a.dir, key, json[key].clone())?;
    }
    let _ = std::fs::remove_file(&checkpoint);
    let report = a.dir.join(rigfit::report::html::REPORT_FILE);
    let rebuilt = match rigfit::report::html::write_report(&a.dir) {
        Ok(p) => Some(p),
        Err(e) => {
            out.note(&format!("warning: {} not rebuilt: {e}", report.display()));
            None
        }
    };
    out.json(&profiles)?;
    out.say(|| {
        let mut text = String::new();
        for p in &profiles.parameters {
            let show = |v: Option<f64>| v.map_or("open".to_string(), |v| format!("{v:.4e}"));
            let [lo, hi] = p.interval.unwrap_or([None, None]);
            let cov = p
                .covariance_interval
                .map_or("none".into(), |[a, b]| format!("[{a:.4e}, {b:.4e}]"));
            text.push_str(&format!(
                "  {:<16} {:.6e} {}: profile [{}, {}], covariance {cov}{}\n",
                p.name,
                p.value,
                p.unit,
                show(lo),
                show(hi),
                p.flag
                    .map_or(String::new(), |f| format!("  ({})", f.as_str()))
            ));
        }
        for w in profiles.warnings() {
            text.push_str(&format!("warning: {w}\n"));
        }
        text.push_str(&format!(
            "{} evaluations, {} iterations, {:.1} s; written into {}{}",
            profiles.evaluations,
            profiles.iterations,
            profiles.wall_time_s,
            result_path.display(),
            rebuilt.map_or(String::new(), |p| format!(" and {}", p.display()))
        ));
        text
    });
    Ok(ExitCode::SUCCESS)
}

/// A parameter's elite range in result.json's `parameters`, by name.
fn elite_range(result: &serde_json::Value, name: &str) -> Option<[f64; 2]> {
    let row = result["parameters"]
        .as_array()?
        .iter()
        .find(|p| p["name"].as_str() == Some(name))?;
    let r = row["elite_range"].as_array()?;
    Some([r.first()?.as_f64()?, r.get(1)?.as_f64()?])
}
