//! `auto` chooses the faster path by measurement.
//!
//! Which path scores a rig fastest depends on the rig, its records and the
//! machine: a 2-core machine's lavapipe runs the tensile rig's population
//! faster than the CPU lanes and the EMPS drive's long record at half their
//! rate. So `auto` scores one trial batch (the job's population, or fewer
//! where that would take more than [`TRIAL_STEPS`] candidate-steps, spread
//! over the search box by a fixed seed) on each
//! path it can open, after one warm-up batch that builds the kernels the job
//! would build anyway, and keeps the faster. The choice and the measured rates
//! go into the job's first line and `result.json` (`backend_trial`), and into
//! a cache ([`cache_file`]) keyed by the processor, the adapters, the
//! campaign's digest (its file and records), the precision and the
//! population, so the next run of the same job on the same machine skips the
//! trial and repeats the choice (and a resumed job keeps its path).
//!
//! The trial is made cheap by overlapping its parts: a job long enough to
//! build the CPU lanes' native code starts that build on a thread of its
//! own ([`CpuEvaluator::start_early_builds`]) before the GPU opens, so the C
//! compiler and the GPU's device and pipelines are made ready at once, and
//! every path is ready before any is timed (on a 2-core machine, 0.1 to
//! 0.3 s for the whole trial where it took 0.2 to 0.5 s one part after the
//! other; about 0.9 s on a long record, the EMPS closed loop). Only the
//! search's build is waited for: the polish's starts once the CPU is chosen
//! (on the aa2024 campaign the trial took 0.72 to 0.77 s where it took 1.0
//! to 1.3 s waiting for both). On a long record the GPU's kernel variants
//! are timed over its first quarter ([`trial_part`]), and the GPU scores the
//! batch whole only once it is chosen. A close call
//! ([`CLOSE_CALL`]) is timed once more on each path. Its batch is the search's
//! first generation, which the path kept then answers from memory
//! ([`Remembered`]). The same early build serves a job that runs on the CPU
//! from the start: its lanes interpret while the compiler works.
//!
//! The trial is bounded to a share of the job ([`TRIAL_SHARE`] of its
//! estimated candidate-steps, [`trial_plan`]): a trial over whole runs that
//! would cost more, or any run longer than [`TRIAL_LONG_RECORD_STEPS`], is
//! timed over each run's first steps on both paths (the CPU on the runs cut
//! short); one that cannot afford even [`TRIAL_PREFIX_MIN_STEPS`] is skipped,
//! the CPU taken. Each stage is said as it starts ([`TrialWatch`]), and an
//! interrupt stops the trial between stages or within a batch.
//!
//! A job too short for a trial to pay back ([`SHORT_JOB_SECONDS`] on its
//! faster path, as `check` estimates it at the assumed rates) runs on the
//! CPU unmeasured: opening lavapipe alone takes 0.1 to 0.3 s on a 2-core
//! machine, about what it could save on such a job, and the CPU starts at
//! once. It takes a choice measured for it before (by `rigfit check`, which
//! races the paths whatever the job's length, [`AutoPick::Race`]) where the
//! cache holds one; it lists the adapters for the cache's key only where the
//! cache holds a choice for its processor, campaign, precision and
//! population. `RIGFIT_AUTO_TRIAL=always` measures
//! those too, and so does `RIGFIT_REQUIRE_GPU=1`, which makes a missing
//! adapter an error (so the GPU is opened, whatever the job's length).
//!
//! [`open_job_evaluator`] is that flow whole (the refusals before any work,
//! the cached choice, the race, the cache), as the CLI's `rigfit run` and the
//! Python package's `rigfit.fit` both open their evaluator.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::campaign::Campaign;
use crate::eval::{
    Backend, CpuEvaluator, EvalError, Evaluator, PrecisionChoice, Remembered, Scores,
};
use crate::gpu::GpuError;
use crate::search::GeneticAlgorithm;
use crate::search::genes::genome_values;

mod cache;
mod plan;

pub use plan::{
    CHECK_RACE_STEPS, TRIAL_LONG_RECORD_STEPS, TRIAL_PART, TRIAL_PART_FROM_STEPS,
    TRIAL_PREFIX_MIN_STEPS, TRIAL_PREFIX_STEPS, TRIAL_SHARE, TRIAL_STEPS_FLOOR, TrialPlan,
    check_trial_budget, job_trial_budget, trial_part, trial_plan,
};
use plan::{longest_record_steps, prefix_campaign};

use cache::auto_key_if;
pub use cache::{
    KeptChoice, ObservedRate, TrialKey, adapters_key, auto_key, cache_file, cached, kept_choices,
    observed_cpu_rate, observed_key, processor, remember, remember_observed,
};

/// Most candidate-steps a trial batch takes on each path: below it the
/// trial scores the job's whole population (a GPU's rate depends on the
/// batch's size: lavapipe's two threads run the tensile rig's 2048
/// candidates faster than the CPU lanes and 256 of them slower), above it
/// fewer candidates, in whole workgroups of 64.
pub const TRIAL_STEPS: f64 = 3e7;

/// Estimated wall time (s) on the faster path below which `auto` runs a job
/// on the CPU without a trial ([`crate::job::memory::TimeEstimate`], at the
/// assumed rates: every core at the CPU's, the GPU at
/// [`crate::job::memory::GPU_STEPS_PER_S_ASSUMED`]). Measured on the shipped
/// campaigns (2026-11-26, 2 cores, lavapipe): every one estimated below it
/// ran as fast on the CPU as on lavapipe or faster, within 6 %, once each
/// path's start-up is counted; the trial took 0.3 to 0.7 s of their 0.4 to
/// 4 s.
pub const SHORT_JOB_SECONDS: f64 = 4.0;

