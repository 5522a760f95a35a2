//! What a search reports: per generation, and at the end. Also the NaN-proof
//! statistics behind those reports.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::genes::GeneSpec;
use super::methods::Method;
use super::polish::PolishOutcome;
use crate::eval::DIVERGED;

/// Why a search stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TerminationReason {
    /// The best cost reached `target_fitness`.
    TargetReached,
    /// `generations` generations were evaluated.
    MaxGenerations,
    /// The best cost did not improve for `stall_generations` generations.
    Stalled,
    /// `max_time_s` of wall time passed.
    Timeout,
    /// `max_evaluations` candidates were scored.
    MaxEvaluations,
    /// The method found nothing more to learn (CMA-ES: its step or the spread
    /// of its costs fell below its tolerance, with no restart left).
    Converged,
    /// The interrupt flag was raised (Ctrl-C, SIGTERM).
    Interrupted,
}

impl fmt::Display for TerminationReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::TargetReached => "target fitness reached",
            Self::MaxGenerations => "maximum number of generations reached",
            Self::Stalled => "no improvement for the allowed number of generations",
            Self::Timeout => "wall-time limit reached",
            Self::MaxEvaluations => "maximum number of evaluations reached",
            Self::Converged => "the search method converged",
            Self::Interrupted => "interrupted",
        })
    }
}

/// One generation, as observers and `history.csv` see it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GenerationReport {
    /// Generation index (0 = initial population).
    pub generation: usize,
    /// Best cost so far (1 − R², joint), over all generations.
    pub best_cost: f64,
    /// Median cost of this generation's population.
    pub median_cost: f64,
    /// Best genome so far (values, not scale space).
    pub best_genome: Vec<f64>,
    /// Whether the best improved in this generation.
    pub improved: bool,
    /// Mean over genes of the population's standard deviation in scale space,
    /// divided by the gene's scale-space range (0: collapsed; ≈0.29: uniform).
    pub diversity: f64,
    /// Cost evaluations so far (candidates, not counting reused elites).
    pub evaluations: u64,
    /// Candidates evaluated in this generation.
    pub evaluated: usize,
    /// Candidates evaluated per second of this generation's wall time.
    pub evals_per_s: f64,
    /// Candidates of this generation whose cost was [`DIVERGED`] (or non-finite).
    pub diverged: usize,
    /// Blown-up runs as the cost function counted them (e.g. candidate × experiment).
    pub diverged_runs: usize,
    /// Wall time since the search began, including time before a resume (s).
    pub elapsed_s: f64,
}

/// Spread of one gene over the final elite (best 10 % of the population).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EliteSpread {
    /// Gene name.
    pub name: String,
    /// Smallest elite value.
    pub min: f64,
    /// Largest elite value.
    pub max: f64,
    /// Mean elite value (in scale space, mapped back: geometric mean for log genes).
    pub center: f64,
    /// Standard deviation in scale space (log genes: of ln value).
    pub std_scaled: f64,
    /// Elite range over the gene's search range, in scale space: near 0 means the
    /// data pin the parameter down, near 1 means they do not constrain it.
    pub relative_width: f64,
}

/// Everything a finished search returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchOutcome {
    /// Best genome found (values).
    pub best_genome: Vec<f64>,
    /// Its cost.
    pub best_cost: f64,
    /// Final population (values), best first.
    pub population: Vec<Vec<f64>>,
    /// Costs of [`Self::population`], ascending.
    pub costs: Vec<f64>,
    /// Per-gene spread over the final elite.
    pub elite_spread: Vec<EliteSpread>,
    /// Generations evaluated.
    pub generations: usize,
    /// Cost evaluations.
    pub evaluations: u64,
    /// Wall time including time before any resume (s).
    pub wall_time_s: f64,
    /// Why the search stopped.
    pub termination: TerminationReason,
    /// Per-generation reports.
    pub history: Vec<GenerationReport>,
    /// Things a user should know (e.g. many diverged candidates).
    pub warnings: Vec<String>,
    /// The method that searched.
    #[serde(default)]
    pub method: Method,
    /// What the method learned beside the polish ([`super::Solver::summary`]:
    /// CMA-ES's covariance); `None` for the GA.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method_summary: Option<serde_json::Value>,
    /// The polish that followed the GA ([`super::Executor::then_polish`]);
    /// `None` when none was configured or the GA was interrupted. Not part of
    /// a checkpoint: the polish is a pure function of the GA's final state, so a
    /// resumed job runs it again and reaches the same bits.
    #[serde(skip)]
    pub polish: Option<PolishOutcome>,
}

