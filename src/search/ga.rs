//! The genetic algorithm as pure state transitions: an initial population, and
//! the next population from the current one and its costs. No I/O, no clock; all
//! randomness from the RNG passed in (argmin's `init` / `next_iter` split).

use rand::Rng;

use super::genes::{GeneSpec, clamp_into};
use super::operators::{latin_hypercube, mutate, sbx, tournament, uniform};
use super::report::ranking;
use super::{GaSettings, InitKind, SearchError};

/// A real-coded GA over a fixed set of genes.
///
/// Genomes here are in scale space (see [`crate::search::genes`]).
#[derive(Debug, Clone)]
pub struct GeneticAlgorithm {
    settings: GaSettings,
    genes: Vec<GeneSpec>,
    bounds: Vec<(f64, f64)>,
    mutation_probability: f64,
}

/// The next generation before evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Offspring {
    /// Indices (into the previous population) of the elites carried over
    /// unchanged, best first; their costs are reused.
    pub elites: Vec<usize>,
    /// New genomes (scale space) that need evaluation.
    pub children: Vec<Vec<f64>>,
}

impl GeneticAlgorithm {
    /// Checks the settings and genes the algorithm depends on.
    pub fn new(settings: GaSettings, genes: Vec<GeneSpec>) -> Result<Self, SearchError> {
        let invalid = |field, reason: String| Err(SearchError::InvalidSettings { field, reason });
        if genes.is_empty() {
            return invalid("genes", "no free parameters to search".into());
        }
        for g in &genes {
            g.validate()?;
        }
        let s = &settings;
        if s.population < 2 {
            return invalid(
                "population",
                format!("need at least 2, found {}", s.population),
            );
        }
        if s.generations < 1 {
            return invalid("generations", "need at least 1".into());
        }
        if s.tournament < 1 {
            return invalid("tournament", "need at least 1".into());
        }
        if s.elitism >= s.population {
            return invalid(
                "elitism",
                format!(
                    "{} elites leave no room in a population of {}",
                    s.elitism, s.population
                ),
            );
        }
        let prob_ok = |p: f64| (0.0..=1.0).contains(&p);
        if !prob_ok(s.crossover.probability) {
            return invalid(
                "crossover.probability",
                format!("{} is not in [0, 1]", s.crossover.probability),
            );
        }
        if !(s.crossover.eta >= 0.0 && s.crossover.eta.is_finite()) {
            return invalid(
                "crossover.eta",
                format!("{} is not a finite value ≥ 0", s.crossover.eta),
            );
        }
        if !(s.mutation.eta >= 0.0 && s.mutation.eta.is_finite()) {
            return invalid(
                "mutation.eta",
                format!("{} is not a finite value ≥ 0", s.mutation.eta),
            );
        }
        let mutation_probability = s.mutation.probability.unwrap_or(1.0 / genes.len() as f64);
        if !prob_ok(mutation_probability) {
            return invalid(
                "mutation.probability",
                format!("{mutation_probability} is not in [0, 1]"),
            );
        }
        let bounds = genes.iter().map(GeneSpec::scaled_bounds).collect();
        Ok(Self {
            settings,
            genes,
            bounds,
            mutation_probability,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &GaSettings {
        &self.settings
    }

    /// The genes, in genome order.
    pub fn genes(&self) -> &[GeneSpec] {
        &self.genes
    }

    /// Scale-space bounds per gene.
    pub fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    /// The first population (scale space), by Latin hypercube or uniformly.
    ///
    /// When at least one gene has an `init` value, candidate 0 is replaced by the
    /// *seed candidate*: every gene at its `init`, genes without one at the
    /// middle of their range in scale space (the geometric mean for log genes).
    /// The rest of the population is drawn as usual, so the draw order (and the
    /// RNG state afterwards) does not depend on the starting guesses.
    pub fn init<R: Rng + ?Sized>(&self, rng: &mut R) -> Vec<Vec<f64>> {
        let n = self.settings.population;
        let mut pop = match self.settings.init {
            InitKind::Lhs => latin_hypercube(rng, n, &self.bounds),
            InitKind::Uniform => uniform(rng, n, &self.bounds),
        };
        if self.genes.iter().any(|g| g.init.is_some()) {
            pop[0] = self.seed_candidate();
        }
        pop
    }

    /// The candidate built from the genes' starting guesses (scale space).
    pub fn seed_candidate(&self) -> Vec<f64> {
        self.genes
            .iter()
            .zip(&self.bounds)
            .map(|(g, &(lo, hi))| match g.init {
                Some(v) => clamp_into(g.to_scaled(v), lo, hi),
                None => 0.5 * (lo + hi),
            })
            .collect()
    }

    /// Breeds the next generation from `population` (scale space) and its costs.
    ///
    /// The best `elitism` candidates are carried over; the remaining slots are
    /// filled pairwise: two tournament winners are crossed by SBX with the
    /// crossover probability, and both children are mutated.
    pub fn next_generation<R: Rng + ?Sized>(
        &self,
        rng: &mut R,
        population: &[Vec<f64>],
        costs: &[f64],
    ) -> Offspring {
        let order = ranking(costs);
        let mut rank = vec![0; order.len()];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r;
        }
        let s = &self.settings;
        let elites: Vec<usize> = order[..s.elitism].to_vec();
        let needed = s.population - s.elitism;
        let mut children = Vec::with_capacity(needed + 1);
        while children.len() < needed {
            let p1 = &population[tournament(rng, &rank, s.tournament)];
            let p2 = &population[tournament(rng, &rank, s.tournament)];
            let (mut c1, mut c2) = if rng.random::<f64>() < s.crossover.probability {
                sbx(rng, p1, p2, &self.bounds, s.crossover.eta)
            } else {
                (p1.clone(), p2.clone())
            };
            let (eta, pm) = (s.mutation.eta, self.mutation_probability);
            mutate(rng, &mut c1, &self.bounds, eta, pm);
            mutate(rng, &mut c2, &self.bounds, eta, pm);
            children.push(c1);
            children.push(c2);
        }
        children.truncate(needed);
        Offspring { elites, children }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::Scale;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn settings() -> GaSettings {
        serde_json::from_str(r#"{"population": 10, "generations": 5}"#).unwrap()
    }

    fn genes() -> Vec<GeneSpec> {
        vec![GeneSpec::new("a", 0.0, 1.0, Scale::Linear)]
    }

    #[test]
    fn bad_settings_name_the_field() {
        let mut s = settings();
        s.elitism = 10;
        let e = GeneticAlgorithm::new(s, genes()).unwrap_err();
        assert!(matches!(
            e,
            SearchError::InvalidSettings {
                field: "elitism",
                ..
            }
        ));
        let mut s = settings();
        s.crossover.probability = 1.5;
        let e = GeneticAlgorithm::new(s, genes()).unwrap_err();
        assert!(e.to_string().contains("crossover.probability"));
        assert!(GeneticAlgorithm::new(settings(), vec![]).is_err());
    }

    #[test]
    fn elites_are_the_best_and_population_size_is_kept() {
        let ga = GeneticAlgorithm::new(settings(), genes()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let pop = ga.init(&mut rng);
        let costs: Vec<f64> = (0..10)
            .map(|i| [5.0, f64::NAN, 1.0, 3.0, 0.5][i % 5])
            .collect();
        let off = ga.next_generation(&mut rng, &pop, &costs);
        assert_eq!(off.elites, [4, 9]);
        assert_eq!(off.elites.len() + off.children.len(), 10);
    }

    #[test]
    fn seed_candidate_uses_inits_and_mid_range() {
        let genes = vec![
            GeneSpec::new("a", 1.0, 100.0, Scale::Log),
            GeneSpec::new("b", 0.0, 1.0, Scale::Linear).with_init(0.25),
        ];
        let ga = GeneticAlgorithm::new(settings(), genes).unwrap();
        let pop = ga.init(&mut ChaCha8Rng::seed_from_u64(0));
        assert!((pop[0][0].exp() - 10.0).abs() < 1e-12);
        assert_eq!(pop[0][1], 0.25);
    }
}
