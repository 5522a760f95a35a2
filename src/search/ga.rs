//! The genetic algorithm as pure state transitions: an initial population, and
//! the next population from the current one and its costs. No I/O, no clock; all
//! randomness from the RNG passed in. As a [`Solver`], the first batch asked is
//! the initial population and each later batch the children of the next
//! generation; the elites keep their costs.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::checkpoint::Fingerprint;
use super::genes::{GeneSpec, clamp_into};
use super::methods::Method;
use super::operators::{latin_hypercube, mutate, sbx, tournament, uniform};
use super::report::ranking;
use super::solver::Solver;
use super::{InitKind, SearchError, SearchSettings};

/// A real-coded GA over a fixed set of genes.
///
/// Genomes here are in scale space (see [`crate::search::genes`]).
#[derive(Debug, Clone)]
pub struct GeneticAlgorithm {
    settings: SearchSettings,
    genes: Vec<GeneSpec>,
    bounds: Vec<(f64, f64)>,
    mutation_probability: f64,
    /// The current population and its costs (empty before the first tell).
    now: Population,
    /// The batch in hand: children asked for, and the elites (indices into
    /// `now`) that join them.
    asked: Offspring,
}

/// A population (scale space) with its costs: the GA's state between
/// generations.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
struct Population {
    population: Vec<Vec<f64>>,
    costs: Vec<f64>,
}

/// The next generation before evaluation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Offspring {
    /// Indices (into the previous population) of the elites carried over
    /// unchanged, best first; their costs are reused.
    pub elites: Vec<usize>,
    /// New genomes (scale space) that need evaluation.
    pub children: Vec<Vec<f64>>,
}

