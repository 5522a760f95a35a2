//! Opening a job's evaluator ([`open_job_evaluator`]): the refusals before
//! any work, a short job's CPU, the cached choice, the race, the cache.

use std::collections::BTreeMap;
use std::time::Instant;

use super::cache::{auto_key_if, cached, remember};
use super::plan::{
    TRIAL_PREFIX_MIN_STEPS, check_trial_budget, job_trial_budget, prefix_campaign, trial_plan,
};
use super::{BackendTrial, SHORT_JOB_SECONDS, TrialError, TrialWatch, race};
use crate::campaign::Campaign;
use crate::eval::{Backend, CpuEvaluator, EvalError, Evaluator, PrecisionChoice, Timed};
use crate::gpu::GpuError;

/// How `auto` picks between the two paths when both are there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AutoPick {
    /// A job's choice: the one cached for this job on this machine, else a
    /// race of the two paths ([`race`]), cached for the next run.
    Measure,
    /// A race of the two paths whatever the job's length (`check`'s
    /// measurement where none is cached), cached for the next run as
    /// [`Self::Measure`]'s.
    Race,
    /// The GPU when there is one, unmeasured (one ensemble, with no
    /// generations to repay a race).
    Gpu,
}

/// Why a job's evaluator is refused before any work.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The CPU evaluator's threads would not start.
    #[error("{threads} threads: {source}")]
    Threads {
        /// Threads asked for (0: all cores).
        threads: usize,
        /// What refused them.
        source: EvalError,
    },
    /// The adapter selector (`--adapter`, `RIGFIT_ADAPTER`) names no adapter.
    #[error("{selected_by}: {why}; the adapters are: {adapters}")]
    Adapter {
        /// Where the selector came from (`--adapter X`, `RIGFIT_ADAPTER=X`).
        selected_by: String,
        /// Why it names none.
        why: String,
        /// The adapters there are, as `rigfit devices` lists them.
        adapters: String,
    },
    /// The GPU was asked for and its kernels cannot hold the rig.
    #[error(transparent)]
    KernelLimits(GpuError),
    /// Opening the GPU evaluator failed.
    #[error("opening the GPU evaluator")]
    Gpu(#[source] GpuError),
    /// `auto`'s race failed.
    #[error(transparent)]
    Trial(#[from] TrialError),
}

/// What opening a job's evaluator has to tell the user, in the order it
/// happened.
#[derive(Debug, Clone, PartialEq)]
pub enum OpenNote {
    /// `f32` was asked for on the CPU and the rig has no native f32 lanes:
    /// it is scored in f64.
    CpuF32 {
        /// Why the lanes are missing.
        reason: String,
    },
    /// `auto` found no GPU to run on and runs on the CPU.
    Fallback {
        /// Why.
        note: String,
        /// Whether the rig has GPU kernels, so that a driver would help.
        driver_helps: bool,
    },
    /// The measured choice could not be cached: the next run measures again.
    NotCached {
        /// Why.
        error: String,
    },
    /// `auto` ran a short job on the CPU without a trial.
    ShortJob {
        /// The job's estimated wall time on its faster path (s).
        seconds: f64,
    },
    /// The job runs on a discrete GPU that its batches leave far from full
    /// ([`crate::gpu::underfilled`]).
    GpuUnderfilled {
        /// What to say.
        note: String,
    },
}

impl std::fmt::Display for OpenNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::CpuF32 { reason } => {
                write!(f, "precision f32 on the CPU: {reason}; scoring in f64")
            }
            Self::Fallback { note, .. } | Self::GpuUnderfilled { note } => write!(f, "{note}"),
            Self::NotCached { error } => write!(
                f,
                "the backend choice could not be cached ({error}); the next run measures again"
            ),
            Self::ShortJob { seconds } => write!(
                f,
                "backend auto chose the CPU without a trial: the job is estimated at {seconds:.1} s on \
                 its faster path, under {SHORT_JOB_SECONDS} s, too short for a GPU's start-up and a \
                 trial to pay back (--backend gpu runs it there)"
            ),
        }
    }
}

/// The evaluator a job runs on, with what opening it said and, where `auto`
/// chose by measurement, what was measured (`backend_trial` in `result.json`).
pub struct JobEvaluator {
    /// The evaluator.
    pub evaluator: Box<dyn Evaluator>,
    /// What to tell the user.
    pub notes: Vec<OpenNote>,
    /// What `auto` measured and chose (from the cache or a race).
    pub trial: Option<BackendTrial>,
}

