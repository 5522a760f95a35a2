//! Search settings as written in a campaign's `"search"` object.

use serde::{Deserialize, Serialize};

use super::cmaes::CmaesSettings;
use super::islands::IslandSettings;
use super::methods::Method;
use super::profile::{ProfileSettings, deserialize_profiles};

/// How the first generation is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum InitKind {
    /// Latin hypercube over the bounds (in each gene's scale).
    #[default]
    Lhs,
    /// Uniform random over the bounds (in each gene's scale).
    Uniform,
}

/// Simulated-binary crossover settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrossoverSettings {
    /// Probability that a pair of parents is crossed (0..1).
    #[serde(default = "default_crossover_probability")]
    pub probability: f64,
    /// SBX distribution index η_c (larger: children closer to parents).
    #[serde(default = "default_crossover_eta")]
    pub eta: f64,
}

/// Polynomial mutation settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MutationSettings {
    /// Per-gene mutation probability; `null` means 1 / number of genes.
    pub probability: Option<f64>,
    /// Polynomial-mutation distribution index η_m.
    #[serde(default = "default_mutation_eta")]
    pub eta: f64,
}

/// The genetic algorithm's operators: the `"search"` keys only the GA reads
/// (written beside the executor's keys in a campaign, for files written
/// before a second method existed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GaSettings {
    /// Tournament size for parent selection (≥ 2).
    pub tournament: usize,
    /// Crossover.
    pub crossover: CrossoverSettings,
    /// Mutation.
    pub mutation: MutationSettings,
    /// Best candidates copied unchanged into the next generation.
    pub elitism: usize,
    /// Initial population.
    pub init: InitKind,
}

impl Default for GaSettings {
    fn default() -> Self {
        Self {
            tournament: default_tournament(),
            crossover: CrossoverSettings::default(),
            mutation: MutationSettings::default(),
            elitism: default_elitism(),
            init: InitKind::default(),
        }
    }
}

/// The campaign's `"search"` object: the method, what the executor reads for
/// every method (the batch size, the seed, the limits, checkpoints, the
/// polish after), and each method's own settings.
///
/// In a campaign file the GA's operators sit beside the executor's keys
/// (`"tournament": 3`), each other method's settings in an object of its
/// name (`"cmaes": {"sigma0": 0.2}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "SearchFile", into = "SearchFile")]
pub struct SearchSettings {
    /// The search method ([`Method`]; default the genetic algorithm).
    pub method: Method,
    /// Candidates per generation, the batch each evaluation scores (≥ 4).
    pub population: usize,
    /// Maximum number of generations (iterations of the method, ≥ 1).
    pub generations: usize,
    /// RNG seed; the same seed, campaign and backend give bit-identical results.
    pub seed: u64,
    /// Stop once the best joint fitness (weighted mean of 1 − R²) is at or below this.
    pub target_fitness: Option<f64>,
    /// Stop after this many generations without improvement of the best.
    pub stall_generations: Option<usize>,
    /// Stop after this many cost evaluations (candidates scored).
    pub max_evaluations: Option<u64>,
    /// Stop after this much wall time (s).
    pub max_time_s: Option<f64>,
    /// Write a checkpoint every this many generations (0: only on interrupt).
    pub checkpoint_every: usize,
    /// The local polish after the search, and the parameter uncertainty it gives.
    pub polish: PolishSettings,
    /// Profile likelihoods after the polish (`None`: none; see
    /// [`super::Profiles`]).
    pub profiles: Option<ProfileSettings>,
    /// Islands: several seeded searches trading their best candidates
    /// (`None`: one search; see [`super::islands`]).
    pub islands: Option<IslandSettings>,
    /// The genetic algorithm's operators.
    pub ga: GaSettings,
    /// CMA-ES's settings.
    pub cmaes: CmaesSettings,
}

