//! One GPU job over experiments that need different kernels of a rig.
//!
//! A compiled rig is lowered to one program per drive mode, and each program
//! has its own WGSL kernels, so a campaign that mixes velocity- and
//! force-driven experiments of one rig cannot run in one pipeline. The
//! [`GpuByDrive`] evaluator groups the experiments by the kernels they need
//! ([`kernel_groups`]), opens one [`GpuEvaluator`] per group on the shared
//! [`GpuContext`], hands each the part of every batch that belongs to its
//! experiments and puts the results back in the problem's experiment order.
//! Each run computes the same bits as in a job of its own group alone.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use crate::eval::{
    Batch, EvalError, Evaluator, EvaluatorInfo, History, Precision, Problem, Scores, Timed,
};
use crate::model::GpuModel;

use super::evaluator::gpu_info;
use super::{GpuContext, GpuError, GpuEvaluator, GpuOptions};

/// The experiments of a problem that run on one set of kernels.
#[derive(Debug, Clone)]
pub struct KernelGroup {
    /// The model's GPU plug-in for these experiments.
    pub model: GpuModel,
    /// Indices of the experiments in the problem, ascending.
    pub experiments: Vec<usize>,
}

/// The problem's experiments grouped by the kernels that run them, in the
/// order each group's first experiment appears. An error when the model has
/// no kernels for some experiment (or the problem has no experiments).
pub fn kernel_groups(problem: &Problem) -> Result<Vec<KernelGroup>, GpuError> {
    let id = problem.model.id().to_string();
    let mut groups: Vec<KernelGroup> = Vec::new();
    for e in 0..problem.experiments.len() {
        let g = super::kernels_for(problem, e)?;
        match groups
            .iter_mut()
            .find(|k| std::sync::Arc::ptr_eq(&k.model, &g))
        {
            Some(k) => k.experiments.push(e),
            None => groups.push(KernelGroup {
                model: g,
                experiments: vec![e],
            }),
        }
    }
    if groups.is_empty() {
        return Err(GpuError::UnsupportedModel(id));
    }
    Ok(groups)
}

/// One group's evaluator and the problem experiments it scores.
#[derive(Debug)]
struct Part {
    experiments: Vec<usize>,
    evaluator: GpuEvaluator,
}

/// Scores a problem whose experiments need different kernels: one
/// [`GpuEvaluator`] per [`KernelGroup`], on one device.
#[derive(Debug)]
pub struct GpuByDrive {
    ctx: GpuContext,
    problem: Problem,
    precision: Precision,
    parts: Vec<Part>,
}