/// Two paths' trial rates closer than this ratio are a close call, timed
/// once more each: on the shipped tensile example (2 048 candidates) the
/// CPU lanes' rate on a 2-core machine read 1.06e8 to 1.25e8 from one run
/// to the next, and lavapipe's 1.02e8 to 1.09e8, so that one batch each
/// chose lavapipe about one time in three, for a job 15 to 18 % slower.
pub const CLOSE_CALL: f64 = 1.15;

/// Fewest candidates a trial batch scores (the population, where smaller).
pub const TRIAL_MIN_CANDIDATES: usize = 128;

/// Largest population whose first generation a trial draws whole to take
/// its batch from it (a million genomes of a few genes: tens of megabytes).
const TRIAL_DRAWS_GENERATION_UP_TO: usize = 1 << 20;

/// Candidates of a warm-up batch: enough for the GPU evaluator to build the
/// specialised kernel the job's generations use, and for the CPU's first
/// call into its native code and its first buffers of a batch's size (a
/// timed batch without it made the CPU look a third slower than it is).
const WARM_UP_CANDIDATES: usize = 64;

/// What `auto` measured and chose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BackendTrial {
    /// `"gpu"` or `"cpu"`: the path chosen.
    pub chosen: String,
    /// The GPU path's rate (candidate-steps per second), with its fastest
    /// kernel variant.
    pub gpu_rate: f64,
    /// The GPU kernel variant chosen ([`crate::eval::KERNEL_VARIANTS`]), the
    /// fastest on this adapter; `None` where the GPU has no variants.
    #[serde(default)]
    pub gpu_kernel: Option<String>,
    /// Each GPU kernel variant's rate (candidate-steps per second).
    #[serde(default)]
    pub gpu_kernel_rates: BTreeMap<String, f64>,
    /// The CPU path's rate (candidate-steps per second).
    pub cpu_rate: f64,
    /// Candidates in the timed batch.
    pub candidates: usize,
    /// The campaign measured: its name and file, as `rigfit devices` lists
    /// the choices kept on this machine; `None` in a cache written before
    /// it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub campaign: Option<String>,
    /// Steps of each run the GPU was timed over, where a long record was
    /// timed over its first part ([`trial_part`]); `None` for whole passes.
    #[serde(default)]
    pub gpu_steps_timed: Option<usize>,
    /// Steps of each run both paths were timed over where the trial was
    /// shortened ([`TrialPlan`]: a very long record, or whole runs that
    /// would have cost more than [`TRIAL_SHARE`] of the job); `None` where
    /// the CPU was timed over whole runs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps_timed: Option<usize>,
    /// Why the trial was shortened or skipped, where it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shortened: Option<String>,
    /// Whether the trial was skipped (`shortened` says why): the CPU was
    /// taken unmeasured and the rates are 0. Never cached.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub skipped: bool,
    /// Wall time the trial took (s), warm-up batches included; 0 when the
    /// choice came from the cache.
    pub trial_s: f64,
    /// Whether the choice came from the cache ([`cache_file`]).
    pub cached: bool,
    /// Wall time from asking for the GPU to its first kernel variant built
    /// and warmed up (s): what a job on the GPU spends before its first
    /// generation beyond the CPU's start-up (`check` estimates from it);
    /// `None` in a cache written before it was measured.
    #[serde(default)]
    pub gpu_startup_s: Option<f64>,
}

impl BackendTrial {
    /// One line for the job's start: the choice and the rates behind it.
    pub fn line(&self) -> String {
        if self.skipped {
            return format!(
                "backend auto chose the CPU without a trial: {}",
                self.shortened.as_deref().unwrap_or("no trial")
            );
        }
        let how = if self.cached {
            "as measured before on this machine".to_string()
        } else {
            format!("measured in {:.2} s", self.trial_s)
        };
        let kernels = match &self.gpu_kernel {
            Some(k) if self.gpu_kernel_rates.len() > 1 => {
                let others: Vec<String> = self
                    .gpu_kernel_rates
                    .iter()
                    .filter(|(v, _)| *v != k)
                    .map(|(v, r)| format!("{v} {r:.2e}"))
                    .collect();
                format!(" with {k} kernels ({})", others.join(", "))
            }
            _ => String::new(),
        };
        let part = match (self.steps_timed, self.gpu_steps_timed) {
            (Some(_), _) => String::new(),
            (None, Some(steps)) => format!(" over each run's first {steps} steps"),
            (None, None) => String::new(),
        };
        let both = match (self.steps_timed, &self.shortened) {
            (Some(steps), Some(why)) => {
                format!(", both over each run's first {steps} steps ({why})")
            }
            (Some(steps), None) => format!(", both over each run's first {steps} steps"),
            (None, _) => String::new(),
        };
        format!(
            "backend auto chose the {}: GPU {:.2e}{kernels}{part}, CPU {:.2e} candidate-steps/s{both} ({how})",
            self.chosen.to_uppercase(),
            self.gpu_rate,
            self.cpu_rate
        )
    }
}

/// Errors of a trial.
#[derive(Debug, thiserror::Error)]
pub enum TrialError {
    /// A path failed to score the trial batch.
    #[error("the {path} trial batch failed: {source}")]
    Eval {
        /// `"gpu"` or `"cpu"`.
        path: &'static str,
        /// What failed.
        source: EvalError,
    },
    /// The interrupt flag ([`TrialWatch::cancel`]) was raised during the
    /// trial: nothing was chosen, cached or written.
    #[error("interrupted during auto's backend trial")]
    Cancelled,
}