/// [`SearchSettings`] as a campaign writes it: one flat object.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SearchFile {
    #[serde(default)]
    method: Method,
    population: usize,
    generations: usize,
    #[serde(default)]
    seed: u64,
    #[serde(default = "default_tournament")]
    tournament: usize,
    #[serde(default)]
    crossover: CrossoverSettings,
    #[serde(default)]
    mutation: MutationSettings,
    #[serde(default = "default_elitism")]
    elitism: usize,
    #[serde(default)]
    init: InitKind,
    target_fitness: Option<f64>,
    stall_generations: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    max_evaluations: Option<u64>,
    max_time_s: Option<f64>,
    #[serde(default = "default_checkpoint_every")]
    checkpoint_every: usize,
    #[serde(default)]
    polish: PolishSettings,
    #[serde(
        default,
        deserialize_with = "deserialize_profiles",
        skip_serializing_if = "Option::is_none"
    )]
    profiles: Option<ProfileSettings>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    islands: Option<IslandSettings>,
    #[serde(default, skip_serializing_if = "CmaesSettings::is_default")]
    cmaes: CmaesSettings,
}

impl From<SearchFile> for SearchSettings {
    fn from(f: SearchFile) -> Self {
        Self {
            method: f.method,
            population: f.population,
            generations: f.generations,
            seed: f.seed,
            target_fitness: f.target_fitness,
            stall_generations: f.stall_generations,
            max_evaluations: f.max_evaluations,
            max_time_s: f.max_time_s,
            checkpoint_every: f.checkpoint_every,
            polish: f.polish,
            profiles: f.profiles,
            islands: f.islands,
            ga: GaSettings {
                tournament: f.tournament,
                crossover: f.crossover,
                mutation: f.mutation,
                elitism: f.elitism,
                init: f.init,
            },
            cmaes: f.cmaes,
        }
    }
}

impl From<SearchSettings> for SearchFile {
    fn from(s: SearchSettings) -> Self {
        Self {
            method: s.method,
            population: s.population,
            generations: s.generations,
            seed: s.seed,
            tournament: s.ga.tournament,
            crossover: s.ga.crossover,
            mutation: s.ga.mutation,
            elitism: s.ga.elitism,
            init: s.ga.init,
            target_fitness: s.target_fitness,
            stall_generations: s.stall_generations,
            max_evaluations: s.max_evaluations,
            max_time_s: s.max_time_s,
            checkpoint_every: s.checkpoint_every,
            polish: s.polish,
            profiles: s.profiles,
            islands: s.islands,
            cmaes: s.cmaes,
        }
    }
}

/// The campaign's `"search": {"polish": {…}}` object: Levenberg–Marquardt from
/// the best distinct candidates of the GA's final population, then the
/// parameters' standard errors at the optimum (see [`crate::search::Polish`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolishSettings {
    /// Polish the GA's result and estimate the uncertainty (default `true`).
    #[serde(default = "default_polish_enabled")]
    pub enabled: bool,
    /// Distinct GA candidates to start from, best first (≥ 1; default 8).
    #[serde(default = "default_polish_starts")]
    pub starts: usize,
    /// Iterations at most (default 30); each scores one batch of
    /// `starts × (2 × genes + 1)` candidates. 0 keeps the GA's best and only
    /// estimates the uncertainty there.
    #[serde(default = "default_polish_iterations")]
    pub max_iterations: usize,
}

impl Default for PolishSettings {
    fn default() -> Self {
        Self {
            enabled: default_polish_enabled(),
            starts: default_polish_starts(),
            max_iterations: default_polish_iterations(),
        }
    }
}

fn default_polish_enabled() -> bool {
    true
}
fn default_polish_starts() -> usize {
    8
}
fn default_polish_iterations() -> usize {
    30
}

fn default_crossover_probability() -> f64 {
    0.9
}
fn default_crossover_eta() -> f64 {
    15.0
}
fn default_mutation_eta() -> f64 {
    20.0
}
fn default_tournament() -> usize {
    2
}
fn default_elitism() -> usize {
    2
}
fn default_checkpoint_every() -> usize {
    10
}

