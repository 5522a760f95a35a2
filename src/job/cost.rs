//! The campaign as the search's batched cost, with CPU fallback on device loss.

use crate::campaign::Campaign;
use crate::eval::{CpuEvaluator, EvalError, Evaluator};
use crate::search::{BatchCost, CostBatch, SearchError};

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

    /// The evaluator in use now.
    pub fn into_evaluator(self) -> Box<dyn Evaluator> {
        self.evaluator
    }
}

impl BatchCost for CampaignCost<'_> {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        let batch = self.campaign.batch(genomes);
        let scores = match self.evaluator.fitness(&batch) {
            Ok(s) => s,
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
                self.evaluator.fitness(&batch)?
            }
            Err(e) => return Err(e.into()),
        };
        Ok(CostBatch {
            costs: self.campaign.combine(&scores),
            diverged: scores.diverged,
        })
    }
}
