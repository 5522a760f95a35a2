//! The CPU evaluator: the f64 RK4 reference, parallel over candidates (rayon);
//! or, asked for f32 ([`CpuEvaluator::use_f32`]), a compiled rig's f32 lane
//! ensemble.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::{
    Batch, EvalError, Evaluator, EvaluatorInfo, History, Precision, Problem, Scores, Timed,
    score_many, score_one, simulate_histories, simulate_history, simulate_scored,
};

/// Scores candidates with the f64 reference on a rayon pool.
#[derive(Debug)]
pub struct CpuEvaluator {
    problem: Problem,
    pool: Arc<rayon::ThreadPool>,
    cancel: Option<Arc<AtomicBool>>,
    precision: Precision,
    /// The thread of [`Timed::prepare_soon`]'s builds, joined on drop.
    early_builds: Option<std::thread::JoinHandle<()>>,
    /// One thread fewer than `pool`, which batches run on while the early
    /// builds' C compiler runs ([`CpuEvaluator::active_pool`]); `None` on
    /// a pool of one thread.
    beside_builds: Option<rayon::ThreadPool>,
}

impl Drop for CpuEvaluator {
    fn drop(&mut self) {
        if let Some(builds) = self.early_builds.take() {
            let _ = builds.join();
        }
    }
}

/// The cores this process may run on: what "all cores" means for
/// [`CpuEvaluator`] (`threads` 0), for the rates kept per machine and for the
/// time estimates; 1 where the system will not say.
pub fn all_cores() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

impl CpuEvaluator {
    /// An evaluator on `threads` threads (0: all cores).
    ///
    /// # Panics
    /// When the system refuses to start the threads; [`CpuEvaluator::try_new`]
    /// returns that as an error instead.
    pub fn new(problem: Problem, threads: usize) -> Self {
        Self::try_new(problem, threads).expect("starting the CPU evaluator's threads")
    }

