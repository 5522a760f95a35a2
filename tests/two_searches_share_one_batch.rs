//! Ask/tell lets several searches share one evaluation: two searches (a GA
//! and a CMA-ES, each with its own seed) are asked for their batches, both
//! batches are scored in one call of the cost, and each is told its share.
//! Each ends exactly where it ends when the executor runs it alone — what a
//! lab series or an island model needs to fill one GPU dispatch with many
//! searches.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rigfit::base::Scale;
use rigfit::search::{BatchCost, Executor, FnCost, GeneSpec, SearchSettings, genes::genome_values};

fn settings(method: &str, seed: u64) -> SearchSettings {
    serde_json::from_value(serde_json::json!({
        "method": method, "population": 12, "generations": 25, "seed": seed
    }))
    .unwrap()
}

fn genes() -> Vec<GeneSpec> {
    vec![
        GeneSpec::new("x", -2.0, 2.0, Scale::Linear),
        GeneSpec::new("k", 1e-2, 1e2, Scale::Log),
    ]
}

fn cost(g: &[f64]) -> f64 {
    (g[0] - 0.7).powi(2) + (g[1].ln() - 1.0).powi(2) + 0.3 * (g[0] - 0.7) * g[1].ln()
}

#[test]
fn two_searches_in_one_batch_end_where_each_ends_alone() {
    let plans = [settings("ga", 3), settings("cmaes", 4)];
    let alone: Vec<_> = plans
        .iter()
        .map(|s| {
            let solver = s.method.solver(s, genes()).unwrap();
            Executor::boxed(solver, FnCost(cost)).run().unwrap()
        })
        .collect();

    let mut solvers: Vec<_> = plans
        .iter()
        .map(|s| s.method.solver(s, genes()).unwrap())
        .collect();
    let mut rngs: Vec<_> = plans
        .iter()
        .map(|s| ChaCha8Rng::seed_from_u64(s.seed))
        .collect();
    let mut best = [f64::INFINITY; 2];
    let mut evaluations = [0usize; 2];
    let mut calls = 0;
    let mut scorer = FnCost(cost);
    for _generation in 0..25 {
        // Ask every search, score all candidates in one call.
        let mut joint = Vec::new();
        let mut sizes = Vec::new();
        for (solver, rng) in solvers.iter_mut().zip(&mut rngs) {
            let batch = solver.ask(rng);
            sizes.push(batch.len());
            joint.extend(batch.iter().map(|g| genome_values(&genes(), g)));
        }
        let costs = scorer.cost(&joint).unwrap().costs;
        calls += 1;
        // Tell each its share.
        let mut at = 0;
        for (i, (solver, rng)) in solvers.iter_mut().zip(&mut rngs).enumerate() {
            let share = &costs[at..at + sizes[i]];
            at += sizes[i];
            best[i] = share.iter().copied().fold(best[i], f64::min);
            evaluations[i] += share.len();
            solver.tell(rng, share);
        }
    }
    assert_eq!(calls, 25);
    for i in 0..2 {
        assert_eq!(
            best[i].to_bits(),
            alone[i].best_cost.to_bits(),
            "search {i}"
        );
        assert_eq!(evaluations[i] as u64, alone[i].evaluations, "search {i}");
    }
}