impl TrialError {
    /// Whether the trial stopped because it was interrupted.
    pub fn is_cancelled(&self) -> bool {
        matches!(
            self,
            Self::Cancelled
                | Self::Eval {
                    source: EvalError::Cancelled,
                    ..
                }
        )
    }
}

/// What watches `auto`'s trial: a line for each of its stages (what it
/// builds or times, and how far it is), and a flag that, once raised
/// (Ctrl-C), stops it between two stages or, where the evaluator can stop
/// a batch partway, within one ([`Evaluator::set_cancel`]).
#[derive(Clone, Copy)]
pub struct TrialWatch<'a> {
    /// Called with one line per stage.
    pub progress: &'a dyn Fn(&str),
    /// Raised to stop the trial.
    pub cancel: Option<&'a Arc<AtomicBool>>,
}

impl TrialWatch<'_> {
    /// Nothing said, never cancelled.
    pub const SILENT: TrialWatch<'static> = TrialWatch {
        progress: &|_| {},
        cancel: None,
    };

    fn say(&self, line: &str) {
        (self.progress)(line);
    }

    fn check(&self) -> Result<(), TrialError> {
        match self.cancel {
            Some(flag) if flag.load(Ordering::SeqCst) => Err(TrialError::Cancelled),
            _ => Ok(()),
        }
    }

    fn arm(&self, evaluator: &mut dyn Evaluator) {
        if let Some(flag) = self.cancel {
            evaluator.set_cancel(flag.clone());
        }
    }
}

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
}

impl std::fmt::Display for OpenNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::CpuF32 { reason } => {
                write!(f, "precision f32 on the CPU: {reason}; scoring in f64")
            }
            Self::Fallback { note, .. } => write!(f, "{note}"),
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
                    Some(Box::new(e) as Box<dyn Evaluator>)
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
    Ok(JobEvaluator {
        evaluator,
        notes,
        trial,
    })
}

/// Whether the job's search alone, at its full length, runs the CPU lanes
/// long enough to build their native code
/// ([`crate::compile::back::native::NATIVE_AFTER`]).
fn worth_building_early(campaign: &Campaign) -> bool {
    let s = &campaign.search;
    (s.population * s.generations) as f64 * super::steps_per_candidate(campaign)
        >= crate::compile::back::native::NATIVE_AFTER as f64
}

/// The job's estimated wall time on its faster path (s), at the assumed
/// rates `check` starts from.
fn short_job_estimate(campaign: &Campaign) -> f64 {
    let cores = crate::eval::all_cores();
    let e = crate::job::memory::TimeEstimate::of(
        campaign,
        super::steps_per_candidate(campaign),
        cores,
        crate::job::memory::GPU_STEPS_PER_S_ASSUMED,
    );
    e.cpu_seconds.min(e.gpu_seconds)
}

/// The trial batch: the first `n` candidates of the search's first
/// generation (as the job's executor draws it, from the campaign's seed), so
/// that the path kept has already scored that generation where `n` is the
/// whole population ([`Remembered`]).
fn trial_genomes(campaign: &Campaign, n: usize) -> Vec<Vec<f64>> {
    let genes = super::gene_specs(campaign);
    let mut rng = ChaCha8Rng::seed_from_u64(campaign.search.seed);
    // A first generation too large to draw for a few of its candidates
    // (its Latin hypercube is drawn whole) is not drawn: the trial's batch
    // is then a spread of its own, which the generation does not repeat.
    let ga = (campaign.search.population <= TRIAL_DRAWS_GENERATION_UP_TO)
        .then(|| GeneticAlgorithm::new(campaign.search.clone(), genes.clone()).ok())
        .flatten();
    match ga {
        Some(ga) => ga
            .init(&mut rng)
            .iter()
            .take(n)
            .map(|g| genome_values(&genes, g))
            .collect(),
        // Settings the search would refuse, or a generation too large:
        // any spread over the box times the paths as well.
        None => (0..n)
            .map(|_| genes.iter().map(|g| g.at_fraction(rng.random())).collect())
            .collect(),
    }
}

/// Makes `evaluator` ready to be timed on `genomes`: what it would make
/// ready once it pays ([`Evaluator::prepare`]: the CPU lanes' native builds),
/// then [`Evaluator::warm_up`] on the first [`WARM_UP_CANDIDATES`] genomes
/// (the GPU's pipelines for the kernel variant in use, run for one chunk;
/// the CPU scores them: its first call into its native code and its first
/// buffers).
fn make_ready(
    campaign: &Campaign,
    evaluator: &mut dyn Evaluator,
    genomes: &[Vec<f64>],
    path: &'static str,
) -> Result<(), TrialError> {
    evaluator.prepare();
    let warm = &genomes[..genomes.len().min(WARM_UP_CANDIDATES)];
    evaluator
        .warm_up(&campaign.batch(warm))
        .map_err(|source| TrialError::Eval { path, source })
}

/// Candidate-steps per second of `evaluator` on `batch`, made ready, with
/// the scores.
fn rate(
    campaign: &Campaign,
    evaluator: &mut dyn Evaluator,
    batch: &crate::eval::Batch,
    path: &'static str,
) -> Result<(f64, Scores), TrialError> {
    let start = Instant::now();
    let scores = evaluator
        .fitness(batch)
        .map_err(|source| TrialError::Eval { path, source })?;
    let s = start.elapsed().as_secs_f64().max(1e-9);
    let candidate_steps = batch.candidates as f64 * super::steps_per_candidate(campaign);
    Ok((candidate_steps / s, scores))
}