impl Default for CrossoverSettings {
    fn default() -> Self {
        Self {
            probability: default_crossover_probability(),
            eta: default_crossover_eta(),
        }
    }
}

impl Default for MutationSettings {
    fn default() -> Self {
        Self {
            probability: None,
            eta: default_mutation_eta(),
        }
    }
}

/// A `"search"` setting outside its allowed range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: expected {expected}, found {found}")]
pub struct SettingsError {
    /// Field path inside the `"search"` object (e.g. `crossover.eta`).
    pub field: &'static str,
    /// What was expected.
    pub expected: String,
    /// What was found.
    pub found: String,
}

impl SearchSettings {
    /// Settings of a campaign that has no `search` section: every default, no
    /// population and no generations, so [`SearchSettings::validate`] refuses them.
    pub fn unset() -> Self {
        serde_json::from_str(r#"{"population": 0, "generations": 0}"#)
            .expect("the defaults deserialise")
    }

    /// Checks every setting's range: population ≥ 4, generations ≥ 1,
    /// tournament ≥ 2 and ≤ population, elitism < population, probabilities in
    /// [0, 1], distribution indices > 0, evaluation and time limits > 0,
    /// polish starts ≥ 1, and the method's own settings.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let err = |field, expected: &str, found: String| {
            Err(SettingsError {
                field,
                expected: expected.into(),
                found,
            })
        };
        let prob = |p: f64| (0.0..=1.0).contains(&p);
        if self.population < 4 {
            return err("population", "at least 4", self.population.to_string());
        }
        if self.generations < 1 {
            return err("generations", "at least 1", "0".into());
        }
        let ga = &self.ga;
        if ga.tournament < 2 || ga.tournament > self.population {
            let exp = format!("between 2 and the population ({})", self.population);
            return err("tournament", &exp, ga.tournament.to_string());
        }
        if ga.elitism >= self.population {
            let exp = format!("less than the population ({})", self.population);
            return err("elitism", &exp, ga.elitism.to_string());
        }
        if !prob(ga.crossover.probability) {
            let found = ga.crossover.probability.to_string();
            return err("crossover.probability", "a value in [0, 1]", found);
        }
        if !(ga.crossover.eta > 0.0 && ga.crossover.eta.is_finite()) {
            return err("crossover.eta", "a value > 0", ga.crossover.eta.to_string());
        }
        if let Some(p) = ga.mutation.probability
            && !prob(p)
        {
            return err("mutation.probability", "a value in [0, 1]", p.to_string());
        }
        if !(ga.mutation.eta > 0.0 && ga.mutation.eta.is_finite()) {
            return err("mutation.eta", "a value > 0", ga.mutation.eta.to_string());
        }
        if self.max_evaluations == Some(0) {
            return err("max_evaluations", "at least 1", "0".into());
        }
        if let Some(t) = self.max_time_s
            && (t.is_nan() || t <= 0.0)
        {
            return err("max_time_s", "a time > 0 s", t.to_string());
        }
        if self.polish.starts < 1 {
            return err("polish.starts", "at least 1", "0".into());
        }
        if let Some((field, expected, found)) = self.profiles.and_then(|p| p.invalid()) {
            let field = match field {
                "points" => "profiles.points",
                _ => "profiles.span",
            };
            return err(field, expected, found);
        }
        if let Some(f) = self.target_fitness
            && !f.is_finite()
        {
            return err("target_fitness", "a finite number", f.to_string());
        }
        if let Some(islands) = &self.islands {
            if let Some((field, expected, found)) = islands.invalid(self.population) {
                return err(field, &expected, found);
            }
            if self.method != Method::Ga {
                // CMA-ES's state is a distribution, not a population a
                // migrant could join.
                let found = format!("method \"{}\"", self.method);
                return err(
                    "islands",
                    "the GA (method \"ga\"); CMA-ES cannot take migrants",
                    found,
                );
            }
        }
        self.cmaes.validate()
    }
}
