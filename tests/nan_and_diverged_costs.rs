//! Proves NaN, infinite and DIVERGED costs neither break sorting and statistics
//! nor go unreported.

use rigfit::base::Scale;
use rigfit::eval::DIVERGED;
use rigfit::search::{
    BatchCost, CostBatch, Executor, FnCost, GeneSpec, GeneticAlgorithm, SearchError,
};

mod common;

fn genes() -> Vec<GeneSpec> {
    vec![
        GeneSpec::new("x", -1.0, 1.0, Scale::Linear),
        GeneSpec::new("y", -1.0, 1.0, Scale::Linear),
    ]
}

#[test]
fn blown_up_candidates_rank_last_and_are_warned_about() {
    let ga = GeneticAlgorithm::new(common::settings(40, 30, 11), genes()).unwrap();
    // Half the box "diverges": NaN, +∞ or DIVERGED.
    let cost = FnCost(|g: &[f64]| match g[0] {
        x if x > 0.6 => f64::NAN,
        x if x > 0.3 => f64::INFINITY,
        x if x > 0.0 => DIVERGED,
        _ => g[0] * g[0] + g[1] * g[1],
    });
    let out = Executor::new(ga, cost).run().unwrap();
    assert!(out.best_cost < 1e-3, "{}", out.best_cost);
    assert!(out.costs.iter().all(|c| c.is_finite()));
    assert!(out.costs.windows(2).all(|w| w[0] <= w[1]));
    let first = &out.history[0];
    assert!(first.diverged > 10 && first.median_cost.is_finite() && first.diversity.is_finite());
    assert!(
        out.warnings.iter().any(|w| w.contains("diverged")),
        "{:?}",
        out.warnings
    );
}

#[test]
fn all_diverged_is_a_warning_not_a_crash() {
    let ga = GeneticAlgorithm::new(common::settings(8, 3, 12), genes()).unwrap();
    let out = Executor::new(ga, FnCost(|_: &[f64]| f64::NAN))
        .run()
        .unwrap();
    assert_eq!(out.best_cost, DIVERGED);
    assert!(
        out.warnings
            .iter()
            .any(|w| w.contains("every candidate diverged"))
    );
}

struct WrongLength;
impl BatchCost for WrongLength {
    fn cost(&mut self, _: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        Ok(CostBatch {
            costs: vec![0.0],
            diverged: 0,
        })
    }
}

#[test]
fn wrong_cost_count_is_an_error() {
    let ga = GeneticAlgorithm::new(common::settings(8, 3, 13), genes()).unwrap();
    let err = Executor::new(ga, WrongLength).run().unwrap_err();
    assert!(
        matches!(
            err,
            SearchError::CostLength {
                expected: 8,
                found: 1
            }
        ),
        "{err}"
    );
}
