//! A calibration job: campaign + evaluator + search + outputs.
//!
//! The job never writes into the output folder before the campaign, the data and
//! the evaluator are ready, writes every file atomically, keeps a checkpoint
//! while it runs and removes it only once the results are complete.

pub mod backend;
mod cost;
mod folder;
pub mod islands;
pub mod memory;
mod outputs;
mod reopen;
mod resume_key;
mod save;
pub mod sensitivity;
mod verdict;

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

pub use cost::CampaignCost;
pub use folder::{FolderMode, LOCK_FILE, MANIFEST_FILE, OutputFolder, output_files};
pub use outputs::{
    ExperimentFit, JobSummary, ParamSummary, PolishSummary, write_outputs, write_outputs_watched,
};
pub use outputs::{
    FLAG_PREFIX, VALIDATION_FACTOR, ValidationFit, ValidationSummary, WARNING_PREFIX,
    simulate_validation, summarise_validation, validation_csv_name,
};
pub use reopen::{
    RESULT_FILE, Reopened, fitted_campaign, reopen, update_result, update_result_keys,
};
pub use resume_key::{STOPPING_LIMITS, fingerprint};
pub use save::save_files;
pub use verdict::{
    PROFILE_FLAG_PREFIX, Verdict, attach_profiles, replace_flags, replace_profile_warnings,
};

use crate::campaign::Campaign;
use crate::eval::Evaluator;
use crate::eval::Precision;
use crate::search::{
    Executor, GeneSpec, HistoryCsvObserver, Observer, ObserverMode, Polish, PolishSettings,
    ProgressObserver, SearchError, TerminationReason,
};

/// Name of the checkpoint file inside the output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";

/// Name of the profiles' checkpoint inside the output folder (while the
/// profile likelihoods run, after the polish).
pub const PROFILE_CHECKPOINT_FILE: &str = "profiles.checkpoint.json";

/// How to run a job.
#[derive(Debug, Clone)]
pub struct JobOptions {
    /// Output folder.
    pub out: PathBuf,
    /// Continue from the checkpoint in `out`.
    pub resume: bool,
    /// Hide the progress bar.
    pub quiet: bool,
    /// Set by the binary on Ctrl-C / SIGTERM.
    pub interrupt: Arc<AtomicBool>,
    /// Stop (with the last checkpoint) instead of falling back to the CPU when
    /// the GPU fails mid-run.
    pub require_gpu: bool,
    /// CPU threads for a fallback CPU evaluator (0: all cores).
    pub threads: usize,
}

impl JobOptions {
    /// A fresh job into `out` with no progress bar, no interrupt, a CPU
    /// fallback on all cores (what tests and library callers mostly want).
    pub fn quiet(out: impl Into<PathBuf>) -> Self {
        Self {
            out: out.into(),
            resume: false,
            quiet: true,
            interrupt: Arc::new(AtomicBool::new(false)),
            require_gpu: false,
            threads: 0,
        }
    }
}

