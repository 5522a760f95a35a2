//! CMA-ES under the one executor: it finds the optimum of correlated valleys
//! in fewer evaluations than the GA, never asks for a point outside the
//! bounds, gives the same bits for the same seed, resumes from a checkpoint
//! to the same bits, and restarts with a growing population when asked to.

mod common;

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use common::{InterruptAt, assert_same_result};
use rigfit::base::Scale;
use rigfit::search::{
    Executor, Fingerprint, FnCost, GeneSpec, GeneticAlgorithm, Method, ObserverMode, SearchOutcome,
    SearchSettings, TerminationReason,
};

fn settings(method: &str, population: usize, generations: usize, seed: u64) -> SearchSettings {
    serde_json::from_value(serde_json::json!({
        "method": method, "population": population, "generations": generations, "seed": seed
    }))
    .unwrap()
}

fn linear(n: usize, lo: f64, hi: f64) -> Vec<GeneSpec> {
    (0..n)
        .map(|i| GeneSpec::new(format!("x{i}"), lo, hi, Scale::Linear))
        .collect()
}

/// A rotated, ill-conditioned ellipsoid (condition 10⁴) with its minimum 0
/// at 0.3 in every coordinate: the correlated valley a GA samples blindly.
fn rotated_ellipsoid(x: &[f64]) -> f64 {
    let n = x.len();
    let d: Vec<f64> = x.iter().map(|v| v - 0.3).collect();
    (0..n)
        .map(|i| {
            // Coordinate i of a fixed rotation: sums of neighbours.
            let r = (d[i] + d[(i + 1) % n]) / 2f64.sqrt();
            1e4f64.powf(i as f64 / (n - 1) as f64) * r * r
        })
        .sum()
}

fn run(s: SearchSettings, genes: Vec<GeneSpec>) -> SearchOutcome {
    let solver = s.method.solver(&s, genes).unwrap();
    Executor::boxed(solver, FnCost(rotated_ellipsoid))
        .run()
        .unwrap()
}

#[test]
fn cmaes_reaches_a_correlated_valley_in_fewer_evaluations_than_the_ga() {
    let target = 1e-6;
    let evals = |method: &str, seed: u64| {
        let mut s = settings(method, 40, 2_000, seed);
        s.target_fitness = Some(target);
        let out = run(s, linear(6, -1.0, 1.0));
        (out.best_cost, out.evaluations)
    };
    let mut ratios = Vec::new();
    for seed in 1..=3 {
        let (cma_cost, cma) = evals("cmaes", seed);
        let (ga_cost, ga) = evals("ga", seed);
        assert!(cma_cost <= target, "CMA-ES seed {seed}: {cma_cost:e}");
        // The GA may not reach the target at all in its budget; count its
        // budget then.
        let _ = ga_cost;
        ratios.push(cma as f64 / ga as f64);
    }
    ratios.sort_by(f64::total_cmp);
    assert!(ratios[1] < 0.5, "CMA-ES ÷ GA evaluations: {ratios:?}");
}

#[test]
fn cmaes_never_asks_outside_the_bounds_and_finds_an_optimum_on_one() {
    let genes = vec![
        GeneSpec::new("a", 0.0, 1.0, Scale::Linear),
        GeneSpec::new("k", 1e-2, 1e2, Scale::Log),
    ];
    let mut s = settings("cmaes", 12, 150, 5);
    s.cmaes.sigma0 = 1.0;
    let solver = s.method.solver(&s, genes).unwrap();
    // The optimum lies beyond the upper bound of `a`: the search must pile
    // up on the bound, never cross it.
    let cost = FnCost(|g: &[f64]| {
        assert!((0.0..=1.0).contains(&g[0]), "a = {}", g[0]);
        assert!((1e-2..=1e2).contains(&g[1]), "k = {}", g[1]);
        (g[0] - 1.5).powi(2) + g[1].ln().powi(2)
    });
    let out = Executor::boxed(solver, cost).run().unwrap();
    assert!(
        (out.best_genome[0] - 1.0).abs() < 1e-6,
        "{:?}",
        out.best_genome
    );
    assert!(
        out.best_genome[1].ln().abs() < 1e-4,
        "{:?}",
        out.best_genome
    );
}

type Ellipsoid = FnCost<fn(&[f64]) -> f64>;