impl GpuByDrive {
    /// Builds one evaluator per kernel group of `problem` on `ctx`.
    pub fn new(
        ctx: GpuContext,
        problem: Problem,
        precision: Precision,
        options: GpuOptions,
    ) -> Result<Self, GpuError> {
        let parts = kernel_groups(&problem)?
            .into_iter()
            .map(|group| {
                let sub = Problem {
                    model: problem.model.clone(),
                    experiments: group
                        .experiments
                        .iter()
                        .map(|&e| problem.experiments[e].clone())
                        .collect(),
                    substeps: problem.substeps,
                };
                Ok(Part {
                    evaluator: GpuEvaluator::new(ctx.clone(), sub, precision, options)?,
                    experiments: group.experiments,
                })
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        Ok(Self {
            ctx,
            problem,
            precision,
            parts,
        })
    }

    /// The experiments each evaluator scores, one list per kernel group.
    pub fn groups(&self) -> Vec<Vec<usize>> {
        self.parts.iter().map(|p| p.experiments.clone()).collect()
    }

    /// `run` on each kernel group's part of `batch`, each group on a thread
    /// of its own, so that their first batch's kernels compile side by side
    /// and their passes are submitted together; every run's bits are its own
    /// whatever runs beside it. The results in the groups' order.
    fn each_group<T: Send>(
        &mut self,
        batch: &Batch,
        run: impl Fn(&mut GpuEvaluator, &Batch) -> T + Sync,
    ) -> Vec<T> {
        let run = &run;
        std::thread::scope(|s| {
            let running: Vec<_> = self
                .parts
                .iter_mut()
                .map(|part| {
                    let sub = sub_batch(batch, &part.experiments);
                    s.spawn(move || run(&mut part.evaluator, &sub))
                })
                .collect();
            running
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
                .collect()
        })
    }

    /// Each kernel group's `[candidate][experiment]` records of candidates
    /// `which` (from `run` on the group's part of `batch`), put back in the
    /// problem's experiment order.
    fn gather<T>(
        &mut self,
        batch: &Batch,
        which: &[usize],
        mut run: impl FnMut(&mut GpuEvaluator, &Batch) -> Result<Vec<Vec<T>>, EvalError>,
    ) -> Result<Vec<Vec<T>>, EvalError> {
        let ne = self.problem.experiments.len();
        let mut out: Vec<Vec<Option<T>>> = (0..which.len())
            .map(|_| (0..ne).map(|_| None).collect())
            .collect();
        for part in &mut self.parts {
            let got = run(&mut part.evaluator, &sub_batch(batch, &part.experiments))?;
            for (row, per_exp) in out.iter_mut().zip(got) {
                for (&e, r) in part.experiments.iter().zip(per_exp) {
                    row[e] = Some(r);
                }
            }
        }
        out.into_iter()
            .map(|row| {
                row.into_iter()
                    .map(|r| {
                        r.ok_or_else(|| {
                            EvalError::Device("a kernel group left out a record".into())
                        })
                    })
                    .collect()
            })
            .collect()
    }
}

/// The part of `batch` that belongs to `experiments`, in their order.
fn sub_batch(batch: &Batch, experiments: &[usize]) -> Batch {
    Batch {
        candidates: batch.candidates,
        params: experiments
            .iter()
            .map(|&e| batch.params[e].clone())
            .collect(),
        offsets: experiments
            .iter()
            .map(|&e| batch.offsets[e].clone())
            .collect(),
    }
}

impl Evaluator for GpuByDrive {
    fn info(&self) -> EvaluatorInfo {
        gpu_info(&self.ctx, self.precision)
    }

    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        self.problem.check_batch(batch)?;
        let ne = self.problem.experiments.len();
        let mut values = vec![0.0; batch.candidates * ne];
        let mut diverged = 0;
        let all = self.each_group(batch, |ev, sub| ev.fitness(sub));
        for (part, scores) in self.parts.iter().zip(all) {
            let scores = scores?;
            let ng = part.experiments.len();
            for i in 0..batch.candidates {
                for (k, &e) in part.experiments.iter().enumerate() {
                    values[i * ne + e] = scores.values[i * ng + k];
                }
            }
            diverged += scores.diverged;
        }
        Ok(Scores {
            experiments: ne,
            values,
            diverged,
        })
    }

    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        self.gather(batch, which, |ev, sub| ev.histories(sub, which))
    }

    fn checked_scored_outputs(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, EvalError> {
        self.gather(batch, which, |ev, sub| ev.scored_outputs(sub, which))
    }

    fn set_cancel(&mut self, flag: Arc<AtomicBool>) {
        for part in &mut self.parts {
            part.evaluator.set_cancel(flag.clone());
        }
    }

    fn problem(&self) -> &Problem {
        &self.problem
    }
}

impl Timed for GpuByDrive {
    /// Each group's first chunk alone ([`Timed::fitness_part`] of one
    /// step).
    fn warm_up(&mut self, batch: &Batch) -> Result<(), EvalError> {
        self.fitness_part(batch, 1).map(|_| ())
    }

    fn fitness_part(&mut self, batch: &Batch, steps: usize) -> Result<Option<usize>, EvalError> {
        self.problem.check_batch(batch)?;
        // Every group's part, the most steps of any; `None` where any group
        // cannot stop partway.
        let mut most = Some(0);
        for part in self.each_group(batch, |ev, sub| ev.fitness_part(sub, steps)) {
            most = most.zip(part?).map(|(a, b)| a.max(b));
        }
        Ok(most)
    }

    fn kernel_variants(&self) -> &'static [&'static str] {
        crate::eval::KERNEL_VARIANTS
    }

    fn use_kernel_variant(&mut self, variant: &str) {
        for part in &mut self.parts {
            part.evaluator.use_kernel_variant(variant);
        }
    }
}