/// Errors of a job.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The output folder holds an earlier job's files.
    #[error(
        "output folder `{}` already holds {found}; pass --overwrite to replace it or --resume to continue a checkpoint",
        path.display()
    )]
    OutputInUse {
        /// The folder.
        path: PathBuf,
        /// What is there.
        found: String,
    },
    /// `--resume` without a checkpoint.
    #[error(
        "nothing to resume: `{}` does not exist (a job stopped before its first checkpoint \
         leaves none; run it again without --resume to start it from the beginning)",
        path.display()
    )]
    NoCheckpoint {
        /// The expected checkpoint.
        path: PathBuf,
    },
    /// The output folder cannot be one: a file, under a file, unnamable.
    #[error("output folder `{}`: {reason}", path.display())]
    OutputPath {
        /// The folder.
        path: PathBuf,
        /// Why not.
        reason: String,
    },
    /// A file the job would write exists and is not rigfit's to replace.
    #[error(
        "`{}` {what}; rigfit never replaces a file it did not write, not even with \
         --overwrite: move it away or choose another output folder",
        path.display()
    )]
    ForeignFile {
        /// The file.
        path: PathBuf,
        /// Why it is not rigfit's.
        what: String,
    },
    /// Another job holds the output folder.
    #[error(
        "output folder `{}` is in use by another rigfit job ({holder}); wait for it or choose \
         another output folder",
        path.display()
    )]
    OutputLocked {
        /// The folder.
        path: PathBuf,
        /// What the lock file says about its holder.
        holder: String,
    },
    /// The search failed, or refused its settings or checkpoint.
    #[error("{}", search_headline(.0))]
    Search(#[from] SearchError),
    /// Writing results failed.
    #[error("writing `{}`", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// An evaluator failed outside the search.
    #[error("evaluating the best candidate")]
    Eval(#[from] crate::eval::EvalError),
    /// Drawing a plot failed.
    #[error(transparent)]
    Plot(#[from] crate::report::plots::PlotError),
    /// The interrupt flag was raised while the outputs were written; the
    /// checkpoint is kept.
    #[error("interrupted while writing the outputs; {}", written_before(.written))]
    OutputsInterrupted {
        /// The files written before it, in order.
        written: Vec<String>,
    },
    /// A finished job's `result.json` cannot be read back ([`reopen`]).
    #[error("`{}`: {json_path}: {reason}", path.display())]
    ResultFile {
        /// The file.
        path: PathBuf,
        /// JSON path of what is missing or wrong (`params.k1`), or `(file)`.
        json_path: String,
        /// What is wrong.
        reason: String,
    },
    /// The campaign a finished job is read back with is refused.
    #[error(transparent)]
    Campaign(#[from] crate::campaign::CampaignError),
    /// Islands that cannot be gathered or run as asked.
    #[error("islands in `{}`: {reason}", path.display())]
    Islands {
        /// The output folder.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// The files an interrupted output writing had written, as its message says.
fn written_before(written: &[String]) -> String {
    if written.is_empty() {
        "no file was written".to_string()
    } else {
        format!("written before the interrupt: {}", written.join(", "))
    }
}

/// The headline of a search's error: a checkpoint that cannot be resumed is
/// not a failed search.
fn search_headline(e: &SearchError) -> &'static str {
    match e {
        SearchError::FingerprintMismatch { .. } => {
            "cannot resume: the campaign changed since the checkpoint was written"
        }
        SearchError::CheckpointFormat { .. } => "cannot resume from the checkpoint",
        _ => "search failed",
    }
}

impl JobError {
    /// Whether the job's input is at fault rather than the job: an output
    /// folder or checkpoint it was pointed at, or a search that refused its
    /// settings or checkpoint ([`SearchError::blames_input`]).
    pub fn blames_input(&self) -> bool {
        match self {
            Self::OutputInUse { .. }
            | Self::NoCheckpoint { .. }
            | Self::OutputPath { .. }
            | Self::ForeignFile { .. }
            | Self::OutputLocked { .. }
            | Self::ResultFile { .. }
            | Self::Islands { .. }
            | Self::Campaign(_) => true,
            Self::Search(e) => e.blames_input(),
            _ => false,
        }
    }
}

/// The genes as the search sees them.
pub fn gene_specs(campaign: &Campaign) -> Vec<GeneSpec> {
    campaign
        .genes
        .iter()
        .map(|g| {
            let s = GeneSpec::new(g.name.clone(), g.lower, g.upper, g.scale);
            match g.init {
                Some(v) => s.with_init(v),
                None => s,
            }
        })
        .collect()
}

/// RK4 steps one candidate takes over all experiments, the steps from
/// `t = 0` to a record's first sample included (for throughput figures and
/// rates): [`Campaign::run_length`]'s count, which `check` estimates from.
pub fn steps_per_candidate(campaign: &Campaign) -> f64 {
    campaign.run_length().steps_per_candidate
}

/// Runs the search and writes every output. The binary opens the output folder
/// with [`OutputFolder::open`] first and holds it until this returns.
pub fn run(
    campaign: &Campaign,
    evaluator: Box<dyn Evaluator>,
    opts: &JobOptions,
) -> Result<JobSummary, JobError> {
    run_chosen(campaign, evaluator, opts, None)
}

/// [`run`] on an evaluator that `auto` chose by measurement
/// ([`backend::race`]): `result.json` says what was measured.
pub fn run_chosen(
    campaign: &Campaign,
    evaluator: Box<dyn Evaluator>,
    opts: &JobOptions,
    backend_trial: Option<backend::BackendTrial>,
) -> Result<JobSummary, JobError> {
    run_observed(campaign, evaluator, opts, backend_trial, Vec::new())
}

/// [`run_chosen`] with more observers of the search, called every generation
/// and polish iteration (the Python package's progress and Ctrl-C).
pub fn run_observed(
    campaign: &Campaign,
    evaluator: Box<dyn Evaluator>,
    opts: &JobOptions,
    backend_trial: Option<backend::BackendTrial>,
    observers: Vec<Box<dyn Observer>>,
) -> Result<JobSummary, JobError> {
    let info = evaluator.info();
    let precision = format!("{:?}", info.precision).to_lowercase();
    let fp = fingerprint(campaign, &info.backend, &precision);
    std::fs::create_dir_all(&opts.out).map_err(|source| JobError::Write {
        path: opts.out.clone(),
        source,
    })?;
    let genes = gene_specs(campaign);
    let solver = campaign
        .search
        .method
        .solver(&campaign.search, genes.clone())?;
    let mut cost = CampaignCost::new(campaign, evaluator, opts.require_gpu, opts.threads)
        .with_interrupt(opts.interrupt.clone());
    let polish = campaign
        .search
        .polish
        .enabled
        .then(|| polish(campaign, &genes, cost.precision()));
    let checkpoint = opts.out.join(CHECKPOINT_FILE);
    let progress = ProgressObserver::new(campaign.search.generations, opts.quiet)
        .with_steps_per_candidate(steps_per_candidate(campaign));
    let mut exec = Executor::boxed(solver, &mut cost)
        .fingerprint(fp)
        .checkpoint_to(&checkpoint)
        .interrupt(opts.interrupt.clone())
        .observe(progress, ObserverMode::Always)
        .observe(
            HistoryCsvObserver::new(opts.out.join("history.csv"), &genes),
            ObserverMode::Every(10),
        );
    for o in observers {
        exec = exec.observe(o, ObserverMode::Always);
    }
    if !opts.quiet {
        exec = exec.observe(InterimNotice, ObserverMode::Never);
    }
    if let Some(polish) = polish {
        exec = exec.then_polish(polish, campaign.search.polish.starts);
    }
    if opts.resume {
        exec = exec.resume_from(&checkpoint)?;
    }
    let outcome = exec.run()?;
    conclude(campaign, cost, outcome, &genes, opts, backend_trial, true)
}

/// After the search and its polish: the profiles, the outputs, and the
/// checkpoints removed once the results are complete; the CPU's rate kept
/// for `check` when `remember_rate` (a job whose search ran here).
fn conclude(
    campaign: &Campaign,
    mut cost: CampaignCost<'_>,
    outcome: crate::search::SearchOutcome,
    genes: &[GeneSpec],
    opts: &JobOptions,
    backend_trial: Option<backend::BackendTrial>,
    remember_rate: bool,
) -> Result<JobSummary, JobError> {
    let checkpoint = opts.out.join(CHECKPOINT_FILE);
    if let Some(p) = &outcome.polish {
        log::info!(
            "polish: {} starts, {} iterations, {} evaluations in {:.1} s ({:?}): 1 − R² {:.4e} → {:.4e}",
            p.starts.len(),
            p.iterations,
            p.evaluations,
            p.wall_time_s,
            p.stop,
            outcome.best_cost,
            p.best_cost
        );
    }
    let profiles = profile_stage(campaign, genes, &mut cost, &outcome, opts)?;
    let fallback = cost.fallback_note();
    let mut evaluator = cost.into_evaluator();
    // An interrupted search's interim outputs are written with the flag
    // lowered, so that a second interrupt stops them in turn; it is raised
    // again after them. A complete search's outputs stop at the first.
    let interrupted = outcome.termination == TerminationReason::Interrupted;
    if interrupted {
        opts.interrupt.store(false, Ordering::SeqCst);
    }
    let written = write_outputs_watched(
        campaign,
        evaluator.as_mut(),
        &outcome,
        genes,
        &opts.out,
        fallback,
        backend_trial,
        profiles,
        &opts.interrupt,
    );
    if interrupted {
        opts.interrupt.store(true, Ordering::SeqCst);
    }
    let summary = written?;
    if outcome.termination != TerminationReason::Interrupted {
        // The results are complete: the checkpoints have served their purpose.
        let _ = std::fs::remove_file(&checkpoint);
        let _ = std::fs::remove_file(opts.out.join(PROFILE_CHECKPOINT_FILE));
        if remember_rate {
            observe_cpu_rate(campaign, &summary, opts);
        }
    }
    Ok(summary)
}

/// The profile likelihoods the campaign asks for (`"search": {"profiles":
/// …}`), after a polish that gave intervals, through the search's own cost,
/// at the point the outputs report; progress on stderr unless quiet. An
/// interrupt stops them as one within the polish's residuals does
/// ([`crate::eval::EvalError::Cancelled`]): their checkpoint is kept, and a
/// resumed job polishes again and goes on from it.
fn profile_stage(
    campaign: &Campaign,
    genes: &[GeneSpec],
    cost: &mut CampaignCost<'_>,
    outcome: &crate::search::SearchOutcome,
    opts: &JobOptions,
) -> Result<Option<crate::search::ProfileOutcome>, JobError> {
    let Some(settings) = campaign.search.profiles else {
        return Ok(None);
    };
    let polished = outcome
        .polish
        .as_ref()
        .filter(|p| p.best_cost.is_finite() && p.best_cost <= outcome.best_cost * (1.0 + 1e-9));
    let (Some(p), Some(u)) = (
        outcome.polish.as_ref(),
        outcome.polish.as_ref().and_then(|p| p.uncertainty.as_ref()),
    ) else {
        return Ok(None);
    };
    if outcome.termination == TerminationReason::Interrupted {
        return Ok(None);
    }
    let best = polished.map_or(&outcome.best_genome, |_| &p.best_genome);
    let elite: Vec<Option<[f64; 2]>> = genes
        .iter()
        .map(|g| {
            let s = outcome.elite_spread.iter().find(|s| s.name == g.name);
            s.map(|s| [s.min, s.max])
        })
        .collect();
    let units = campaign.genes.iter().map(|g| g.unit.clone()).collect();
    let step = polish(campaign, genes, cost.precision());
    let profiles = crate::search::Profiles::from_polish(settings, &step)
        .units(units)
        .elite_ranges(&elite)
        .interrupt(opts.interrupt.clone())
        .checkpoint_to(opts.out.join(PROFILE_CHECKPOINT_FILE), opts.resume);
    let quiet = opts.quiet;
    let out = profiles.run_observed(&mut *cost, best, u, &mut |i| {
        if !quiet {
            eprintln!("rigfit: {i}");
        }
        Ok(())
    })?;
    if out.stop == crate::search::PolishStop::Interrupted {
        return Err(SearchError::Eval(crate::eval::EvalError::Cancelled).into());
    }
    log::info!(
        "profiles: {} iterations, {} evaluations in {:.1} s ({})",
        out.iterations,
        out.evaluations,
        out.wall_time_s,
        out.stop
    );
    Ok(Some(out))
}

/// Says, once an interrupted search has stopped, that its interim results
/// are written next and that a second interrupt stops them (on a record of
/// millions of samples they take seconds).
struct InterimNotice;

impl Observer for InterimNotice {
    fn observe(&mut self, _: &crate::search::GenerationReport) -> Result<(), SearchError> {
        Ok(())
    }

    fn finish(&mut self, outcome: &crate::search::SearchOutcome) -> Result<(), SearchError> {
        if outcome.termination == TerminationReason::Interrupted {
            use std::io::Write as _;
            let _ = writeln!(
                std::io::stderr(),
                "rigfit: the search stopped; writing its interim results (Ctrl-C again stops \
                 them; the checkpoint is kept either way)"
            );
        }
        Ok(())
    }
}

/// Keeps the rate a whole search ran at on every CPU core, for `check`'s
/// next estimate of the same job ([`backend::remember_observed`]), from a
/// search that was not interrupted; nothing for a search on the GPU, on
/// fewer threads or resumed.
fn observe_cpu_rate(campaign: &Campaign, summary: &JobSummary, opts: &JobOptions) {
    let cores = crate::eval::all_cores();
    let whole = !opts.resume && summary.wall_time_s > 0.0 && summary.evaluations > 0;
    if summary.backend != "cpu" || !(opts.threads == 0 || opts.threads == cores) || !whole {
        return;
    }
    let observed = backend::ObservedRate {
        cpu_rate: summary.evaluations as f64 * steps_per_candidate(campaign) / summary.wall_time_s,
        evaluations: summary.evaluations,
        seconds: summary.wall_time_s,
    };
    if let Err(e) = backend::remember_observed(campaign, &summary.precision, observed) {
        log::info!("the search's CPU rate could not be kept for `check`: {e}");
    }
}

/// The local polish the executor runs after the GA, from the GA's final
/// state: a resumed job whose GA had finished polishes again from the same
/// state, so a polish cut short by a kill or an interrupt ends, once resumed,
/// with the same bits. Its finite-difference step suits the evaluator's
/// arithmetic.
fn polish(campaign: &Campaign, genes: &[GeneSpec], precision: Precision) -> Polish {
    polish_with(campaign.search.polish, genes, precision)
}

/// A polish of `genes` with `settings` whose finite-difference step suits
/// an evaluator of `precision` (`cbrt(ε)` of its arithmetic): the job's, and
/// `rigfit profile`'s covariance at a finished job's fitted point.
pub fn polish_with(settings: PolishSettings, genes: &[GeneSpec], precision: Precision) -> Polish {
    let eps = match precision {
        Precision::F32 => f64::from(f32::EPSILON),
        Precision::F64 => f64::EPSILON,
    };
    Polish::new(settings, genes.to_vec()).relative_step(eps.cbrt())
}