/// What a timed GPU batch gave besides its rate.
enum GpuTimed {
    /// A whole pass: the batch's scores.
    Whole(Scores),
    /// The pass's first part: the most steps a run advanced.
    Part(usize),
}

/// The GPU's rate on `batch` (made ready): over its first `part` steps
/// where given and the evaluator can stop a pass partway, else over a
/// whole pass, with its scores.
fn time_gpu(
    campaign: &Campaign,
    gpu: &mut dyn Evaluator,
    batch: &crate::eval::Batch,
    part: Option<usize>,
) -> Result<(f64, GpuTimed), TrialError> {
    let path = "gpu";
    if let Some(steps) = part {
        let start = Instant::now();
        let advanced = gpu
            .fitness_part(batch, steps)
            .map_err(|source| TrialError::Eval { path, source })?;
        if let Some(advanced) = advanced {
            let s = start.elapsed().as_secs_f64().max(1e-9);
            let per_candidate: f64 = campaign
                .run_length()
                .experiments
                .iter()
                .map(|x| x.steps.min(advanced as f64))
                .sum();
            let rate = batch.candidates as f64 * per_candidate / s;
            return Ok((rate, GpuTimed::Part(advanced)));
        }
    }
    rate(campaign, gpu, batch, path).map(|(r, scores)| (r, GpuTimed::Whole(scores)))
}

/// Scores the trial batch on both paths and returns the faster evaluator
/// with what was measured; `population` is the job's.
///
/// Every path is made ready before any is timed: the GPU's kernels build
/// while the CPU's native code may still be building
/// ([`CpuEvaluator::start_early_builds`]), and nothing builds while a batch
/// is timed (the CPU needs no warm-up batch once its builds are done). The
/// batch is the search's first generation, or its first candidates: the
/// evaluator returned remembers what it scored ([`Remembered`]), so where the
/// trial scored the whole generation the job does not score it again. On a
/// long record ([`trial_part`]) the GPU's kernel variants are timed over
/// the record's first part, and the GPU scores the batch whole only once it
/// is chosen. Where `plan` shortens the trial, both paths are timed over
/// each run's first steps (the CPU on `cpu_prefix`, an evaluator of the
/// runs cut short) and neither scores the batch whole: the job scores its
/// first generation itself. `gpu` comes with the instant it was asked for,
/// from which its start-up is timed.
pub fn race(
    campaign: &Campaign,
    plan: &TrialPlan,
    gpu: (Box<dyn Evaluator>, Instant),
    cpu: Box<dyn Evaluator>,
    cpu_prefix: Option<Box<dyn Evaluator>>,
    watch: TrialWatch<'_>,
) -> Result<(Box<dyn Evaluator>, BackendTrial), TrialError> {
    let part = plan.prefix.or_else(|| trial_part(campaign));
    race_over(campaign, plan, gpu, cpu, cpu_prefix, part, watch)
}

