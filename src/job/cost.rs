//! The campaign as the search's batched cost, with CPU fallback on device loss.

use crate::campaign::Campaign;
use crate::eval::{CpuEvaluator, EvalError, Evaluator, scored_residuals};
use crate::search::{BatchCost, CostBatch, ResidualCost, SearchError};

/// Scores genomes: genomes → per-experiment parameter vectors → evaluator →
/// weighted mean of `1 − R²`.
pub struct CampaignCost<'a> {
    campaign: &'a Campaign,
    evaluator: Box<dyn Evaluator>,
    require_gpu: bool,
    threads: usize,
    fallback: Option<String>,
    chunk: usize,
    history_chunk: usize,
    interrupt: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
}

/// RK4 steps per CPU core a chunk of the polish's residuals takes at most
/// (at the assumed rate, about a quarter of a second), where the chunk can
/// be smaller than the memory allows: between two chunks an interrupt is
/// honoured, and the evaluators do not stop a run of residuals partway.
const RESIDUAL_STEPS_PER_CORE: f64 = 0.25 * crate::campaign::CPU_STEPS_PER_S_PER_CORE;

impl<'a> CampaignCost<'a> {
    /// A cost over `campaign` scored by `evaluator`.
    pub fn new(
        campaign: &'a Campaign,
        evaluator: Box<dyn Evaluator>,
        require_gpu: bool,
        threads: usize,
    ) -> Self {
        let info = evaluator.info();
        let gpu_real =
            (info.backend == "gpu").then_some(crate::gpu::real_size(info.precision) as usize);
        Self {
            campaign,
            evaluator,
            require_gpu,
            threads,
            fallback: None,
            chunk: super::memory::chunk_candidates(campaign),
            history_chunk: super::memory::history_chunk(campaign, gpu_real),
            interrupt: None,
        }
    }

    /// Stops the residuals between two chunks once `flag` is raised
    /// ([`EvalError::Cancelled`]), each chunk at most about a quarter of a
    /// second's work (`RESIDUAL_STEPS_PER_CORE`) but a pair of runs for
    /// each core.
    pub fn with_interrupt(mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) -> Self {
        let cores = crate::eval::all_cores();
        let steps = super::steps_per_candidate(self.campaign).max(1.0);
        let quick = ((RESIDUAL_STEPS_PER_CORE * cores as f64 / steps) as usize).max(2 * cores);
        self.history_chunk = self.history_chunk.min(quick).max(1);
        self.interrupt = Some(flag);
        self
    }

    /// Evaluates at most `fitness` candidates and `histories` histories per
    /// call of the evaluator (the defaults come from [`super::memory`]). The
    /// results do not depend on it: every run is scored on its own.
    pub fn with_chunks(mut self, fitness: usize, histories: usize) -> Self {
        self.chunk = fitness.max(1);
        self.history_chunk = histories.max(1);
        self
    }

    /// Why the job moved to the CPU, if it did.
    pub fn fallback_note(&self) -> Option<String> {
        self.fallback.clone()
    }

    /// Arithmetic precision of the evaluator in use now.
    pub fn precision(&self) -> crate::eval::Precision {
        self.evaluator.info().precision
    }

    /// The evaluator in use now.
    pub fn into_evaluator(self) -> Box<dyn Evaluator> {
        self.evaluator
    }
}

impl CampaignCost<'_> {
    /// Runs `f` on the evaluator; on a device failure (unless the GPU is
    /// required) moves to the CPU, says so once, and runs `f` again there.
    fn with_fallback<T>(
        &mut self,
        mut f: impl FnMut(&mut dyn Evaluator) -> Result<T, EvalError>,
    ) -> Result<T, SearchError> {
        match f(self.evaluator.as_mut()) {
            Ok(v) => Ok(v),
            Err(EvalError::Device(msg)) if !self.require_gpu => {
                let note =
                    format!("the GPU failed ({msg}); continuing on the CPU from this generation");
                log::warn!("{note}");
                eprintln!("rigfit: warning: {note}");
                self.fallback = Some(note);
                self.evaluator = Box::new(CpuEvaluator::new(
                    self.campaign.problem.clone(),
                    self.threads,
                ));
                Ok(f(self.evaluator.as_mut())?)
            }
            Err(e) => Err(e.into()),
        }
    }
}

impl BatchCost for CampaignCost<'_> {
    /// Chunk by chunk, so that the batches and the evaluator's buffers stay
    /// the size of one chunk whatever the population.
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        let campaign = self.campaign;
        let mut costs = Vec::with_capacity(genomes.len());
        let mut diverged = 0;
        for part in genomes.chunks(self.chunk) {
            let batch = campaign.batch(part);
            let scores = self.with_fallback(|ev| ev.fitness(&batch))?;
            costs.extend(campaign.combine(&scores));
            diverged += scores.diverged;
        }
        Ok(CostBatch { costs, diverged })
    }
}

/// Residuals of every experiment's fit window, one after the other, each
/// scaled by `√(w_e / (W · SS_tot,e))` so that their sum of squares is the
/// joint fitness [`Campaign::combine`] gives (`W`: the sum of the weights).
/// The weights are taken relative to the largest, as `combine` takes them,
/// so that weights near the largest f64 (whose sum overflows) still give
/// finite residuals.
impl ResidualCost for CampaignCost<'_> {
    fn residuals(&mut self, genomes: &[Vec<f64>]) -> Result<Vec<Option<Vec<f64>>>, SearchError> {
        let campaign = self.campaign;
        let exps = &campaign.problem.experiments;
        let weights = campaign.problem.relative_weights();
        let total: f64 = weights.iter().sum();
        let scale: Vec<f64> = exps
            .iter()
            .zip(&weights)
            .map(|(x, w)| (w / (total * x.ss_tot())).sqrt())
            .collect();
        let mut out = Vec::with_capacity(genomes.len());
        // Records are the size of the record: a chunk at a time, each turned
        // into residuals (the fit windows only) before the next.
        for part in genomes.chunks(self.history_chunk) {
            if self
                .interrupt
                .as_ref()
                .is_some_and(|f| f.load(std::sync::atomic::Ordering::SeqCst))
            {
                return Err(EvalError::Cancelled.into());
            }
            let batch = campaign.batch(part);
            let which: Vec<usize> = (0..part.len()).collect();
            let scored = self.with_fallback(|ev| ev.scored_outputs(&batch, &which))?;
            out.extend(scored.iter().map(|per_exp| {
                let mut r = Vec::new();
                for ((exp, o), s) in exps.iter().zip(per_exp).zip(&scale) {
                    r.extend(scored_residuals(exp, o)?.into_iter().map(|v| v * s));
                }
                Some(r)
            }));
        }
        Ok(out)
    }

    fn blocks(&self) -> Vec<usize> {
        let exps = &self.campaign.problem.experiments;
        exps.iter().map(|x| x.window.len()).collect()
    }
}