/// Opens the evaluator a job on `campaign` runs on, refusing before any work
/// what cannot run: CPU `threads` the system will not start, an adapter
/// selector (`adapter`, else `RIGFIT_ADAPTER`) that names no adapter, a rig
/// the GPU kernels cannot hold when the GPU was asked for. `auto` with a
/// named adapter means that GPU, unmeasured; otherwise it picks as `pick`
/// says. A CPU choice from the cache opens no GPU.
pub fn open_job_evaluator(
    campaign: &Campaign,
    backend: Backend,
    precision: PrecisionChoice,
    adapter: Option<&str>,
    threads: usize,
    pick: AutoPick,
) -> Result<JobEvaluator, OpenError> {
    open_job_evaluator_watched(
        campaign,
        backend,
        precision,
        adapter,
        threads,
        pick,
        TrialWatch::SILENT,
    )
}

/// [`open_job_evaluator`], its trial watched: a line for each stage, and a
/// flag that stops it ([`TrialError::Cancelled`]).
pub fn open_job_evaluator_watched(
    campaign: &Campaign,
    backend: Backend,
    precision: PrecisionChoice,
    adapter: Option<&str>,
    threads: usize,
    pick: AutoPick,
    watch: TrialWatch<'_>,
) -> Result<JobEvaluator, OpenError> {
    let mut notes = Vec::new();
    let mut cpu = CpuEvaluator::try_new(campaign.problem.clone(), threads)
        .map_err(|source| OpenError::Threads { threads, source })?;
    // `auto` races the CPU against the GPU in the precision asked for.
    let f32_refused = (backend != Backend::Gpu && precision == PrecisionChoice::F32)
        .then(|| cpu.use_f32().err())
        .flatten()
        .map(|e| OpenNote::CpuF32 {
            reason: e.to_string(),
        });
    // A job long enough to build the CPU lanes' native code builds it on a
    // thread of its own from the start (`prepare_soon`), while the lanes
    // interpret and, where `auto` races, while the GPU opens.
    let build_early = worth_building_early(campaign);
    let on_cpu = |mut cpu: CpuEvaluator, mut notes: Vec<OpenNote>, trial| {
        notes.extend(f32_refused.clone());
        if build_early {
            cpu.prepare_soon();
        }
        JobEvaluator {
            evaluator: Box::new(cpu),
            notes,
            trial,
        }
    };
    if backend == Backend::Cpu {
        return Ok(on_cpu(cpu, notes, None));
    }
    let requested = crate::gpu::requested_adapter(adapter);
    if let Some((selector, selected_by)) = &requested {
        let adapters = crate::gpu::list_adapters();
        if let Err(why) = crate::gpu::choose_adapter(selector, &adapters) {
            return Err(OpenError::Adapter {
                selected_by: selected_by.clone(),
                why,
                adapters: crate::gpu::adapter_list(&adapters),
            });
        }
    }
    let kernels = crate::gpu::kernel_groups(&campaign.problem);
    let driver_helps = kernels.is_ok();
    if backend == Backend::Gpu
        && let Err(e) = kernels
    {
        return Err(OpenError::KernelLimits(e));
    }
    // A named adapter asks for that GPU: no race.
    let measure = backend == Backend::Auto
        && matches!(pick, AutoPick::Measure | AutoPick::Race)
        && requested.is_none();
    let always = std::env::var("RIGFIT_AUTO_TRIAL").is_ok_and(|v| v == "always")
        || crate::gpu::gpu_required();
    let precision_key = format!("{precision:?}").to_lowercase();
    // Before the cache's key, which lists the adapters (tens of
    // milliseconds, a tenth of the shortest jobs): a short job takes a
    // choice measured for it (by `check`), else runs on the CPU unmeasured.
    let short = (measure && !always && pick == AutoPick::Measure)
        .then(|| short_job_estimate(campaign))
        .filter(|&seconds| seconds < SHORT_JOB_SECONDS);
    let trial_key = measure
        .then(|| auto_key_if(campaign, &precision_key, short.is_none()))
        .flatten();
    let cached = trial_key.as_deref().and_then(cached);
    if let Some(seconds) = short
        && cached.is_none()
    {
        notes.push(OpenNote::ShortJob { seconds });
        return Ok(on_cpu(cpu, notes, None));
    }
    if let Some(t) = cached.clone().filter(|t| t.chosen == "cpu") {
        return Ok(on_cpu(cpu, notes, Some(t)));
    }
    // The trial's bound: a share of the job (or `check`'s second or two).
    let mut plan = match pick {
        AutoPick::Race => trial_plan(
            campaign,
            campaign.search.population,
            check_trial_budget(campaign),
        ),
        AutoPick::Measure | AutoPick::Gpu => trial_plan(
            campaign,
            campaign.search.population,
            job_trial_budget(campaign),
        ),
    };
    if plan.skip && always {
        // Measured whatever it costs: over the fewest steps a trial times.
        plan.skip = false;
        plan.prefix = Some(TRIAL_PREFIX_MIN_STEPS);
    }
    if trial_key.is_some() && cached.is_none() && plan.skip {
        let t = BackendTrial {
            chosen: "cpu".into(),
            gpu_rate: 0.0,
            gpu_kernel: None,
            gpu_kernel_rates: BTreeMap::new(),
            cpu_rate: 0.0,
            candidates: 0,
            campaign: Some(format!("{} ({})", campaign.name, campaign.path.display())),
            gpu_steps_timed: None,
            steps_timed: None,
            shortened: plan.why.clone(),
            skipped: true,
            trial_s: 0.0,
            cached: false,
            gpu_startup_s: None,
        };
        return Ok(on_cpu(cpu, notes, Some(t)));
    }
    if trial_key.is_some() && cached.is_none() {
        // The search's builds alone before the race: the CPU is timed as
        // soon as they are done; the polish's start once the CPU is chosen.
        cpu.start_early_builds(false);
    }
    let asked = Instant::now();
    let opened =
        crate::gpu::open_evaluator_on(campaign.problem.clone(), backend, precision, adapter)
            .map_err(OpenError::Gpu)?;
    if let Some(note) = opened.note {
        // No GPU for `auto`: the job's own CPU evaluator, on its threads and
        // in its precision.
        notes.push(OpenNote::Fallback { note, driver_helps });
        return Ok(on_cpu(cpu, notes, None));
    }
    let (evaluator, trial) = match (trial_key, cached) {
        (Some(_), Some(t)) => {
            let mut evaluator = opened.evaluator;
            if let Some(k) = &t.gpu_kernel {
                evaluator.use_kernel_variant(k);
            }
            (evaluator, Some(t))
        }
        (Some(key), None) => {
            let cpu_prefix = match plan.prefix {
                Some(p) => {
                    let mut e =
                        CpuEvaluator::try_new(prefix_campaign(campaign, p).problem, threads)
                            .map_err(|source| OpenError::Threads { threads, source })?;
                    if precision == PrecisionChoice::F32 {
                        // As the job's own evaluator: f32 where the rig has it.
                        let _ = e.use_f32();
                    }
                    Some(Box::new(e) as Box<dyn Timed>)
                }
                None => None,
            };
            let (mut chosen, t) = race(
                campaign,
                &plan,
                (opened.evaluator, asked),
                Box::new(cpu),
                cpu_prefix,
                watch,
            )?;
            if t.chosen == "cpu" {
                notes.extend(f32_refused);
                if build_early {
                    chosen.prepare_soon();
                }
            }
            if let Err(e) = remember(&key, &t) {
                notes.push(OpenNote::NotCached {
                    error: e.to_string(),
                });
            }
            (chosen, Some(t))
        }
        (None, _) => (opened.evaluator, None),
    };
    let info = evaluator.info();
    if opened.discrete_gpu && info.backend == "gpu" {
        let experiments = campaign.problem.experiments.len();
        if let Some(note) =
            crate::gpu::underfilled(campaign.search.population, experiments, &info.device)
        {
            notes.push(OpenNote::GpuUnderfilled { note });
        }
    }
    Ok(JobEvaluator {
        evaluator,
        notes,
        trial,
    })
}

/// Whether the job's search alone, at its full length, runs the CPU lanes
/// long enough to build their native code
/// ([`crate::compile::back::native::NATIVE_AFTER`]).
pub fn worth_building_early(campaign: &Campaign) -> bool {
    let s = &campaign.search;
    (s.population * s.generations) as f64 * crate::job::steps_per_candidate(campaign)
        >= crate::compile::back::native::NATIVE_AFTER as f64
}

/// The job's estimated wall time on its faster path (s), at the assumed
/// rates `check` starts from.
fn short_job_estimate(campaign: &Campaign) -> f64 {
    let cores = crate::eval::all_cores();
    let e = crate::job::memory::TimeEstimate::of(
        campaign,
        crate::job::steps_per_candidate(campaign),
        cores,
        crate::job::memory::GPU_STEPS_PER_S_ASSUMED,
    );
    e.cpu_seconds.min(e.gpu_seconds)
}