/// [`race`], the GPU timed over the first `part` steps of each run where
/// given (a shortened trial's prefix, else a long record's part).
#[expect(
    clippy::too_many_lines,
    reason = "one race, its stages in the order they run"
)]
fn race_over(
    campaign: &Campaign,
    plan: &TrialPlan,
    (mut gpu, asked): (Box<dyn Evaluator>, Instant),
    mut cpu: Box<dyn Evaluator>,
    cpu_prefix: Option<Box<dyn Evaluator>>,
    part: Option<usize>,
    watch: TrialWatch<'_>,
) -> Result<(Box<dyn Evaluator>, BackendTrial), TrialError> {
    let start = Instant::now();
    let n = plan.candidates;
    let genomes = trial_genomes(campaign, n);
    watch.arm(gpu.as_mut());
    watch.arm(cpu.as_mut());
    let over = match part {
        Some(p) => format!(
            "over each run's first {p} of {:.0} steps",
            longest_record_steps(campaign)
        ),
        None => format!(
            "over whole runs ({:.3e} steps each candidate)",
            super::steps_per_candidate(campaign)
        ),
    };
    let variants = gpu.kernel_variants();
    let stages = variants.len().max(1) + 1;
    let mut stage = 0;
    let mut next = |what: &str| {
        stage += 1;
        watch.say(&format!(
            "auto's trial {stage}/{stages}: {what}, {n} candidates {over} ({:.1} s so far)",
            start.elapsed().as_secs_f64()
        ));
    };
    watch.say(&format!(
        "auto's trial: making both paths ready (the GPU's kernels, the CPU lanes' code) to time \
         {n} candidates {over} on each"
    ));
    let mut gpu_startup_s = None;
    for &variant in variants {
        watch.check()?;
        gpu.use_kernel_variant(variant);
        make_ready(campaign, gpu.as_mut(), &genomes, "gpu")?;
        gpu_startup_s.get_or_insert(asked.elapsed().as_secs_f64());
    }
    if variants.is_empty() {
        make_ready(campaign, gpu.as_mut(), &genomes, "gpu")?;
        gpu_startup_s = Some(asked.elapsed().as_secs_f64());
    }
    watch.check()?;
    // Shortened, the CPU is timed on the runs cut short; the job's own
    // evaluator only makes its native code ready.
    let (prefix_campaign_, mut timed_cpu) = match (plan.prefix, cpu_prefix) {
        (Some(p), Some(mut e)) => {
            watch.arm(e.as_mut());
            cpu.prepare();
            (Some(prefix_campaign(campaign, p)), Some(e))
        }
        _ => (None, None),
    };
    let cpu_campaign = prefix_campaign_.as_ref().unwrap_or(campaign);
    let cpu_timed: &mut dyn Evaluator = match timed_cpu.as_mut() {
        Some(e) => e.as_mut(),
        None => cpu.as_mut(),
    };
    make_ready(cpu_campaign, cpu_timed, &genomes, "cpu")?;
    watch.check()?;
    let batch = campaign.batch(&genomes);
    // Each kernel variant of the GPU, the fastest kept.
    let mut gpu_kernel_rates = BTreeMap::new();
    let mut best: Option<(&str, f64, GpuTimed)> = None;
    for &variant in variants {
        next(&format!("timing the GPU's {variant} kernels"));
        gpu.use_kernel_variant(variant);
        let (r, timed) = time_gpu(campaign, gpu.as_mut(), &batch, part)?;
        watch.check()?;
        gpu_kernel_rates.insert(variant.to_string(), r);
        if best.as_ref().is_none_or(|(_, b, _)| r > *b) {
            best = Some((variant, r, timed));
        }
    }
    let (gpu_kernel, (mut gpu_rate, gpu_timed)) = match best {
        Some((variant, r, timed)) => {
            gpu.use_kernel_variant(variant);
            (Some(variant), (r, timed))
        }
        None => {
            next("timing the GPU");
            (None, time_gpu(campaign, gpu.as_mut(), &batch, part)?)
        }
    };
    watch.check()?;
    next("timing the CPU");
    let (mut cpu_rate, cpu_scores) = rate(cpu_campaign, cpu_timed, &batch, "cpu")?;
    watch.check()?;
    // A close call is timed once more on each path (the CPU first, its
    // threads undisturbed by the GPU's), the faster of each path's two kept.
    if gpu_rate.max(cpu_rate) < CLOSE_CALL * gpu_rate.min(cpu_rate) {
        watch.say(&format!(
            "auto's trial: a close call (GPU {gpu_rate:.2e}, CPU {cpu_rate:.2e} \
             candidate-steps/s): timing each once more"
        ));
        cpu_rate = cpu_rate.max(rate(cpu_campaign, cpu_timed, &batch, "cpu")?.0);
        watch.check()?;
        let again = time_gpu(campaign, gpu.as_mut(), &batch, part)?.0;
        if let Some(variant) = gpu_kernel {
            let r = gpu_kernel_rates
                .get_mut(variant)
                .expect("the kept variant's rate");
            *r = r.max(again);
        }
        gpu_rate = gpu_rate.max(again);
        watch.check()?;
    }
    let gpu_wins = gpu_rate >= cpu_rate;
    let gpu_steps_timed = match gpu_timed {
        GpuTimed::Part(steps) => Some(steps),
        GpuTimed::Whole(_) => None,
    };
    let shortened = plan.prefix.is_some() && timed_cpu.is_some();
    let chosen: Box<dyn Evaluator> = match (gpu_wins, gpu_timed, shortened) {
        // Timed over the runs' first steps: the job scores its first
        // generation itself.
        (true, _, true) => gpu,
        (false, _, true) => cpu,
        (true, GpuTimed::Whole(scores), false) => Box::new(Remembered::new(gpu, batch, scores)),
        // Timed over a part, the GPU scores the batch whole now: the
        // generation the job would score next.
        (true, GpuTimed::Part(_), false) => {
            watch.say(&format!(
                "auto's trial: the GPU is faster; scoring the search's first {n} candidates on it"
            ));
            let scores = gpu.fitness(&batch).map_err(|source| TrialError::Eval {
                path: "gpu",
                source,
            })?;
            Box::new(Remembered::new(gpu, batch, scores))
        }
        (false, _, false) => Box::new(Remembered::new(cpu, batch, cpu_scores)),
    };
    let trial = BackendTrial {
        chosen: if gpu_wins { "gpu" } else { "cpu" }.into(),
        gpu_rate,
        gpu_kernel: gpu_kernel.map(str::to_string),
        gpu_kernel_rates,
        cpu_rate,
        candidates: n,
        campaign: Some(format!("{} ({})", campaign.name, campaign.path.display())),
        gpu_steps_timed,
        steps_timed: plan.prefix.filter(|_| shortened),
        shortened: plan.why.clone().filter(|_| shortened),
        skipped: false,
        trial_s: start.elapsed().as_secs_f64(),
        cached: false,
        gpu_startup_s,
    };
    Ok((chosen, trial))
}

/// Most candidate-steps `check` times the CPU lanes on where nothing was
/// measured before ([`cpu_trial`]): about 0.1 to 0.4 s on a 2-core machine,
/// the native build included.
pub const CHECK_TRIAL_STEPS: f64 = 1e7;

/// What `check` measured of the CPU lanes on this job's rig and records
/// ([`cpu_trial`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CpuTrial {
    /// The rate (candidate-steps per second, every core).
    pub rate: f64,
    /// Candidates in the timed batch.
    pub candidates: usize,
    /// Steps of each run timed, where the runs were too long to time whole
    /// within [`CHECK_TRIAL_STEPS`]; `None`: whole runs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps_timed: Option<usize>,
    /// `"f64"` or `"f32"`: the arithmetic timed.
    pub precision: &'static str,
    /// Wall time the measurement took (s), the native build and the
    /// warm-up included.
    pub trial_s: f64,
}

