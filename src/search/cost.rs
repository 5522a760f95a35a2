//! The cost interface the search calls, one whole population at a time.

use super::SearchError;
use super::report::is_diverged;

/// Costs of one batch of genomes.
#[derive(Debug, Clone, PartialEq)]
pub struct CostBatch {
    /// One cost per genome, lower is better: the joint `1 − R²`, or
    /// [`crate::eval::DIVERGED`] for a blown-up candidate. NaN is tolerated
    /// (treated as diverged) but should not happen.
    pub costs: Vec<f64>,
    /// Blown-up runs as the cost function counts them (for an
    /// [`crate::eval::Evaluator`]: [`crate::eval::Scores::diverged`], i.e.
    /// candidate × experiment runs). Only reported, never used by the search.
    pub diverged: usize,
}

/// A batched cost function: the GA hands it a whole generation, so a GPU
/// evaluator can score every candidate in one dispatch.
pub trait BatchCost {
    /// Costs of `genomes` (values in each gene's own unit, inside its bounds),
    /// in the same order.
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError>;
}

impl<C: BatchCost + ?Sized> BatchCost for &mut C {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        (**self).cost(genomes)
    }
}

impl<C: BatchCost + ?Sized> BatchCost for Box<C> {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        (**self).cost(genomes)
    }
}

/// A per-genome closure as a [`BatchCost`] (tests, analytic problems).
///
/// ```
/// use rigfit::search::{BatchCost, FnCost};
/// let mut sphere = FnCost(|x: &[f64]| x.iter().map(|v| v * v).sum::<f64>());
/// let batch = sphere.cost(&[vec![1.0, 2.0], vec![0.0, 0.0]]).unwrap();
/// assert_eq!(batch.costs, [5.0, 0.0]);
/// ```
#[derive(Debug, Clone)]
pub struct FnCost<F>(pub F);

impl<F: FnMut(&[f64]) -> f64> BatchCost for FnCost<F> {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        let costs: Vec<f64> = genomes.iter().map(|g| (self.0)(g)).collect();
        let diverged = costs.iter().filter(|&&c| is_diverged(c)).count();
        Ok(CostBatch { costs, diverged })
    }
}
