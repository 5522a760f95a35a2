//! The Levenberg–Marquardt polish runs under the GA's executor: the same cost,
//! the same observers (one call per polish iteration), the same interrupt flag
//! and one termination reason; and it reaches the same bits as the polish run
//! on its own from the GA's outcome.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rigfit::base::Scale;
use rigfit::search::{
    BatchCost, CostBatch, Executor, GeneSpec, GeneticAlgorithm, Observer, ObserverMode, Polish,
    PolishIteration, PolishSettings, PolishStop, ResidualCost, SearchError, SearchOutcome,
    SearchSettings, TerminationReason, distinct_starts,
};

/// y = a·exp(−t/τ) + c sampled on a grid with a fixed, deterministic
/// "noise"; the cost is the sum of squared residuals.
struct Decay {
    t: Vec<f64>,
    y: Vec<f64>,
}

impl Decay {
    fn new() -> Self {
        let t: Vec<f64> = (0..60).map(|k| k as f64 * 0.05).collect();
        let y = t
            .iter()
            .enumerate()
            .map(|(k, &t)| 2.0 * (-t / 0.7).exp() + 0.3 + 1e-3 * ((k * 7919) % 13) as f64)
            .collect();
        Self { t, y }
    }

    fn residual(&self, g: &[f64]) -> Vec<f64> {
        self.t
            .iter()
            .zip(&self.y)
            .map(|(&t, y)| g[0] * (-t / g[1]).exp() + g[2] - y)
            .collect()
    }
}

impl BatchCost for Decay {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        let costs = genomes
            .iter()
            .map(|g| self.residual(g).iter().map(|r| r * r).sum())
            .collect();
        Ok(CostBatch { costs, diverged: 0 })
    }
}

impl ResidualCost for Decay {
    fn residuals(&mut self, genomes: &[Vec<f64>]) -> Result<Vec<Option<Vec<f64>>>, SearchError> {
        Ok(genomes.iter().map(|g| Some(self.residual(g))).collect())
    }
}

fn genes() -> Vec<GeneSpec> {
    vec![
        GeneSpec::new("a", 0.0, 10.0, Scale::Linear),
        GeneSpec::new("tau", 1e-2, 1e2, Scale::Log),
        GeneSpec::new("c", -1.0, 1.0, Scale::Linear),
    ]
}

fn ga() -> GeneticAlgorithm {
    let settings: SearchSettings =
        serde_json::from_str(r#"{"population": 24, "generations": 8, "seed": 3}"#).unwrap();
    GeneticAlgorithm::new(settings, genes()).unwrap()
}

/// Counts the polish iterations it is told of; raises `flag` at iteration `stop_at`.
#[derive(Clone)]
struct Watch {
    seen: Arc<std::sync::Mutex<Vec<PolishIteration>>>,
    flag: Arc<AtomicBool>,
    stop_at: Option<usize>,
}

impl Observer for Watch {
    fn observe(&mut self, _: &rigfit::search::GenerationReport) -> Result<(), SearchError> {
        Ok(())
    }

    fn polished(&mut self, step: &PolishIteration) -> Result<(), SearchError> {
        self.seen.lock().unwrap().push(*step);
        if self.stop_at == Some(step.iteration) {
            self.flag.store(true, Ordering::SeqCst);
        }
        Ok(())
    }
}

fn watched(stop_at: Option<usize>) -> (SearchOutcome, Vec<PolishIteration>) {
    let flag = Arc::new(AtomicBool::new(false));
    let watch = Watch {
        seen: Arc::default(),
        flag: flag.clone(),
        stop_at,
    };
    let outcome = Executor::new(ga(), Decay::new())
        .interrupt(flag)
        .observe(watch.clone(), ObserverMode::Every(100))
        .then_polish(Polish::new(PolishSettings::default(), genes()), 3)
        .run()
        .unwrap();
    let seen = watch.seen.lock().unwrap().clone();
    (outcome, seen)
}

#[test]
fn the_executor_polishes_after_the_ga_and_tells_its_observers() {
    let (outcome, seen) = watched(None);
    assert_ne!(outcome.termination, TerminationReason::Interrupted);
    let p = outcome.polish.as_ref().expect("a polish was configured");
    assert_eq!(p.stop, PolishStop::Converged);
    assert!(
        p.best_cost < outcome.best_cost,
        "the polish improves on the GA"
    );
    // One observer call per iteration, in order, with the outcome's own history.
    assert_eq!(seen.len(), p.iterations);
    assert_eq!(seen, p.history);
    assert!(seen.windows(2).all(|w| w[1].best_cost <= w[0].best_cost));

    // The same polish run by hand from the GA's outcome gives the same bits.
    let mut alone = Decay::new();
    let starts = distinct_starts(&genes(), &outcome, 3);
    let by_hand = Polish::new(PolishSettings::default(), genes())
        .run(&mut alone, &starts)
        .unwrap();
    assert_eq!(by_hand.best_cost.to_bits(), p.best_cost.to_bits());
    assert_eq!(by_hand.best_genome, p.best_genome);
}

#[test]
fn an_interrupt_during_the_polish_is_the_search_termination() {
    let (outcome, seen) = watched(Some(1));
    assert_eq!(outcome.termination, TerminationReason::Interrupted);
    let p = outcome.polish.as_ref().expect("the polish started");
    assert_eq!(p.stop, PolishStop::Interrupted);
    assert_eq!(
        seen.len(),
        1,
        "the polish stops after the running iteration"
    );
}

#[test]
fn an_interrupted_ga_is_not_polished() {
    let flag = Arc::new(AtomicBool::new(true));
    let outcome = Executor::new(ga(), Decay::new())
        .interrupt(flag)
        .then_polish(Polish::new(PolishSettings::default(), genes()), 3)
        .run()
        .unwrap();
    assert_eq!(outcome.termination, TerminationReason::Interrupted);
    assert!(outcome.polish.is_none());
}