/// Why [`cpu_trial`] measured nothing.
#[derive(Debug, thiserror::Error)]
pub enum CpuTrialError {
    /// Even the smallest batch would take too long to time before a job.
    #[error(
        "{candidates} candidates of {steps:.3e} steps each are more than `check` times \
         ({limit:.0e} candidate-steps)"
    )]
    TooLong {
        /// The smallest batch.
        candidates: usize,
        /// RK4 steps per candidate.
        steps: f64,
        /// [`CHECK_TRIAL_STEPS`], four times over.
        limit: f64,
    },
    /// The evaluator could not be opened or failed.
    #[error(transparent)]
    Eval(#[from] EvalError),
}

/// The CPU lanes' rate on `campaign`'s rig and records, measured as `auto`'s
/// trial measures it (the search's first candidates, made ready first: the
/// native build, a warm-up batch) on every core, in f32 where `f32` asks
/// and the rig allows it: what `check` estimates the job from when no run
/// has measured it. Its batch is the population or fewer, at most
/// [`CHECK_TRIAL_STEPS`] candidate-steps but at least
/// [`TRIAL_MIN_CANDIDATES`] (a group of lanes for each of two threads);
/// where whole runs would take more, over each run's first steps (as many
/// as [`CHECK_TRIAL_STEPS`] allows, [`TRIAL_PREFIX_MIN_STEPS`] to
/// [`TRIAL_PREFIX_STEPS`]); where even that would take more than four times
/// [`CHECK_TRIAL_STEPS`], nothing is timed.
pub fn cpu_trial(campaign: &Campaign, f32: bool) -> Result<CpuTrial, CpuTrialError> {
    let start = Instant::now();
    let steps = super::steps_per_candidate(campaign);
    let n = trial_candidates(campaign.search.population, steps, CHECK_TRIAL_STEPS);
    // Longer than the budget, the CPU is timed over each run's first steps.
    let runs = campaign.problem.experiments.len().max(1) as f64;
    let prefix = (n as f64 * steps > CHECK_TRIAL_STEPS).then(|| {
        let fit = (CHECK_TRIAL_STEPS / (n as f64 * runs)) as usize;
        fit.clamp(TRIAL_PREFIX_MIN_STEPS, TRIAL_PREFIX_STEPS)
    });
    let timed = prefix.map(|p| prefix_campaign(campaign, p));
    let timed = timed.as_ref().unwrap_or(campaign);
    let timed_steps = super::steps_per_candidate(timed);
    if n as f64 * timed_steps > 4.0 * CHECK_TRIAL_STEPS {
        return Err(CpuTrialError::TooLong {
            candidates: n,
            steps: timed_steps,
            limit: 4.0 * CHECK_TRIAL_STEPS,
        });
    }
    let mut cpu = CpuEvaluator::try_new(timed.problem.clone(), crate::eval::all_cores())?;
    let precision = if f32 && cpu.use_f32().is_ok() {
        "f32"
    } else {
        "f64"
    };
    let genomes = trial_genomes(campaign, n);
    let path = "cpu";
    let source = |e: TrialError| match e {
        TrialError::Eval { source, .. } => source,
        TrialError::Cancelled => EvalError::Cancelled,
    };
    make_ready(timed, &mut cpu, &genomes, path).map_err(source)?;
    let batch = campaign.batch(&genomes);
    let (rate, _) = rate(timed, &mut cpu, &batch, path).map_err(source)?;
    Ok(CpuTrial {
        rate,
        candidates: n,
        steps_timed: prefix,
        precision,
        trial_s: start.elapsed().as_secs_f64(),
    })
}

