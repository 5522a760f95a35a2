//! Proves the GA finds the minimum of analytic cost functions in linear and log
//! scales, and stops for the right reason on every stopping rule.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use rigfit::base::Scale;
use rigfit::search::{
    Executor, FnCost, GeneSpec, GeneticAlgorithm, ObserverMode, TerminationReason,
};

mod common;
use common::{InterruptAt, rosenbrock, settings, sphere};

fn linear(n: usize, lo: f64, hi: f64) -> Vec<GeneSpec> {
    (0..n)
        .map(|i| GeneSpec::new(format!("x{i}"), lo, hi, Scale::Linear))
        .collect()
}

#[test]
fn sphere_linear_converges() {
    let ga = GeneticAlgorithm::new(settings(60, 150, 1), linear(4, -5.0, 5.0)).unwrap();
    let out = Executor::new(ga, FnCost(sphere(&[1.0, -2.0, 0.5, 3.0])))
        .run()
        .unwrap();
    assert_eq!(out.termination, TerminationReason::MaxGenerations);
    assert!(out.best_cost < 1e-4, "best {}", out.best_cost);
    assert_eq!(out.generations, 150);
    assert_eq!(out.history.len(), 150);
    // Elitism: the best never gets worse.
    assert!(
        out.history
            .windows(2)
            .all(|w| w[1].best_cost <= w[0].best_cost)
    );
}

#[test]
fn rosenbrock_linear_converges() {
    let ga = GeneticAlgorithm::new(settings(80, 300, 2), linear(2, -2.0, 2.0)).unwrap();
    let out = Executor::new(ga, FnCost(rosenbrock)).run().unwrap();
    assert!(out.best_cost < 1e-3, "best {}", out.best_cost);
    assert!((out.best_genome[0] - 1.0).abs() < 0.05 && (out.best_genome[1] - 1.0).abs() < 0.1);
}

#[test]
fn rosenbrock_log_scale_converges_across_decades() {
    // Minimum at (1, 1) inside ranges spanning four decades.
    let genes = vec![
        GeneSpec::new("a", 1e-2, 1e2, Scale::Log),
        GeneSpec::new("b", 1e-2, 1e2, Scale::Log),
    ];
    let ga = GeneticAlgorithm::new(settings(100, 500, 3), genes).unwrap();
    let out = Executor::new(ga, FnCost(rosenbrock)).run().unwrap();
    assert!(out.best_cost < 1e-2, "best {}", out.best_cost);
    assert!(
        (out.best_genome[0] - 1.0).abs() < 0.1,
        "{:?}",
        out.best_genome
    );
}

#[test]
fn log_sphere_finds_parameters_decades_apart() {
    // Stiffness-like, damping-like and unit-order parameters.
    let targets = [3.0e-3, 4.0e4, 1.0];
    let genes = vec![
        GeneSpec::new("c", 1e-6, 1.0, Scale::Log),
        GeneSpec::new("k", 1e2, 1e8, Scale::Log),
        GeneSpec::new("r", 1e-2, 1e2, Scale::Log),
    ];
    let ga = GeneticAlgorithm::new(settings(60, 200, 10), genes).unwrap();
    let cost = move |g: &[f64]| -> f64 {
        g.iter()
            .zip(&targets)
            .map(|(x, t)| (x / t).ln().powi(2))
            .sum()
    };
    let out = Executor::new(ga, FnCost(cost)).run().unwrap();
    for (x, t) in out.best_genome.iter().zip(&targets) {
        assert!((x / t - 1.0).abs() < 1e-2, "{x} vs {t}");
    }
}

#[test]
fn elite_spread_separates_pinned_from_free_parameters() {
    let genes = vec![
        GeneSpec::new("pinned", 1e-3, 1e3, Scale::Log),
        GeneSpec::new("free", 1e-3, 1e3, Scale::Log),
    ];
    let ga = GeneticAlgorithm::new(settings(60, 100, 14), genes).unwrap();
    let out = Executor::new(ga, FnCost(|g: &[f64]| g[0].ln().powi(2)))
        .run()
        .unwrap();
    let (pinned, free) = (&out.elite_spread[0], &out.elite_spread[1]);
    assert_eq!(
        (pinned.name.as_str(), free.name.as_str()),
        ("pinned", "free")
    );
    assert!(pinned.relative_width < 0.05, "{pinned:?}");
    assert!(
        free.relative_width > 4.0 * pinned.relative_width,
        "{free:?}"
    );
    assert!(pinned.min <= 1.0 + 1e-2 && pinned.max >= 1.0 - 1e-2);
}

