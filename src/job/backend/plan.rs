//! How much of a job `auto`'s trial may time, and over what: whole runs, a
//! part of a long record on the GPU, each run's first steps, or nothing
//! ([`TrialPlan`]); the budgets of a job's trial and of `check`'s race.

use super::{CHECK_TRIAL_STEPS, TRIAL_MIN_CANDIDATES, TRIAL_STEPS};
use crate::campaign::Campaign;

/// Steps of a record from which `auto`'s trial times the GPU over a part of
/// it ([`trial_part`]); below it, over whole passes.
pub const TRIAL_PART_FROM_STEPS: f64 = 32_768.0;

/// Share of a long record the GPU's kernel variants are timed over.
pub const TRIAL_PART: f64 = 0.25;

/// The steps `auto`'s trial times the GPU over: a quarter
/// ([`TRIAL_PART`]) of the longest record where it has at least
/// [`TRIAL_PART_FROM_STEPS`] steps, else none (whole passes). A GPU pass's
/// rate is the same from its first chunks to its last (every run steps
/// through its record at once), and a path the trial does not keep scores
/// nothing the job uses: on the EMPS closed loop (two records of 49 680 steps, 128
/// candidates) lavapipe's two kernel variants took 0.17 to 0.24 s each of a
/// 1.0 to 1.25 s trial, on a job the CPU runs faster.
pub fn trial_part(campaign: &Campaign) -> Option<usize> {
    let longest = longest_record_steps(campaign);
    (longest >= TRIAL_PART_FROM_STEPS).then(|| (longest * TRIAL_PART).ceil() as usize)
}

/// Steps of the campaign's longest record, its prologue included.
pub(super) fn longest_record_steps(campaign: &Campaign) -> f64 {
    campaign
        .run_length()
        .experiments
        .iter()
        .map(|x| x.steps)
        .fold(0.0, f64::max)
}

/// Share of a job's estimated candidate-steps (its GA and the polish's
/// expected steps, [`crate::job::memory::TimeEstimate`]) `auto`'s trial may
/// spend, where that is more than [`TRIAL_STEPS_FLOOR`]: a trial over whole
/// runs that would cost more is timed over each run's first steps.
pub const TRIAL_SHARE: f64 = 0.05;

/// Candidate-steps a trial may always spend, however short the job (a job
/// estimated under [`super::SHORT_JOB_SECONDS`] takes no trial at all).
pub const TRIAL_STEPS_FLOOR: f64 = TRIAL_STEPS;

/// Passes over the trial batch a trial costs at most, on both paths
/// together: the CPU's warm-up and timed batch, the GPU's kernel variants,
/// and a close call timed once more on each.
pub(super) const TRIAL_PASSES: f64 = 5.0;

/// Steps of a run from which `auto`'s trial times both paths over each
/// run's first [`TRIAL_PREFIX_STEPS`] steps only, whatever the job's length:
/// a path's rate is the same from a run's first steps to its last, and a
/// record of millions of samples timed whole on each path took minutes.
pub const TRIAL_LONG_RECORD_STEPS: f64 = 131_072.0;

/// Most steps of each run a shortened trial times.
pub const TRIAL_PREFIX_STEPS: usize = 32_768;

/// Fewest steps of each run a shortened trial times: a trial that cannot
/// afford them is skipped, the CPU taken unmeasured.
pub const TRIAL_PREFIX_MIN_STEPS: usize = 2_048;

/// How `auto`'s trial measures a job ([`trial_plan`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TrialPlan {
    /// Candidates in the timed batch.
    pub candidates: usize,
    /// Steps of each run both paths are timed over, where the trial is
    /// shortened; `None`: whole runs (the GPU over [`trial_part`]).
    pub prefix: Option<usize>,
    /// Why the trial is shortened or skipped.
    pub why: Option<String>,
    /// Whether it is skipped (the CPU taken unmeasured).
    pub skip: bool,
    /// Candidate-steps the trial may spend.
    pub budget: f64,
}

/// The job's estimated candidate-steps: its GA and the polish's expected
/// steps.
pub(super) fn job_candidate_steps(campaign: &Campaign) -> f64 {
    let e = crate::job::memory::TimeEstimate::of(
        campaign,
        crate::job::steps_per_candidate(campaign),
        crate::eval::all_cores(),
        crate::job::memory::GPU_STEPS_PER_S_ASSUMED,
    );
    e.steps + e.polish_steps_expected
}