/// Candidates in a timed trial batch: the population where it takes at
/// most `budget` candidate-steps ([`TRIAL_STEPS`] for `auto`'s race), else
/// as many whole workgroups as fit, at least [`TRIAL_MIN_CANDIDATES`].
fn trial_candidates(population: usize, steps_per_candidate: f64, budget: f64) -> usize {
    let fit = (budget / steps_per_candidate.max(1.0)) as usize / 64 * 64;
    population.min(fit.max(TRIAL_MIN_CANDIDATES)).max(1)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::AtomicUsize;

    use super::plan::TRIAL_PASSES;
    use super::*;
    use crate::eval::{Batch, EvaluatorInfo, History, Precision, Problem};

    /// Takes `per_candidate` seconds per candidate of a whole pass, and
    /// where `parts`, the share of that a pass's first steps take; scores
    /// every run `score`. Counts the whole passes and the parts it runs.
    struct Paced {
        problem: Problem,
        per_candidate: f64,
        parts: bool,
        score: f64,
        whole: Arc<AtomicUsize>,
        parted: Arc<AtomicUsize>,
    }

    impl Paced {
        fn new(problem: &Problem, per_candidate: f64, parts: bool, score: f64) -> Self {
            Self {
                problem: problem.clone(),
                per_candidate,
                parts,
                score,
                whole: Arc::default(),
                parted: Arc::default(),
            }
        }

        fn sleep(&self, batch: &Batch, share: f64) {
            let s = self.per_candidate * batch.candidates as f64 * share;
            std::thread::sleep(std::time::Duration::from_secs_f64(s));
        }
    }

    impl Evaluator for Paced {
        fn info(&self) -> EvaluatorInfo {
            EvaluatorInfo {
                backend: if self.parts { "gpu" } else { "cpu" }.into(),
                device: "test".into(),
                precision: Precision::F64,
            }
        }
        fn problem(&self) -> &Problem {
            &self.problem
        }
        fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
            self.whole.fetch_add(1, Ordering::Relaxed);
            self.sleep(batch, 1.0);
            let ne = self.problem.experiments.len();
            Ok(Scores {
                experiments: ne,
                values: vec![self.score; batch.candidates * ne],
                diverged: 0,
            })
        }
        fn fitness_part(
            &mut self,
            batch: &Batch,
            steps: usize,
        ) -> Result<Option<usize>, EvalError> {
            if !self.parts {
                return Ok(None);
            }
            self.parted.fetch_add(1, Ordering::Relaxed);
            let samples = (self.problem.experiments.iter())
                .map(|x| x.window.end)
                .max()
                .unwrap_or(1);
            let longest = samples * self.problem.substeps;
            self.sleep(batch, (steps as f64 / longest as f64).min(1.0));
            Ok(Some(steps))
        }
        fn warm_up(&mut self, _batch: &Batch) -> Result<(), EvalError> {
            Ok(())
        }
        fn kernel_variants(&self) -> &'static [&'static str] {
            if self.parts {
                crate::eval::KERNEL_VARIANTS
            } else {
                &[]
            }
        }
        fn checked_histories(
            &mut self,
            _batch: &Batch,
            _which: &[usize],
        ) -> Result<Vec<Vec<History>>, EvalError> {
            Ok(vec![])
        }
    }

    #[test]
    fn a_long_record_times_the_gpu_over_its_first_part_and_scores_whole_what_it_keeps() {
        let path = std::path::Path::new("campaigns/friction_sdof_synthetic.json");
        let mut campaign = Campaign::load(path).expect("a shipped campaign");
        campaign.search.population = 64;
        let problem = campaign.problem.clone();
        let part = longest_record_steps(&campaign) as usize / 4;
        let batch = campaign.batch(&trial_genomes(&campaign, 64));
        for gpu_faster in [true, false] {
            // Four times faster or slower than the CPU: no close call.
            let (g, c) = if gpu_faster {
                (5e-4, 2e-3)
            } else {
                (2e-3, 5e-4)
            };
            let gpu = Paced::new(&problem, g, true, 0.25);
            let cpu = Paced::new(&problem, c, false, 0.75);
            let (g_whole, g_parted, c_whole) =
                (gpu.whole.clone(), gpu.parted.clone(), cpu.whole.clone());
            let asked = Instant::now();
            let (mut chosen, t) = race_over(
                &campaign,
                &whole(64),
                (Box::new(gpu), asked),
                Box::new(cpu),
                None,
                Some(part),
                TrialWatch::SILENT,
            )
            .unwrap();
            assert_eq!(t.chosen, if gpu_faster { "gpu" } else { "cpu" }, "{t:?}");
            assert_eq!(t.gpu_steps_timed, Some(part), "{t:?}");
            assert!(
                t.line().contains(&format!("first {part} steps")),
                "{}",
                t.line()
            );
            // Each kernel variant timed over the part, never whole, but
            // where the GPU is kept: then it scored the batch whole once.
            assert_eq!(g_parted.load(Ordering::Relaxed), 2);
            assert_eq!(g_whole.load(Ordering::Relaxed), usize::from(gpu_faster));
            assert_eq!(c_whole.load(Ordering::Relaxed), 1);
            // The kept path's own scores of the batch, from memory.
            let scores = chosen.fitness(&batch).unwrap();
            let own = if gpu_faster { 0.25 } else { 0.75 };
            assert!(scores.values.iter().all(|&v| v == own), "{scores:?}");
            assert_eq!(g_whole.load(Ordering::Relaxed), usize::from(gpu_faster));
            assert_eq!(c_whole.load(Ordering::Relaxed), 1);
        }
        // A record timed whole: each variant scores the batch whole, and
        // the one kept answers from memory.
        let gpu = Paced::new(&problem, 5e-4, true, 0.25);
        let cpu = Paced::new(&problem, 2e-3, false, 0.75);
        let (g_whole, g_parted) = (gpu.whole.clone(), gpu.parted.clone());
        let (mut chosen, t) = race_over(
            &campaign,
            &whole(64),
            (Box::new(gpu), Instant::now()),
            Box::new(cpu),
            None,
            None,
            TrialWatch::SILENT,
        )
        .unwrap();
        assert_eq!((t.chosen.as_str(), t.gpu_steps_timed), ("gpu", None));
        assert_eq!(g_parted.load(Ordering::Relaxed), 0);
        assert_eq!(g_whole.load(Ordering::Relaxed), 2);
        chosen.fitness(&batch).unwrap();
        assert_eq!(g_whole.load(Ordering::Relaxed), 2);
    }

    /// A trial over whole runs of `n` candidates.
    fn whole(n: usize) -> TrialPlan {
        TrialPlan {
            candidates: n,
            prefix: None,
            why: None,
            skip: false,
            budget: f64::INFINITY,
        }
    }

    #[test]
    fn a_shortened_trial_times_both_paths_over_a_prefix_and_scores_nothing_whole() {
        let path = std::path::Path::new("campaigns/friction_sdof_synthetic.json");
        let mut campaign = Campaign::load(path).expect("a shipped campaign");
        campaign.search.population = 64;
        let problem = campaign.problem.clone();
        let prefix = 1000;
        let cut = prefix_campaign(&campaign, prefix);
        let steps = crate::job::steps_per_candidate(&cut);
        assert!(
            (steps - prefix as f64).abs() <= 1.0,
            "{steps} steps for a prefix of {prefix}"
        );
        assert!(crate::job::steps_per_candidate(&campaign) > 4.0 * prefix as f64);
        for gpu_faster in [true, false] {
            let (g, c) = if gpu_faster {
                (5e-4, 2e-3)
            } else {
                (2e-3, 5e-4)
            };
            let gpu = Paced::new(&problem, g, true, 0.25);
            let cpu = Paced::new(&problem, c, false, 0.75);
            // The cut runs take their share of a whole run's time.
            let share = steps / crate::job::steps_per_candidate(&campaign);
            let timed = Paced::new(&cut.problem, c * share, false, 0.5);
            let (g_whole, c_whole, t_whole) =
                (gpu.whole.clone(), cpu.whole.clone(), timed.whole.clone());
            let plan = TrialPlan {
                prefix: Some(prefix),
                why: Some("a test".into()),
                ..whole(64)
            };
            let lines = std::cell::RefCell::new(Vec::<String>::new());
            let say = |l: &str| lines.borrow_mut().push(l.to_string());
            let watch = TrialWatch {
                progress: &say,
                cancel: None,
            };
            let (_, t) = race(
                &campaign,
                &plan,
                (Box::new(gpu), Instant::now()),
                Box::new(cpu),
                Some(Box::new(timed)),
                watch,
            )
            .unwrap();
            assert_eq!(t.chosen, if gpu_faster { "gpu" } else { "cpu" }, "{t:?}");
            assert_eq!(t.steps_timed, Some(prefix), "{t:?}");
            assert!(
                t.line()
                    .contains("both over each run's first 1000 steps (a test)")
            );
            // Neither path scored a whole run; the CPU was timed on the cut
            // runs.
            assert_eq!(g_whole.load(Ordering::Relaxed), 0);
            assert_eq!(c_whole.load(Ordering::Relaxed), 0);
            assert_eq!(t_whole.load(Ordering::Relaxed), 1);
            // Each stage said, with how far.
            let lines = lines.borrow();
            assert!(
                lines.iter().any(|l| l.contains("timing the CPU")),
                "{lines:?}"
            );
            assert!(
                lines.iter().any(|l| l.contains("first 1000 of")),
                "{lines:?}"
            );
        }
    }

    #[test]
    fn an_interrupt_stops_the_trial() {
        let path = std::path::Path::new("campaigns/friction_sdof_synthetic.json");
        let mut campaign = Campaign::load(path).expect("a shipped campaign");
        campaign.search.population = 64;
        let problem = campaign.problem.clone();
        let flag = Arc::new(AtomicBool::new(true));
        let watch = TrialWatch {
            progress: &|_| {},
            cancel: Some(&flag),
        };
        let gpu = Paced::new(&problem, 1e-4, true, 0.25);
        let cpu = Paced::new(&problem, 1e-4, false, 0.75);
        let (g_whole, c_whole) = (gpu.whole.clone(), cpu.whole.clone());
        let e = race(
            &campaign,
            &whole(64),
            (Box::new(gpu), Instant::now()),
            Box::new(cpu),
            None,
            watch,
        )
        .err()
        .expect("an interrupted trial");
        assert!(e.is_cancelled(), "{e}");
        assert_eq!(g_whole.load(Ordering::Relaxed), 0);
        assert_eq!(c_whole.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn a_long_record_or_a_costly_trial_is_shortened_and_an_unaffordable_one_skipped() {
        let path = std::path::Path::new("campaigns/friction_sdof_synthetic.json");
        let mut campaign = Campaign::load(path).expect("a shipped campaign");
        campaign.search.population = 64;
        // The shipped record (5 000 steps) within a generous budget: whole.
        let plan = trial_plan(&campaign, 64, 1e12);
        assert_eq!((plan.prefix, plan.skip), (None, false), "{plan:?}");
        // A budget whole runs exceed: each run's first steps.
        let steps = crate::job::steps_per_candidate(&campaign);
        let budget = TRIAL_PASSES * 64.0 * steps / 2.0;
        let plan = trial_plan(&campaign, 64, budget);
        let p = plan.prefix.expect("a shortened trial");
        assert!(
            p < steps as usize && p >= TRIAL_PREFIX_MIN_STEPS,
            "{plan:?}"
        );
        assert!(plan.why.is_some_and(|w| w.contains("% of the job")));
        // A budget that cannot afford the fewest steps: skipped.
        let plan = trial_plan(&campaign, 64, 1e3);
        assert!(plan.skip && plan.prefix.is_none(), "{plan:?}");
        // A record far longer than TRIAL_LONG_RECORD_STEPS: a prefix,
        // whatever the budget.
        let x = &mut campaign.problem.experiments[0];
        let n = 300_000;
        x.force = (0..n).map(|k| x.force[k % x.force.len()]).collect();
        x.window = 0..n;
        let plan = trial_plan(&campaign, 64, 1e15);
        assert_eq!(plan.prefix, Some(TRIAL_PREFIX_STEPS), "{plan:?}");
        assert!(plan.why.is_some_and(|w| w.contains("longest run")));
    }

    #[test]
    fn the_trial_scores_the_population_unless_it_is_long() {
        assert_eq!(trial_candidates(2048, 2500.0, TRIAL_STEPS), 2048);
        assert_eq!(trial_candidates(128, 49_680.0, TRIAL_STEPS), 128);
        assert_eq!(trial_candidates(4096, 49_680.0, TRIAL_STEPS), 576);
        assert_eq!(
            trial_candidates(4096, 1e9, TRIAL_STEPS),
            TRIAL_MIN_CANDIDATES
        );
        assert_eq!(trial_candidates(40, 1e9, TRIAL_STEPS), 40);
    }
}