fn cmaes_executor(seed: u64) -> Executor<Ellipsoid> {
    let s = settings("cmaes", 16, 60, seed);
    let solver = s.method.solver(&s, linear(4, -2.0, 2.0)).unwrap();
    Executor::boxed(solver, FnCost(rotated_ellipsoid as fn(&[f64]) -> f64))
        .fingerprint(Fingerprint::new().with("test", "cmaes"))
}

#[test]
fn the_same_seed_gives_the_same_bits_and_another_seed_does_not() {
    let a = cmaes_executor(7).run().unwrap();
    let b = cmaes_executor(7).run().unwrap();
    assert_same_result(&a, &b);
    assert_eq!(a.method, Method::Cmaes);
    let c = cmaes_executor(8).run().unwrap();
    assert_ne!(a.best_cost.to_bits(), c.best_cost.to_bits());
}

#[test]
fn an_interrupted_search_resumes_to_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let straight = cmaes_executor(3).run().unwrap();
    for at in [0, 9, 31] {
        let flag = Arc::new(AtomicBool::new(false));
        let stopped = cmaes_executor(3)
            .checkpoint_to(&path)
            .interrupt(flag.clone())
            .observe(InterruptAt { at, flag }, ObserverMode::Always)
            .run()
            .unwrap();
        assert_eq!(stopped.termination, TerminationReason::Interrupted);
        let resumed = cmaes_executor(3)
            .checkpoint_to(&path)
            .resume_from(&path)
            .unwrap()
            .run()
            .unwrap();
        assert_same_result(&straight, &resumed);
        assert_eq!(
            straight.method_summary, resumed.method_summary,
            "the covariance resumes to the same bits"
        );
    }
}

#[test]
fn a_ga_checkpoint_is_refused_by_cmaes_naming_the_method() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let s = settings("ga", 16, 5, 3);
    let ga = GeneticAlgorithm::new(s, linear(4, -2.0, 2.0)).unwrap();
    Executor::new(ga, FnCost(rotated_ellipsoid as fn(&[f64]) -> f64))
        .fingerprint(Fingerprint::new().with("test", "cmaes"))
        .checkpoint_to(&path)
        .run()
        .unwrap();
    let err = cmaes_executor(3)
        .resume_from(&path)
        .unwrap()
        .run()
        .unwrap_err()
        .to_string();
    assert!(err.contains("search.method: ga → cmaes"), "{err}");
}

/// Rastrigin: many local minima, the global one 0 at the origin.
fn rastrigin(x: &[f64]) -> f64 {
    10.0 * x.len() as f64
        + x.iter()
            .map(|v| v * v - 10.0 * (std::f64::consts::TAU * v).cos())
            .sum::<f64>()
}

#[test]
fn restarts_grow_the_population_and_the_search_ends_converged() {
    let mut s = settings("cmaes", 8, 5_000, 2);
    s.cmaes.restarts = 3;
    s.cmaes.sigma0 = 0.2;
    let solver = s.method.solver(&s, linear(3, -5.12, 5.12)).unwrap();
    let out = Executor::boxed(solver, FnCost(rastrigin)).run().unwrap();
    assert_eq!(out.termination, TerminationReason::Converged);
    let sizes: Vec<usize> = out.history.iter().map(|h| h.evaluated).collect();
    for want in [8, 16, 32, 64] {
        assert!(sizes.contains(&want), "batch sizes {sizes:?}");
    }
    assert!(sizes.windows(2).all(|w| w[1] >= w[0]), "{sizes:?}");
    let summary = out.method_summary.expect("CMA-ES reports its covariance");
    assert_eq!(summary["restarts"], 3);
    assert_eq!(summary["run_stops"].as_array().unwrap().len(), 4);
    assert_eq!(summary["correlation"][0][0], 1.0);
}

#[test]
fn the_largest_batch_is_the_last_restart_s() {
    let mut s = settings("cmaes", 100, 10, 1);
    assert_eq!(Method::Cmaes.largest_batch(&s), 100);
    s.cmaes.restarts = 3;
    assert_eq!(Method::Cmaes.largest_batch(&s), 800);
    s.cmaes.population_increase = 1.5;
    assert_eq!(Method::Cmaes.largest_batch(&s), 338);
    assert_eq!(Method::Ga.largest_batch(&s), 100);
}