impl GeneticAlgorithm {
    /// Checks the settings and genes the algorithm depends on.
    pub fn new(settings: SearchSettings, genes: Vec<GeneSpec>) -> Result<Self, SearchError> {
        let invalid = |field, reason: String| Err(SearchError::InvalidSettings { field, reason });
        if genes.is_empty() {
            return invalid("genes", "no free parameters to search".into());
        }
        for g in &genes {
            g.validate()?;
        }
        let (s, ga) = (&settings, &settings.ga);
        if s.population < 2 {
            return invalid(
                "population",
                format!("need at least 2, found {}", s.population),
            );
        }
        if s.generations < 1 {
            return invalid("generations", "need at least 1".into());
        }
        if ga.tournament < 1 {
            return invalid("tournament", "need at least 1".into());
        }
        if ga.elitism >= s.population {
            return invalid(
                "elitism",
                format!(
                    "{} elites leave no room in a population of {}",
                    ga.elitism, s.population
                ),
            );
        }
        let prob_ok = |p: f64| (0.0..=1.0).contains(&p);
        if !prob_ok(ga.crossover.probability) {
            return invalid(
                "crossover.probability",
                format!("{} is not in [0, 1]", ga.crossover.probability),
            );
        }
        if !(ga.crossover.eta >= 0.0 && ga.crossover.eta.is_finite()) {
            return invalid(
                "crossover.eta",
                format!("{} is not a finite value ≥ 0", ga.crossover.eta),
            );
        }
        if !(ga.mutation.eta >= 0.0 && ga.mutation.eta.is_finite()) {
            return invalid(
                "mutation.eta",
                format!("{} is not a finite value ≥ 0", ga.mutation.eta),
            );
        }
        let mutation_probability = ga.mutation.probability.unwrap_or(1.0 / genes.len() as f64);
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
            now: Population::default(),
            asked: Offspring::default(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &SearchSettings {
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
        let mut pop = match self.settings.ga.init {
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
        let s = &self.settings.ga;
        let elites: Vec<usize> = order[..s.elitism].to_vec();
        let needed = self.settings.population - s.elitism;
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

impl Solver for GeneticAlgorithm {
    fn method(&self) -> Method {
        Method::Ga
    }

    fn settings(&self) -> &SearchSettings {
        &self.settings
    }

    fn genes(&self) -> &[GeneSpec] {
        &self.genes
    }

    fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    fn fingerprint(&self, fp: &mut Fingerprint) {
        let s = &self.settings.ga;
        fp.insert("search.tournament".into(), s.tournament.to_string());
        fp.insert_json("search.crossover", &s.crossover);
        fp.insert_json("search.mutation", &s.mutation);
        fp.insert("search.elitism".into(), s.elitism.to_string());
        fp.insert_json("search.init", &s.init);
    }

    fn ask(&mut self, rng: &mut ChaCha8Rng) -> &[Vec<f64>] {
        self.asked = if self.now.population.is_empty() {
            Offspring {
                elites: Vec::new(),
                children: self.init(rng),
            }
        } else {
            self.next_generation(rng, &self.now.population, &self.now.costs)
        };
        &self.asked.children
    }

    fn tell(&mut self, _rng: &mut ChaCha8Rng, costs: &[f64]) {
        let asked = std::mem::take(&mut self.asked);
        let mut next = Population {
            population: Vec::with_capacity(self.settings.population),
            costs: Vec::with_capacity(self.settings.population),
        };
        for &i in &asked.elites {
            next.population.push(self.now.population[i].clone());
            next.costs.push(self.now.costs[i]);
        }
        next.population.extend(asked.children);
        next.costs.extend_from_slice(costs);
        self.now = next;
    }

    fn population(&self) -> (&[Vec<f64>], &[f64]) {
        (&self.now.population, &self.now.costs)
    }

    fn immigrate(&mut self, genomes: &[Vec<f64>], costs: &[f64]) -> bool {
        let n = genomes.len().min(costs.len());
        if self.now.population.len() <= n {
            return n == 0;
        }
        // The worst go, the last-ranked first; ties keep ranking's order.
        let order = ranking(&self.now.costs);
        for (k, &slot) in order.iter().rev().take(n).enumerate() {
            self.now.population[slot] = genomes[k].clone();
            self.now.costs[slot] = costs[k];
        }
        true
    }

    fn state(&self) -> Value {
        serde_json::to_value(&self.now).unwrap_or(Value::Null)
    }

    fn restore(&mut self, state: Value) -> Result<(), String> {
        let now: Population = serde_json::from_value(state).map_err(|e| e.to_string())?;
        let (n, g) = (self.settings.population, self.genes.len());
        let fits = now.population.len() == n
            && now.costs.len() == n
            && now.population.iter().all(|x| x.len() == g);
        if !fits {
            return Err(format!(
                "state does not hold {n} genomes of {g} genes with costs"
            ));
        }
        self.now = now;
        self.asked = Offspring::default();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::Scale;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn settings() -> SearchSettings {
        serde_json::from_str(r#"{"population": 10, "generations": 5}"#).unwrap()
    }

    fn genes() -> Vec<GeneSpec> {
        vec![GeneSpec::new("a", 0.0, 1.0, Scale::Linear)]
    }

    #[test]
    fn bad_settings_name_the_field() {
        let mut s = settings();
        s.ga.elitism = 10;
        let e = GeneticAlgorithm::new(s, genes()).unwrap_err();
        assert!(matches!(
            e,
            SearchError::InvalidSettings {
                field: "elitism",
                ..
            }
        ));
        let mut s = settings();
        s.ga.crossover.probability = 1.5;
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
    fn migrants_replace_the_worst() {
        let mut ga = GeneticAlgorithm::new(settings(), genes()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        assert!(
            !ga.immigrate(&[vec![0.5]], &[0.0]),
            "nothing to replace yet"
        );
        let n = ga.ask(&mut rng).len();
        let costs: Vec<f64> = (0..n).map(|i| i as f64).collect();
        ga.tell(&mut rng, &costs);
        assert!(ga.immigrate(&[vec![0.25], vec![0.75]], &[-2.0, -1.0]));
        let (pop, costs) = Solver::population(&ga);
        assert_eq!(costs[n - 1], -2.0);
        assert_eq!(pop[n - 1], [0.25]);
        assert_eq!(costs[n - 2], -1.0);
        assert_eq!(
            &costs[..n - 2],
            (0..n - 2).map(|i| i as f64).collect::<Vec<_>>()
        );
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
