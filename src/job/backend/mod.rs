//! `--backend auto`: which path scores a job faster, by measurement.
//!
//! Which evaluator scores a rig faster, the CPU lanes or the GPU, depends on
//! the rig, its records and the machine, so `auto` measures rather than
//! guesses. [`open_job_evaluator`] is the whole flow, as `rigfit run` and the
//! Python package's `rigfit.fit` both open their evaluator:
//!
//! 1. **Refusals before any work** ([`OpenError`]): CPU threads the system
//!    will not start, an adapter selector (`--adapter`, `RIGFIT_ADAPTER`)
//!    that names no adapter, a rig the GPU kernels cannot hold when the GPU
//!    was asked for. A named adapter means that GPU, unmeasured.
//! 2. **A short job runs on the CPU unmeasured**: one estimated under
//!    [`SHORT_JOB_SECONDS`] on its faster path, as `check` estimates it, for
//!    which a GPU's start-up and a trial would cost about what they could
//!    save. It still takes a choice measured for it before (by `rigfit
//!    check`, which races the paths whatever the job's length,
//!    [`AutoPick::Race`]) where the cache holds one.
//! 3. **A cached choice is repeated**: the cache ([`cache_file`]) is keyed
//!    by the processor, the adapters, the campaign's digest (its file and
//!    records), the precision and the population ([`TrialKey`]), so the next
//!    run of the same job on the same machine skips the trial and a resumed
//!    job keeps its path. A CPU choice opens no GPU.
//! 4. **Otherwise the two paths race** ([`race`]) on one trial batch: the
//!    search's first generation, or its first candidates where the whole
//!    generation would take more than [`TRIAL_STEPS`] candidate-steps. The
//!    trial is bounded to a share of the job ([`TrialPlan`]): where whole
//!    runs would cost more than [`TRIAL_SHARE`] of it, or a run is longer
//!    than [`TRIAL_LONG_RECORD_STEPS`], both paths are timed over each run's
//!    first steps; where even [`TRIAL_PREFIX_MIN_STEPS`] would cost too
//!    much, the trial is skipped and the CPU taken. The choice and the rates
//!    go into the job's first line, `result.json` (`backend_trial`,
//!    [`BackendTrial`]) and the cache.
//!
//! The trial is made cheap by overlapping its parts: a job long enough to
//! build the CPU lanes' native code starts that build on a thread of its own
//! ([`crate::eval::CpuEvaluator::start_early_builds`]) before the GPU opens, so the C
//! compiler and the GPU's pipelines are made ready at once; the race waits
//! for the search's build only, and the polish's starts once the CPU is
//! chosen. The path kept has already scored the trial batch and answers it
//! from memory ([`crate::eval::Remembered`]). Each stage is said as it
//! starts, and an interrupt stops the trial between stages or within a batch
//! ([`TrialWatch`]). `RIGFIT_AUTO_TRIAL=always` measures short jobs too, and
//! so does `RIGFIT_REQUIRE_GPU=1`, which makes a missing adapter an error.
//! What the evaluators offer the trial (making ready, timing part of a pass,
//! kernel variants) is [`crate::eval::Timed`].
//!
//! The files, in the order a job meets them: `open.rs` (the flow above),
//! `plan.rs` (how much a trial may time, and over what), `racing.rs` (the
//! race), `trial.rs` (what it measured, its errors, what watches it),
//! `cache.rs` (the choices kept per machine) and `cpu_rate.rs` (`check`'s
//! measurement of the CPU lanes alone, [`cpu_trial`]).
//!
//! The measurements behind these choices are in
//! docs/engineering/performance.md, appendix.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::campaign::Campaign;
use crate::search::first_candidates;

mod cache;
mod cpu_rate;
mod open;
mod plan;
mod racing;
mod trial;

pub use cache::{
    KeptChoice, ObservedRate, TrialKey, adapters_key, auto_key, cache_file, cached, kept_choices,
    observed_cpu_rate, observed_key, processor, remember, remember_observed,
};
pub use cpu_rate::{CHECK_TRIAL_STEPS, CpuTrial, CpuTrialError, cpu_trial};
pub use open::{
    AutoPick, JobEvaluator, OpenError, OpenNote, open_job_evaluator, open_job_evaluator_watched,
    worth_building_early,
};
pub use plan::{
    CHECK_RACE_STEPS, TRIAL_LONG_RECORD_STEPS, TRIAL_PART, TRIAL_PART_FROM_STEPS,
    TRIAL_PREFIX_MIN_STEPS, TRIAL_PREFIX_STEPS, TRIAL_SHARE, TRIAL_STEPS_FLOOR, TrialPlan,
    check_trial_budget, job_trial_budget, trial_part, trial_plan,
};
pub use racing::{CLOSE_CALL, race};
pub use trial::{BackendTrial, TrialError, TrialWatch};

/// Most candidate-steps a trial batch takes on each path: below it the
/// trial scores the job's whole population (a GPU's rate depends on the
/// batch's size: lavapipe's two threads run the tensile rig's 2048
/// candidates faster than the CPU lanes and 256 of them slower), above it
/// fewer candidates, in whole workgroups of 64.
pub const TRIAL_STEPS: f64 = 3e7;

/// Estimated wall time (s) on the faster path below which `auto` runs a job
/// on the CPU without a trial ([`crate::job::memory::TimeEstimate`], at the
/// assumed rates: every core at the CPU's, the GPU at
/// [`crate::job::memory::GPU_STEPS_PER_S_ASSUMED`]): on the shipped
/// campaigns every job estimated below it ran as fast on the CPU as on a
/// software GPU or faster, once each path's start-up is counted.
pub const SHORT_JOB_SECONDS: f64 = 4.0;

/// Fewest candidates a trial batch scores (the population, where smaller).
pub const TRIAL_MIN_CANDIDATES: usize = 128;

/// Largest population whose first generation a trial draws whole to take
/// its batch from it (a million genomes of a few genes: tens of megabytes).
const TRIAL_DRAWS_GENERATION_UP_TO: usize = 1 << 20;

/// The trial batch: the first `n` candidates of the search's first
/// generation (as the job's executor draws it, from the campaign's seed), so
/// that the path kept has already scored that generation where `n` is the
/// whole population ([`crate::eval::Remembered`]).
fn trial_genomes(campaign: &Campaign, n: usize) -> Vec<Vec<f64>> {
    let genes = super::gene_specs(campaign);
    // A first generation too large to draw for a few of its candidates
    // (the GA's Latin hypercube is drawn whole) is not drawn: the trial's
    // batch is then a spread of its own, which the generation does not repeat.
    let drawn = (campaign.search.population <= TRIAL_DRAWS_GENERATION_UP_TO)
        .then(|| first_candidates(&campaign.search, &genes, n))
        .flatten();
    drawn.unwrap_or_else(|| {
        // Settings the search would refuse, or a generation too large:
        // any spread over the box times the paths as well.
        let mut rng = ChaCha8Rng::seed_from_u64(campaign.search.seed);
        (0..n)
            .map(|_| genes.iter().map(|g| g.at_fraction(rng.random())).collect())
            .collect()
    })
}