/// How `auto`'s trial measures `campaign` at `population` within `budget`
/// candidate-steps: over whole runs where that costs at most the budget
/// and no run is longer than [`TRIAL_LONG_RECORD_STEPS`]; else over each
/// run's first steps (at most [`TRIAL_PREFIX_STEPS`], as many as the
/// budget allows); skipped where even [`TRIAL_PREFIX_MIN_STEPS`] would cost
/// more.
pub fn trial_plan(campaign: &Campaign, population: usize, budget: f64) -> TrialPlan {
    let steps = crate::job::steps_per_candidate(campaign);
    let n = trial_candidates(population, steps, TRIAL_STEPS);
    let longest = longest_record_steps(campaign);
    let runs = campaign.problem.experiments.len().max(1) as f64;
    let whole = TRIAL_PASSES * n as f64 * steps;
    let mut plan = TrialPlan {
        candidates: n,
        prefix: None,
        why: None,
        skip: false,
        budget,
    };
    if longest < TRIAL_LONG_RECORD_STEPS && whole <= budget {
        return plan;
    }
    let affordable = (budget / (TRIAL_PASSES * n as f64 * runs)).floor();
    let prefix = (TRIAL_PREFIX_STEPS as f64)
        .min(affordable)
        .min(longest.ceil());
    let reason = if longest >= TRIAL_LONG_RECORD_STEPS {
        format!(
            "the longest run is {longest:.3e} steps, over {TRIAL_LONG_RECORD_STEPS:.0}: \
             timed over its first part only"
        )
    } else {
        format!(
            "whole runs would take {:.0} % of the job's estimated {:.2e} candidate-steps, \
             over {:.0} %",
            100.0 * whole / job_candidate_steps(campaign).max(1.0),
            job_candidate_steps(campaign),
            100.0 * TRIAL_SHARE
        )
    };
    if prefix < TRIAL_PREFIX_MIN_STEPS as f64 {
        plan.skip = true;
        plan.why = Some(format!(
            "{n} candidates over each run's first {TRIAL_PREFIX_MIN_STEPS} steps on both paths \
             would take more than the trial's share of the job ({:.0} % of its estimated \
             {:.2e} candidate-steps); --backend gpu runs it on the GPU",
            100.0 * TRIAL_SHARE,
            job_candidate_steps(campaign)
        ));
        return plan;
    }
    plan.prefix = Some(prefix as usize);
    plan.why = Some(reason);
    plan
}

/// The budget of a job's trial: [`TRIAL_SHARE`] of its estimated
/// candidate-steps, at least [`TRIAL_STEPS_FLOOR`].
pub fn job_trial_budget(campaign: &Campaign) -> f64 {
    (TRIAL_SHARE * job_candidate_steps(campaign)).max(TRIAL_STEPS_FLOOR)
}

/// The budget of `check`'s race: [`CHECK_RACE_STEPS`], or the job's own
/// where smaller, so that `check` takes a second or two.
pub fn check_trial_budget(campaign: &Campaign) -> f64 {
    job_trial_budget(campaign).min(CHECK_RACE_STEPS)
}

/// Most candidate-steps `check`'s race spends on both paths together.
pub const CHECK_RACE_STEPS: f64 = 4.0 * CHECK_TRIAL_STEPS;

/// `campaign` with every run cut to its first `steps` steps (at least two
/// samples each): what a shortened trial times the CPU on.
pub(super) fn prefix_campaign(campaign: &Campaign, steps: usize) -> Campaign {
    let mut c = campaign.clone();
    let lengths = campaign.run_length();
    let substeps = c.problem.substeps.max(1);
    for (x, run) in c.problem.experiments.iter_mut().zip(&lengths.experiments) {
        let prologue =
            (run.steps - x.window.end.saturating_sub(1) as f64 * substeps as f64).max(0.0) as usize;
        let samples = steps.saturating_sub(prologue) / substeps + 1;
        let end = x.window.end.min(samples.max(2));
        let start = if x.window.start + 1 < end {
            x.window.start
        } else {
            0
        };
        x.window = start..end;
        x.measured.truncate(end);
    }
    c
}

/// Candidates in a timed trial batch: the population where it takes at
/// most `budget` candidate-steps ([`TRIAL_STEPS`] for `auto`'s race), else
/// as many whole workgroups as fit, at least [`TRIAL_MIN_CANDIDATES`].
pub(super) fn trial_candidates(population: usize, steps_per_candidate: f64, budget: f64) -> usize {
    let fit = (budget / steps_per_candidate.max(1.0)) as usize / 64 * 64;
    population.min(fit.max(TRIAL_MIN_CANDIDATES)).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        x.measured = (0..n).map(|k| x.measured[k % x.measured.len()]).collect();
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
