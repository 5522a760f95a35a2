//! Proves that no GA operator ever leaves a gene's bounds, for any scale,
//! bounds and distribution index.

use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rigfit::base::Scale;
use rigfit::search::operators::{latin_hypercube, mutate, polynomial_mutation, sbx_pair, uniform};
use rigfit::search::{GeneSpec, GeneticAlgorithm, genes::genome_values};

mod common;

fn gene_strategy() -> impl Strategy<Value = GeneSpec> {
    (
        any::<bool>(),
        -1.0e6..1.0e6f64,
        0.0..1.0e6f64,
        1.0e-12..1.0e3f64,
        0.0..12.0f64,
    )
        .prop_map(|(log, lo, width, pos_lo, decades)| {
            if log {
                GeneSpec::new("g", pos_lo, pos_lo * 10f64.powf(decades), Scale::Log)
            } else {
                GeneSpec::new("g", lo, lo + width, Scale::Linear)
            }
        })
}

proptest! {
    #[test]
    fn sbx_children_stay_inside(
        lo in -1.0e6..1.0e6f64, width in 0.0..1.0e6f64,
        a in 0.0..=1.0f64, b in 0.0..=1.0f64, eta in 0.0..200.0f64, seed in any::<u64>(),
    ) {
        let hi = lo + width;
        let (y1, y2) = (lo + a * width, lo + b * width);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..20 {
            let (c1, c2) = sbx_pair(&mut rng, y1.min(hi), y2.min(hi), lo, hi, eta);
            prop_assert!(lo <= c1 && c1 <= hi && lo <= c2 && c2 <= hi, "{c1} {c2} not in [{lo}, {hi}]");
        }
    }

    #[test]
    fn polynomial_mutation_stays_inside(
        lo in -1.0e6..1.0e6f64, width in 0.0..1.0e6f64,
        a in 0.0..=1.0f64, eta in 0.0..200.0f64, seed in any::<u64>(),
    ) {
        let hi = lo + width;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..20 {
            let c = polynomial_mutation(&mut rng, (lo + a * width).min(hi), lo, hi, eta);
            prop_assert!(lo <= c && c <= hi);
        }
        let mut g = vec![lo, hi];
        mutate(&mut rng, &mut g, &[(lo, hi), (lo, hi)], eta, 1.0);
        prop_assert!(g.iter().all(|&c| lo <= c && c <= hi));
    }

    #[test]
    fn initial_sampling_stays_inside(lo in -1.0e3..1.0e3f64, width in 0.0..1.0e3f64, n in 1usize..50, seed in any::<u64>()) {
        let b = [(lo, lo + width)];
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for g in latin_hypercube(&mut rng, n, &b).iter().chain(&uniform(&mut rng, n, &b)) {
            prop_assert!(b[0].0 <= g[0] && g[0] <= b[0].1);
        }
    }

    #[test]
    fn whole_generations_stay_inside_in_value_space(
        genes in prop::collection::vec(gene_strategy(), 1..5),
        cx_eta in 0.0..100.0f64, mut_eta in 0.0..100.0f64, seed in any::<u64>(),
    ) {
        let mut s = common::settings(12, 10, seed);
        s.ga.crossover.eta = cx_eta;
        s.ga.mutation.eta = mut_eta;
        s.ga.mutation.probability = Some(1.0);
        let ga = GeneticAlgorithm::new(s, genes.clone()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut pop = ga.init(&mut rng);
        for round in 0..5 {
            for g in &pop {
                for (x, &(lo, hi)) in g.iter().zip(ga.bounds()) {
                    prop_assert!(lo <= *x && *x <= hi, "scaled {x} not in [{lo}, {hi}]");
                }
                for (v, spec) in genome_values(&genes, g).iter().zip(&genes) {
                    prop_assert!(spec.lower <= *v && *v <= spec.upper, "value {v} outside {spec:?}");
                }
            }
            let costs: Vec<f64> = (0..pop.len()).map(|i| ((i * 7 + round) % 5) as f64).collect();
            let off = ga.next_generation(&mut rng, &pop, &costs);
            pop = off.elites.iter().map(|&i| pop[i].clone()).chain(off.children).collect();
        }
    }
}