    /// An evaluator on `threads` threads (0: all cores), or
    /// [`EvalError::Unsupported`] when the system refuses to start them.
    pub fn try_new(problem: Problem, threads: usize) -> Result<Self, EvalError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| {
                EvalError::Unsupported(format!(
                    "the system refused to start {threads} threads: {e}"
                ))
            })?;
        Ok(Self::on_pool(problem, Arc::new(pool)))
    }

    /// An evaluator on a pool it shares with others: the jobs of a series
    /// run side by side ([`crate::series`]), their batches on the same
    /// threads. The same bits as on a pool of its own.
    pub fn on_pool(problem: Problem, pool: Arc<rayon::ThreadPool>) -> Self {
        Self {
            problem,
            pool,
            cancel: None,
            precision: Precision::F64,
            early_builds: None,
            beside_builds: None,
        }
    }

    /// The pool a batch runs on: while the C compiler of
    /// [`Timed::prepare_soon`]'s builds runs, one thread fewer, so that
    /// the compiler has a core of its own. On two cores the quarter car's
    /// build took 0.8 s beside two interpreting threads and 0.3 s alone,
    /// and the interpreter is several times slower than the code it waits for.
    fn active_pool(&self) -> &rayon::ThreadPool {
        let building = self.early_builds.as_ref().is_some_and(|b| !b.is_finished());
        match &self.beside_builds {
            Some(narrow) if building => narrow,
            _ => &self.pool,
        }
    }

    /// Starts, in the background, the native builds a search scores with
    /// and, with `histories`, the polish's (the full programs') after them:
    /// [`Timed::prepare_soon`] with both; `auto`'s trial with the
    /// search's alone, so that the CPU is timed without waiting for a build
    /// only the polish needs (on the aa2024 campaign each takes 0.4 s), whose
    /// own build starts once the CPU is chosen.
    pub fn start_early_builds(&mut self, histories: bool) {
        if self.early_builds.is_some() {
            return;
        }
        let problem = &self.problem;
        let exps = &problem.experiments;
        let scoring: Vec<_> = (0..exps.len()).map(|e| problem.scoring_model(e)).collect();
        // Every fitness build first (the search: each scoring model's first),
        // then the full programs' (the polish's histories: the rig's own
        // model's last); `start_builds` takes a slot named twice once.
        let fitness = scoring
            .iter()
            .zip(exps)
            .filter_map(|(model, exp)| model.native_builds(&exp.drive).first().copied());
        let full = exps
            .iter()
            .filter_map(|exp| problem.model.native_builds(&exp.drive).last().copied())
            .filter(|_| histories);
        let builds: Vec<_> = fitness.chain(full).collect();
        self.early_builds = crate::compile::back::native::start_builds(&builds);
        let threads = self.pool.current_num_threads();
        if self.early_builds.is_some() && threads > 1 && self.beside_builds.is_none() {
            // A pool that will not start leaves the batches on `pool`.
            self.beside_builds = rayon::ThreadPoolBuilder::new()
                .num_threads(threads - 1)
                .build()
                .ok();
        }
    }

    /// Scores in f32 from now on (a compiled rig's native f32 lane ensemble,
    /// held to the f32 tolerance of the reference), or, unchanged (f64),
    /// [`EvalError::Unsupported`] saying why it cannot: a model without an
    /// f32 path (the hand-written ones), or no C compiler to build it.
    pub fn use_f32(&mut self) -> Result<(), EvalError> {
        for (e, exp) in self.problem.experiments.iter().enumerate() {
            let grid = exp.grid(0.0, self.problem.substeps);
            let built = self.problem.scoring_model(e).simulate_measured(
                &[],
                &exp.drive,
                &grid,
                true,
                &mut |_, _| {},
            );
            if !built {
                return Err(EvalError::Unsupported(format!(
                    "f32 on the CPU needs the rig's lane code built by the C compiler (`cc`, or \
                     RIGFIT_CC; not with RIGFIT_NATIVE=off); experiment {} has none",
                    exp.name
                )));
            }
        }
        self.precision = Precision::F32;
        Ok(())
    }

    /// Runs one task advances together out of `runs`: as many as the model's
    /// lanes hold, but no more than a thread's share (in whole vector blocks
    /// where the share is a block or more), so that a small batch (the
    /// polish's Jacobian, six histories at a time on the EMPS rig) still
    /// spreads over every thread: a block's runs take one vector whether one
    /// lane is used or all, so a thread's three runs cost what its six did.
    fn group_size(&self, runs: usize) -> usize {
        let block = crate::compile::exec::lanes::W;
        let share = runs.div_ceil(self.active_pool().current_num_threads().max(1));
        let share = if share >= block {
            share.next_multiple_of(block)
        } else {
            share
        };
        self.problem.model.lanes().min(share).max(1)
    }

    /// One record per candidate of `which` and experiment,
    /// `[candidate][experiment]`, from `record(problem, e, params, offset)`
    /// (one per run of `params`, which share the clock offset): in groups
    /// of at most a thread's share of the runs, each group advanced by the
    /// lane ensemble where its runs share the clock offset (the same bits as
    /// the reference run by run, at the lanes' rate: the polish asks for
    /// records at every iteration), run by run where they do not.
    fn records<T: Send>(
        &self,
        batch: &Batch,
        which: &[usize],
        record: impl Fn(&Problem, usize, &[&[f64]], f64) -> Vec<T> + Sync,
    ) -> Vec<Vec<T>> {
        let problem = &self.problem;
        let group = self.group_size(which.len());
        let groups: Vec<Vec<Vec<T>>> = self.active_pool().install(|| {
            which
                .par_chunks(group)
                .map(|group| {
                    let per_exp: Vec<Vec<T>> = (0..problem.experiments.len())
                        .map(|e| {
                            let offset = batch.offsets[e][group[0]];
                            let shared = group
                                .iter()
                                .all(|&i| batch.offsets[e][i].to_bits() == offset.to_bits());
                            if shared {
                                let params: Vec<&[f64]> =
                                    group.iter().map(|&i| batch.params_of(e, i)).collect();
                                record(problem, e, &params, offset)
                            } else {
                                group
                                    .iter()
                                    .flat_map(|&i| {
                                        let (p, o) = (batch.params_of(e, i), batch.offsets[e][i]);
                                        record(problem, e, &[p], o)
                                    })
                                    .collect()
                            }
                        })
                        .collect();
                    // Candidate-major: each run's records over the experiments.
                    let mut per_exp: Vec<_> = per_exp.into_iter().map(Vec::into_iter).collect();
                    (0..group.len())
                        .map(|_| per_exp.iter_mut().filter_map(Iterator::next).collect())
                        .collect()
                })
                .collect()
        });
        groups.into_iter().flatten().collect()
    }
}

