//! Proves the search is a pure function of its seed and costs: the same seed
//! gives a bit-identical outcome, a different seed a different one.

use rigfit::base::Scale;
use rigfit::search::{Executor, FnCost, GeneSpec, GeneticAlgorithm, InitKind, SearchOutcome};

mod common;
use common::{assert_same_result, rosenbrock, settings};

fn run(seed: u64, init: InitKind) -> SearchOutcome {
    let genes = vec![
        GeneSpec::new("a", 1e-2, 1e2, Scale::Log),
        GeneSpec::new("b", -2.0, 2.0, Scale::Linear).with_init(0.5),
    ];
    let mut s = settings(24, 30, seed);
    s.ga.init = init;
    let ga = GeneticAlgorithm::new(s, genes).unwrap();
    Executor::new(ga, FnCost(rosenbrock)).run().unwrap()
}

#[test]
fn same_seed_gives_bit_identical_outcome() {
    for init in [InitKind::Lhs, InitKind::Uniform] {
        assert_same_result(&run(42, init), &run(42, init));
    }
}

#[test]
fn different_seed_gives_different_outcome() {
    let (a, b) = (run(1, InitKind::Lhs), run(2, InitKind::Lhs));
    assert_ne!(a.population, b.population);
    assert_ne!(
        a.history[0].median_cost.to_bits(),
        b.history[0].median_cost.to_bits()
    );
}

#[test]
fn init_kinds_differ() {
    let (a, b) = (run(5, InitKind::Lhs), run(5, InitKind::Uniform));
    assert_ne!(a.population, b.population);
}
