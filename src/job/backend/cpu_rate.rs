//! `check`'s measurement of the CPU lanes alone ([`cpu_trial`]), where no
//! run has measured them on this machine: timed as `auto`'s trial times
//! them, made ready first, over a batch small enough for a second or so.

use std::time::Instant;

use serde::Serialize;

use super::plan::{TRIAL_PREFIX_MIN_STEPS, TRIAL_PREFIX_STEPS, prefix_campaign, trial_candidates};
use super::racing::{make_ready, rate};
use super::{TrialError, trial_genomes};
use crate::campaign::Campaign;
use crate::eval::{CpuEvaluator, EvalError};

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
/// [`TRIAL_MIN_CANDIDATES`](super::TRIAL_MIN_CANDIDATES) (a group of lanes for each of two threads);
/// where whole runs would take more, over each run's first steps (as many
/// as [`CHECK_TRIAL_STEPS`] allows, [`TRIAL_PREFIX_MIN_STEPS`] to
/// [`TRIAL_PREFIX_STEPS`]); where even that would take more than four times
/// [`CHECK_TRIAL_STEPS`], nothing is timed.
pub fn cpu_trial(campaign: &Campaign, f32: bool) -> Result<CpuTrial, CpuTrialError> {
    let start = Instant::now();
    let steps = crate::job::steps_per_candidate(campaign);
    let n = trial_candidates(campaign.search.population, steps, CHECK_TRIAL_STEPS);
    // Longer than the budget, the CPU is timed over each run's first steps.
    let runs = campaign.problem.experiments.len().max(1) as f64;
    let prefix = (n as f64 * steps > CHECK_TRIAL_STEPS).then(|| {
        let fit = (CHECK_TRIAL_STEPS / (n as f64 * runs)) as usize;
        fit.clamp(TRIAL_PREFIX_MIN_STEPS, TRIAL_PREFIX_STEPS)
    });
    let timed = prefix.map(|p| prefix_campaign(campaign, p));
    let timed = timed.as_ref().unwrap_or(campaign);
    let timed_steps = crate::job::steps_per_candidate(timed);
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
