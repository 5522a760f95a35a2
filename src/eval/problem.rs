//! The validated, evaluable part of a campaign.

use std::ops::Range;
use std::sync::Arc;

use super::{Batch, EvalError};
use crate::base::Drive;
use crate::base::SampleGrid;
use crate::model::CompiledRig;

/// One measured experiment, ready to score against.
#[derive(Debug, Clone)]
pub struct ExperimentData {
    /// Name from the campaign.
    pub name: String,
    /// How the actuator is driven.
    pub drive: Drive,
    /// Record time of sample 0 (s).
    pub t_first: f64,
    /// Uniform sample interval (s).
    pub dt: f64,
    /// Which of the rig's outputs is measured (0 unless a campaign's
    /// `channels` name another).
    pub output: usize,
    /// The measured output (a force, a displacement, a voltage or an
    /// acceleration) at each sample, in that output's unit.
    pub measured: Vec<f64>,
    /// Samples scored by the fitness.
    pub window: Range<usize>,
    /// Weight in the joint fitness.
    pub weight: f64,
}

impl ExperimentData {
    /// Sum of squares of the measured output about its mean over the window.
    pub fn ss_tot(&self) -> f64 {
        let w = &self.measured[self.window.clone()];
        let mean = w.iter().sum::<f64>() / w.len() as f64;
        w.iter().map(|f| (f - mean) * (f - mean)).sum()
    }

    /// The record's noise over the fit window, estimated from the record
    /// itself ([`crate::base::noise::noise_sigma`]); `None` for a window too
    /// short to tell.
    pub fn noise_estimate(&self) -> Option<f64> {
        crate::base::noise::noise_sigma(&self.measured[self.window.clone()])
    }

    /// Magnitude beyond which a model output counts as having blown up: 1000 ×
    /// the largest measured magnitude (at least 1).
    pub fn blowup_limit(&self) -> f64 {
        1.0e3 * self.measured.iter().fold(1.0_f64, |m, f| m.max(f.abs()))
    }

    /// Integration grid for a candidate with clock offset `offset` (s).
    pub fn grid(&self, offset: f64, substeps: usize) -> SampleGrid {
        SampleGrid {
            t0: self.t_first + offset,
            dt: self.dt,
            samples: self.window.end,
            substeps,
        }
    }
}

/// A model with the experiments it is scored against.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The rig model.
    pub model: Arc<CompiledRig>,
    /// The experiments.
    pub experiments: Vec<ExperimentData>,
    /// RK4 steps per sample interval.
    pub substeps: usize,
}

impl Problem {
    /// The rig that scores experiment `e`: the model itself where it measures
    /// output 0, else the model compiled with its output first
    /// ([`CompiledRig::scoring`], compiled when the campaign was read).
    pub fn scoring_model(&self, e: usize) -> Arc<CompiledRig> {
        match self.experiments[e].output {
            0 => self.model.clone(),
            k => self
                .model
                .scoring(k)
                .expect("a scoring rig compiled when the campaign was read"),
        }
    }

    /// Each experiment's weight divided by the largest: in (0, 1], so a joint
    /// fitness summed with them cannot overflow, whatever the weights' size.
    /// Equal weights give exactly 1.
    pub fn relative_weights(&self) -> Vec<f64> {
        let max = self
            .experiments
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.weight));
        self.experiments.iter().map(|x| x.weight / max).collect()
    }

    /// The joint cost the records' noise alone would give: each experiment's
    /// `n σ² / SS_tot` (σ its noise estimated from the record over the fit
    /// window, [`crate::base::noise::noise_sigma`]; `n` the window's samples),
    /// weighted as the joint fitness weighs `1 − R²`. A perfect model scores
    /// about this; `None` where a record's noise cannot be estimated. The
    /// convergence plot draws it ([`crate::report::plots::convergence_svg`]).
    pub fn noise_floor(&self) -> Option<f64> {
        let weights = self.relative_weights();
        let total: f64 = weights.iter().sum();
        let mut sum = 0.0;
        for (x, w) in self.experiments.iter().zip(&weights) {
            let sigma = x.noise_estimate()?;
            sum += w * x.window.len() as f64 * sigma * sigma / x.ss_tot();
        }
        let floor = sum / total;
        (floor.is_finite() && floor > 0.0).then_some(floor)
    }

    /// Checks that a batch has one parameter set and one offset per candidate
    /// for every experiment, each of the model's length.
    pub fn check_batch(&self, batch: &Batch) -> Result<(), EvalError> {
        let ne = self.experiments.len();
        let p = self.model.params().len();
        if batch.params.len() != ne || batch.offsets.len() != ne {
            return Err(EvalError::Shape {
                expected: format!("{ne} experiments"),
                found: format!("{} parameter sets", batch.params.len()),
            });
        }
        for (e, (ps, os)) in batch.params.iter().zip(&batch.offsets).enumerate() {
            if ps.len() != batch.candidates * p || os.len() != batch.candidates {
                return Err(EvalError::Shape {
                    expected: format!("{} × {p} parameters in experiment {e}", batch.candidates),
                    found: format!("{}", ps.len()),
                });
            }
        }
        Ok(())
    }
}