/// A cost fit for ordering and statistics: NaN and ±∞ become [`DIVERGED`].
pub fn sanitize_cost(c: f64) -> f64 {
    if c.is_finite() { c } else { DIVERGED }
}

/// Whether a (raw) cost marks a blown-up candidate.
pub fn is_diverged(c: f64) -> bool {
    !c.is_finite() || c >= DIVERGED
}

/// Indices sorted by ascending sanitized cost; ties keep index order.
pub fn ranking(costs: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| sanitize_cost(costs[a]).total_cmp(&sanitize_cost(costs[b])));
    order
}

/// Median of the sanitized costs (mean of the middle two for even length).
pub fn median(costs: &[f64]) -> f64 {
    let mut v: Vec<f64> = costs.iter().map(|&c| sanitize_cost(c)).collect();
    crate::base::stats::median(&mut v)
}

fn mean_std(xs: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = xs.clone().count().max(1) as f64;
    let mean = xs.clone().sum::<f64>() / n;
    let var = xs.map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// Mean normalized standard deviation of a scale-space population.
pub fn diversity(population: &[Vec<f64>], bounds: &[(f64, f64)]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (j, &(lo, hi)) in bounds.iter().enumerate() {
        if hi > lo {
            let (_, std) = mean_std(population.iter().map(|g| g[j]));
            sum += std / (hi - lo);
            count += 1;
        }
    }
    if count == 0 { 0.0 } else { sum / count as f64 }
}

/// Per-gene spread over the best `max(2, ⌈10 %⌉)` of a scale-space population
/// sorted best first (fewer if the population is smaller).
pub fn elite_spread(sorted: &[Vec<f64>], genes: &[GeneSpec]) -> Vec<EliteSpread> {
    let k = sorted.len().div_ceil(10).max(2).min(sorted.len());
    let elite = &sorted[..k];
    genes
        .iter()
        .enumerate()
        .map(|(j, g)| {
            let (lo, hi) = g.scaled_bounds();
            let col = elite.iter().map(|x| x[j]);
            let (mean, std) = mean_std(col.clone());
            let min = col.clone().fold(f64::INFINITY, f64::min);
            let max = col.fold(f64::NEG_INFINITY, f64::max);
            EliteSpread {
                name: g.name.clone(),
                min: g.to_value(min),
                max: g.to_value(max),
                center: g.to_value(mean),
                std_scaled: std,
                relative_width: if hi > lo {
                    (max - min) / (hi - lo)
                } else {
                    0.0
                },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::Scale;

    #[test]
    fn nan_and_diverged_sort_last_and_do_not_poison_median() {
        let costs = [
            0.3,
            f64::NAN,
            DIVERGED,
            0.1,
            f64::INFINITY,
            0.2,
            f64::NEG_INFINITY,
        ];
        let order = ranking(&costs);
        assert_eq!(&order[..3], &[3, 5, 0]);
        assert!(order[3..].iter().all(|&i| is_diverged(costs[i])));
        assert_eq!(median(&costs), DIVERGED);
        assert_eq!(median(&[0.1, f64::NAN, 0.2]), 0.2);
        assert!(median(&[0.1, 0.3]).is_finite());
    }

    #[test]
    fn diversity_of_collapsed_population_is_zero() {
        let pop = vec![vec![0.5, 1.0]; 4];
        assert_eq!(diversity(&pop, &[(0.0, 1.0), (0.0, 2.0)]), 0.0);
    }

    #[test]
    fn elite_spread_reports_values_in_bounds() {
        let g = GeneSpec::new("k", 1.0, 100.0, Scale::Log);
        let sorted: Vec<Vec<f64>> = (0..20).map(|i| vec![(1.0 + i as f64).ln()]).collect();
        let s = &elite_spread(&sorted, &[g])[0];
        assert_eq!((s.min, s.max), (1.0, 2.0));
        assert!(s.relative_width > 0.0 && s.relative_width < 0.2);
    }

    #[test]
    fn display_is_human_readable() {
        assert_eq!(
            TerminationReason::Stalled.to_string(),
            "no improvement for the allowed number of generations"
        );
    }
}
