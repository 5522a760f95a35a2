//! The race itself: the trial batch scored on both paths, each made ready
//! first, and the faster kept ([`race`]).
//!
//! Both paths are made ready before either is timed ([`make_ready`]: the
//! CPU lanes' native code, the GPU's pipelines for each kernel variant),
//! so that nothing builds while a batch is timed. The GPU's kernel
//! variants are each timed, the fastest kept; on a long record over the
//! record's first part ([`super::trial_part`]), and where the trial is
//! shortened ([`super::TrialPlan`]) both paths over each run's first steps.
//! A close call ([`CLOSE_CALL`]) is timed once more on each path. The path
//! kept answers the batch it scored from memory ([`Remembered`]).

use std::collections::BTreeMap;
use std::time::Instant;

use super::plan::{TrialPlan, longest_record_steps, prefix_campaign, trial_part};
use super::{BackendTrial, TrialError, TrialWatch, trial_genomes};
use crate::campaign::Campaign;
use crate::eval::{Batch, Evaluator, Remembered, Scores, Timed};

/// Two paths' trial rates closer than this ratio are a close call, timed
/// once more each: on the shipped tensile example (2 048 candidates) the
/// CPU lanes' rate on a 2-core machine read 1.06e8 to 1.25e8 from one run
/// to the next, and lavapipe's 1.02e8 to 1.09e8, so that one batch each
/// chose lavapipe about one time in three, for a job 15 to 18 % slower.
pub const CLOSE_CALL: f64 = 1.15;

/// Candidates of a warm-up batch: enough for the GPU evaluator to build the
/// specialised kernel the job's generations use, and for the CPU's first
/// call into its native code and its first buffers of a batch's size (a
/// timed batch without it made the CPU look a third slower than it is).
const WARM_UP_CANDIDATES: usize = 64;

/// Makes `evaluator` ready to be timed on `genomes`: what it would make
/// ready once it pays ([`Timed::prepare`]: the CPU lanes' native builds),
/// then [`Timed::warm_up`] on the first [`WARM_UP_CANDIDATES`] genomes
/// (the GPU's pipelines for the kernel variant in use, run for one chunk;
/// the CPU scores them: its first call into its native code and its first
/// buffers).
pub(super) fn make_ready(
    campaign: &Campaign,
    evaluator: &mut dyn Timed,
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
pub(super) fn rate(
    campaign: &Campaign,
    evaluator: &mut dyn Evaluator,
    batch: &Batch,
    path: &'static str,
) -> Result<(f64, Scores), TrialError> {
    let start = Instant::now();
    let scores = evaluator
        .fitness(batch)
        .map_err(|source| TrialError::Eval { path, source })?;
    let s = start.elapsed().as_secs_f64().max(1e-9);
    let candidate_steps = batch.candidates as f64 * crate::job::steps_per_candidate(campaign);
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
    gpu: &mut dyn Timed,
    batch: &Batch,
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
/// ([`crate::eval::CpuEvaluator::start_early_builds`]), and nothing builds while a batch
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
    gpu: (Box<dyn Timed>, Instant),
    cpu: Box<dyn Timed>,
    cpu_prefix: Option<Box<dyn Timed>>,
    watch: TrialWatch<'_>,
) -> Result<(Box<dyn Timed>, BackendTrial), TrialError> {
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
    (mut gpu, asked): (Box<dyn Timed>, Instant),
    mut cpu: Box<dyn Timed>,
    cpu_prefix: Option<Box<dyn Timed>>,
    part: Option<usize>,
    watch: TrialWatch<'_>,
) -> Result<(Box<dyn Timed>, BackendTrial), TrialError> {
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
            crate::job::steps_per_candidate(campaign)
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
    let cpu_timed: &mut dyn Timed = match timed_cpu.as_mut() {
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
    let chosen: Box<dyn Timed> = match (gpu_wins, gpu_timed, shortened) {
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

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

    use super::*;
    use crate::eval::{EvalError, EvaluatorInfo, History, Precision, Problem};

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
        fn checked_histories(
            &mut self,
            _batch: &Batch,
            _which: &[usize],
        ) -> Result<Vec<Vec<History>>, EvalError> {
            Ok(vec![])
        }
    }

    impl Timed for Paced {
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
}