#[test]
fn seeded_init_is_evaluated_first() {
    let genes = vec![
        GeneSpec::new("a", 1e-2, 1e2, Scale::Log).with_init(1.0),
        GeneSpec::new("b", -5.0, 5.0, Scale::Linear),
    ];
    let mut s = settings(10, 1, 4);
    s.ga.elitism = 1;
    let ga = GeneticAlgorithm::new(s, genes).unwrap();
    // Cost is exactly 0 at the seed candidate (a = 1, b = mid-range 0).
    let out = Executor::new(ga, FnCost(|g: &[f64]| g[0].ln().abs() + g[1].abs()))
        .run()
        .unwrap();
    assert!(out.best_cost < 1e-15, "{}", out.best_cost);
}

#[test]
fn target_fitness_stops_early() {
    let mut s = settings(40, 500, 5);
    s.target_fitness = Some(1e-2);
    let ga = GeneticAlgorithm::new(s, linear(2, -5.0, 5.0)).unwrap();
    let out = Executor::new(ga, FnCost(sphere(&[0.0, 0.0])))
        .run()
        .unwrap();
    assert_eq!(out.termination, TerminationReason::TargetReached);
    assert!(out.best_cost <= 1e-2 && out.generations < 500);
}

#[test]
fn stall_stops_after_the_allowed_generations() {
    let mut s = settings(10, 500, 6);
    s.stall_generations = Some(7);
    let ga = GeneticAlgorithm::new(s, linear(2, -1.0, 1.0)).unwrap();
    let out = Executor::new(ga, FnCost(|_: &[f64]| 0.5)).run().unwrap();
    assert_eq!(out.termination, TerminationReason::Stalled);
    // Generation 0 sets the best, then 7 generations without improvement.
    assert_eq!(out.generations, 8);
}

#[test]
fn wall_time_limit_stops() {
    let mut s = settings(8, 10_000, 7);
    s.max_time_s = Some(0.2);
    let ga = GeneticAlgorithm::new(s, linear(2, -1.0, 1.0)).unwrap();
    let slow = |x: &[f64]| {
        std::thread::sleep(std::time::Duration::from_millis(2));
        x[0] * x[0]
    };
    let out = Executor::new(ga, FnCost(slow)).run().unwrap();
    assert_eq!(out.termination, TerminationReason::Timeout);
    assert!(out.wall_time_s >= 0.2 && out.generations < 10_000);
    assert!(out.history.last().unwrap().evals_per_s > 0.0);
}

#[test]
fn interrupt_flag_stops_after_the_running_generation() {
    let flag = Arc::new(AtomicBool::new(false));
    let ga = GeneticAlgorithm::new(settings(10, 100, 8), linear(2, -1.0, 1.0)).unwrap();
    let out = Executor::new(ga, FnCost(sphere(&[0.0, 0.0])))
        .interrupt(flag.clone())
        .observe(InterruptAt { at: 3, flag }, ObserverMode::Always)
        .run()
        .unwrap();
    assert_eq!(out.termination, TerminationReason::Interrupted);
    assert_eq!(out.generations, 4);
    assert_eq!(out.termination.to_string(), "interrupted");
}

#[test]
fn evaluations_count_children_only() {
    let mut s = settings(10, 5, 9);
    s.ga.elitism = 2;
    let ga = GeneticAlgorithm::new(s, linear(1, 0.0, 1.0)).unwrap();
    let out = Executor::new(ga, FnCost(|x: &[f64]| x[0])).run().unwrap();
    assert_eq!(out.evaluations, 10 + 4 * 8);
    assert_eq!(out.population.len(), 10);
    assert!(out.costs.windows(2).all(|w| w[0] <= w[1]));
}
