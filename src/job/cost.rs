//! The campaign as the search's batched cost, with CPU fallback on device loss.

use crate::campaign::Campaign;
use crate::eval::{CpuEvaluator, EvalError, Evaluator, window_residuals};
use crate::search::{BatchCost, CostBatch, ResidualCost, SearchError};

/// Scores genomes: genomes → per-experiment parameter vectors → evaluator →
/// weighted mean of `1 − R²`.
pub struct CampaignCost<'a> {
    campaign: &'a Campaign,
    evaluator: Box<dyn Evaluator>,
    require_gpu: bool,
    threads: usize,
    fallback: Option<String>,
}

impl<'a> CampaignCost<'a> {
    /// A cost over `campaign` scored by `evaluator`.
    pub fn new(
        campaign: &'a Campaign,
        evaluator: Box<dyn Evaluator>,
        require_gpu: bool,
        threads: usize,
    ) -> Self {
        Self {
            campaign,
            evaluator,
            require_gpu,
            threads,
            fallback: None,
        }
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
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        let batch = self.campaign.batch(genomes);
        let scores = self.with_fallback(|ev| ev.fitness(&batch))?;
        Ok(CostBatch {
            costs: self.campaign.combine(&scores),
            diverged: scores.diverged,
        })
    }
}

/// Residuals of every experiment's fit window, one after the other, each
/// scaled by `√(w_e / (W · SS_tot,e))` so that their sum of squares is the
/// joint fitness [`Campaign::combine`] gives (`W`: the sum of the weights).
impl ResidualCost for CampaignCost<'_> {
    fn residuals(&mut self, genomes: &[Vec<f64>]) -> Result<Vec<Option<Vec<f64>>>, SearchError> {
        let batch = self.campaign.batch(genomes);
        let which: Vec<usize> = (0..genomes.len()).collect();
        let histories = self.with_fallback(|ev| ev.histories(&batch, &which))?;
        let exps = &self.campaign.problem.experiments;
        let total: f64 = exps.iter().map(|x| x.weight).sum();
        let scale: Vec<f64> = exps
            .iter()
            .map(|x| (x.weight / (total * x.ss_tot())).sqrt())
            .collect();
        Ok(histories
            .iter()
            .map(|per_exp| {
                let mut r = Vec::new();
                for ((exp, h), s) in exps.iter().zip(per_exp).zip(&scale) {
                    r.extend(window_residuals(exp, h)?.into_iter().map(|v| v * s));
                }
                Some(r)
            })
            .collect())
    }
}
