//! A sweep's runs on a GPU: the experiment's history kernel (the same the
//! job's polish reads), one evaluator per step, every run of a step in one
//! batch; the metrics are computed from the histories read back.
//!
//! The GPU runs in the precision it is asked for; its rows agree with the
//! f64 CPU lanes within the tolerance of that precision (see the design
//! guide), not to the bit.

use std::collections::BTreeMap;

use super::DesignError;
use super::file::Sweep;
use super::run::{PreparedPoint, metrics_of};
use crate::eval::Timed;
use crate::eval::{Batch, PrecisionChoice, Problem};
use crate::gpu::{GpuContext, GpuError, evaluator_on_context};

/// The GPU a sweep runs on, and its evaluators by step.
pub struct GpuRuns {
    ctx: GpuContext,
    precision: PrecisionChoice,
    evaluators: BTreeMap<usize, Box<dyn Timed>>,
}

impl GpuRuns {
    /// Opens the adapter `adapter` names (`--adapter`, else `RIGFIT_ADAPTER`,
    /// else the first), to run in `precision`.
    pub fn open(adapter: Option<&str>, precision: PrecisionChoice) -> Result<Self, GpuError> {
        Ok(Self {
            ctx: GpuContext::select(adapter)?,
            precision,
            evaluators: BTreeMap::new(),
        })
    }

    /// The adapter, as result files name it.
    pub fn describe(&self) -> String {
        self.ctx.describe()
    }

    /// The precision the runs take on this adapter (`auto` resolved).
    pub fn precision(&self) -> Result<crate::eval::Precision, GpuError> {
        crate::gpu::resolve_precision(&self.ctx, self.precision)
    }

    /// The metrics of every run of the prepared points, `[point][run][metric]`.
    pub fn metrics(
        &mut self,
        sweep: &Sweep,
        prepared: &[PreparedPoint],
    ) -> Result<Vec<Vec<Vec<Option<f64>>>>, DesignError> {
        let mut by_step: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
        for (k, p) in prepared.iter().enumerate() {
            for r in 0..p.runs.len() {
                by_step.entry(p.substeps).or_default().push((k, r));
            }
        }
        let mut out: Vec<Vec<Vec<Option<f64>>>> = prepared
            .iter()
            .map(|p| vec![Vec::new(); p.runs.len()])
            .collect();
        // A batch's histories fit the device's largest storage binding and
        // buffer: each run's samples × (time, outputs, states) in f64 at
        // most, the records' layout.
        let limits = self.ctx.device.limits();
        let most = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let c = &sweep.campaign;
        let per_run = (c.problem.experiments[sweep.experiment].window.end as u64)
            * (1 + c.model.output_names().len() + c.model.state_names().len()) as u64
            * 8;
        let batch_runs = ((most / per_run.max(1)) as usize / 2).max(1);
        for (substeps, all) in by_step {
            let evaluator = self.evaluator(sweep, substeps)?;
            for runs in all.chunks(batch_runs) {
                let mut batch = Batch {
                    candidates: runs.len(),
                    params: vec![Vec::new()],
                    offsets: vec![Vec::with_capacity(runs.len())],
                };
                for &(k, r) in runs {
                    let (params, offset) = &prepared[k].runs[r];
                    batch.params[0].extend_from_slice(params);
                    batch.offsets[0].push(*offset);
                }
                let which: Vec<usize> = (0..runs.len()).collect();
                let histories = evaluator
                    .histories(&batch, &which)
                    .map_err(|e| DesignError::Device(e.to_string()))?;
                for (&(k, r), h) in runs.iter().zip(histories) {
                    let h = h.into_iter().next().ok_or_else(|| {
                        DesignError::Device("the GPU returned no history for a run".into())
                    })?;
                    out[k][r] = metrics_of(sweep, &h, &prepared[k].values);
                }
            }
        }
        Ok(out)
    }

    /// The evaluator of the sweep's experiment at `substeps` RK4 steps per
    /// sample, built on first use.
    fn evaluator(
        &mut self,
        sweep: &Sweep,
        substeps: usize,
    ) -> Result<&mut Box<dyn Timed>, DesignError> {
        if !self.evaluators.contains_key(&substeps) {
            let base = &sweep.campaign.problem;
            let problem = Problem {
                model: base.model.clone(),
                experiments: vec![base.experiments[sweep.experiment].clone()],
                substeps,
            };
            let ev = evaluator_on_context(self.ctx.clone(), problem, self.precision)
                .map_err(|e| DesignError::Device(e.to_string()))?;
            self.evaluators.insert(substeps, ev);
        }
        Ok(self.evaluators.get_mut(&substeps).expect("inserted"))
    }
}