impl Evaluator for CpuEvaluator {
    fn info(&self) -> EvaluatorInfo {
        EvaluatorInfo {
            backend: "cpu".into(),
            device: match self.pool.current_num_threads() {
                1 => "1 thread".to_string(),
                n => format!("{n} threads (rayon)"),
            },
            precision: self.precision,
        }
    }

    fn problem(&self) -> &Problem {
        &self.problem
    }

    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        self.problem.check_batch(batch)?;
        let ne = self.problem.experiments.len();
        let problem = &self.problem;
        let cancelled = || {
            self.cancel
                .as_ref()
                .is_some_and(|f| f.load(Ordering::Relaxed))
        };
        // Groups of consecutive candidates of one experiment with one offset
        // (one sample grid), as many as the model advances together, at most
        // a thread's share.
        let lanes = self.group_size(batch.candidates);
        let mut groups: Vec<(usize, usize, usize)> = Vec::new();
        for e in 0..ne {
            let mut i = 0;
            while i < batch.candidates {
                let off = batch.offsets[e][i].to_bits();
                let mut n = 1;
                while n < lanes
                    && i + n < batch.candidates
                    && batch.offsets[e][i + n].to_bits() == off
                {
                    n += 1;
                }
                groups.push((e, i, n));
                i += n;
            }
        }
        let scored: Vec<Vec<(f64, bool)>> = self.active_pool().install(|| {
            groups
                .par_iter()
                .map(|&(e, i, n)| {
                    // Each group checks before its runs, so an interrupt stops
                    // the batch within one group per thread.
                    if cancelled() {
                        return vec![(f64::NAN, false); n];
                    }
                    if n == 1 && self.precision == Precision::F64 {
                        return vec![score_one(
                            problem,
                            e,
                            batch.params_of(e, i),
                            batch.offsets[e][i],
                        )];
                    }
                    let params: Vec<&[f64]> = (i..i + n).map(|c| batch.params_of(e, c)).collect();
                    score_many(problem, e, &params, batch.offsets[e][i], self.precision)
                })
                .collect()
        });
        let mut runs = vec![(f64::NAN, false); batch.candidates * ne];
        for (&(e, i, _), vals) in groups.iter().zip(scored) {
            for (k, v) in vals.into_iter().enumerate() {
                runs[(i + k) * ne + e] = v;
            }
        }
        if cancelled() {
            return Err(EvalError::Cancelled);
        }
        Ok(Scores {
            experiments: ne,
            diverged: runs.iter().filter(|r| r.1).count(),
            values: runs.into_iter().map(|r| r.0).collect(),
        })
    }

    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        Ok(
            self.records(batch, which, |problem, e, params, offset| match params {
                [p] => vec![simulate_history(problem, e, p, offset)],
                _ => simulate_histories(problem, e, params, offset),
            }),
        )
    }

    fn checked_scored_outputs(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, EvalError> {
        Ok(self.records(batch, which, simulate_scored))
    }

    fn set_cancel(&mut self, flag: Arc<AtomicBool>) {
        self.cancel = Some(flag);
    }
}

impl Timed for CpuEvaluator {
    fn prepare(&mut self) {
        // Every build started early is done (none left to compete with a
        // timed batch), then the fitness builds, if none was started.
        if let Some(builds) = self.early_builds.take() {
            let _ = builds.join();
        }
        for (e, exp) in self.problem.experiments.iter().enumerate() {
            self.problem.scoring_model(e).prepare_native(&exp.drive);
        }
    }

    fn prepare_soon(&mut self) {
        self.start_early_builds(true);
    }
}
