//! Helpers shared by the search tests.
#![allow(dead_code, reason = "each test file uses a different subset")]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rigfit::search::{GenerationReport, Observer, SearchError, SearchOutcome, SearchSettings};

/// Settings from the campaign JSON defaults plus population, generations, seed.
pub fn settings(population: usize, generations: usize, seed: u64) -> SearchSettings {
    serde_json::from_value(serde_json::json!({
        "population": population, "generations": generations, "seed": seed
    }))
    .unwrap()
}

/// Sphere: Σ (x_i − c_i)².
pub fn sphere(center: &[f64]) -> impl FnMut(&[f64]) -> f64 + use<> {
    let c = center.to_vec();
    move |x: &[f64]| x.iter().zip(&c).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// 2-D Rosenbrock, minimum 0 at (1, 1).
pub fn rosenbrock(x: &[f64]) -> f64 {
    (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2)
}

/// Raises `flag` after generation `at` is observed (a simulated Ctrl-C).
pub struct InterruptAt {
    pub at: usize,
    pub flag: Arc<AtomicBool>,
}

impl Observer for InterruptAt {
    fn observe(&mut self, r: &GenerationReport) -> Result<(), SearchError> {
        if r.generation == self.at {
            self.flag.store(true, Ordering::SeqCst);
        }
        Ok(())
    }
}

/// Asserts two outcomes agree bit for bit in everything but wall-clock fields.
pub fn assert_same_result(a: &SearchOutcome, b: &SearchOutcome) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(a.best_cost.to_bits(), b.best_cost.to_bits(), "best cost");
    assert_eq!(bits(&a.best_genome), bits(&b.best_genome), "best genome");
    assert_eq!(a.population.len(), b.population.len());
    for (x, y) in a.population.iter().zip(&b.population) {
        assert_eq!(bits(x), bits(y), "population");
    }
    assert_eq!(bits(&a.costs), bits(&b.costs), "costs");
    assert_eq!(a.elite_spread, b.elite_spread, "elite spread");
    assert_eq!(
        (a.generations, a.evaluations),
        (b.generations, b.evaluations)
    );
    assert_eq!(a.termination, b.termination);
    assert_eq!(a.history.len(), b.history.len());
    for (x, y) in a.history.iter().zip(&b.history) {
        assert_eq!(x.generation, y.generation);
        assert_eq!(x.best_cost.to_bits(), y.best_cost.to_bits());
        assert_eq!(x.median_cost.to_bits(), y.median_cost.to_bits());
        assert_eq!(x.diversity.to_bits(), y.diversity.to_bits());
        assert_eq!(bits(&x.best_genome), bits(&y.best_genome));
        assert_eq!((x.evaluations, x.diverged), (y.evaluations, y.diverged));
    }
}
