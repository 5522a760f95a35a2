//! Search settings as written in a campaign's `"search"` object.

use serde::{Deserialize, Serialize};

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

/// The campaign's `"search"` object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaSettings {
    /// Candidates per generation (≥ 4).
    pub population: usize,
    /// Maximum number of generations (≥ 1).
    pub generations: usize,
    /// RNG seed; the same seed, campaign and backend give bit-identical results.
    #[serde(default)]
    pub seed: u64,
    /// Tournament size for parent selection (≥ 2).
    #[serde(default = "default_tournament")]
    pub tournament: usize,
    /// Crossover.
    #[serde(default)]
    pub crossover: CrossoverSettings,
    /// Mutation.
    #[serde(default)]
    pub mutation: MutationSettings,
    /// Best candidates copied unchanged into the next generation.
    #[serde(default = "default_elitism")]
    pub elitism: usize,
    /// Initial population.
    #[serde(default)]
    pub init: InitKind,
    /// Stop once the best joint fitness (weighted mean of 1 − R²) is at or below this.
    pub target_fitness: Option<f64>,
    /// Stop after this many generations without improvement of the best.
    pub stall_generations: Option<usize>,
    /// Stop after this much wall time (s).
    pub max_time_s: Option<f64>,
    /// Write a checkpoint every this many generations (0: only on interrupt).
    #[serde(default = "default_checkpoint_every")]
    pub checkpoint_every: usize,
    /// The local polish after the GA, and the parameter uncertainty it gives.
    #[serde(default)]
    pub polish: PolishSettings,
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

impl GaSettings {
    /// Settings of a campaign that has no `search` section: every default, no
    /// population and no generations, so [`GaSettings::validate`] refuses them.
    pub fn unset() -> Self {
        serde_json::from_str(r#"{"population": 0, "generations": 0}"#)
            .expect("the defaults deserialise")
    }

    /// Checks every setting's range: population ≥ 4, generations ≥ 1,
    /// tournament ≥ 2 and ≤ population, elitism < population, probabilities in
    /// [0, 1], distribution indices > 0, time limit > 0, polish starts ≥ 1.
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
        if self.tournament < 2 || self.tournament > self.population {
            let exp = format!("between 2 and the population ({})", self.population);
            return err("tournament", &exp, self.tournament.to_string());
        }
        if self.elitism >= self.population {
            let exp = format!("less than the population ({})", self.population);
            return err("elitism", &exp, self.elitism.to_string());
        }
        if !prob(self.crossover.probability) {
            let found = self.crossover.probability.to_string();
            return err("crossover.probability", "a value in [0, 1]", found);
        }
        if !(self.crossover.eta > 0.0 && self.crossover.eta.is_finite()) {
            return err(
                "crossover.eta",
                "a value > 0",
                self.crossover.eta.to_string(),
            );
        }
        if let Some(p) = self.mutation.probability {
            if !prob(p) {
                return err("mutation.probability", "a value in [0, 1]", p.to_string());
            }
        }
        if !(self.mutation.eta > 0.0 && self.mutation.eta.is_finite()) {
            return err("mutation.eta", "a value > 0", self.mutation.eta.to_string());
        }
        if let Some(t) = self.max_time_s {
            if t.is_nan() || t <= 0.0 {
                return err("max_time_s", "a time > 0 s", t.to_string());
            }
        }
        if self.polish.starts < 1 {
            return err("polish.starts", "at least 1", "0".into());
        }
        if let Some(f) = self.target_fitness {
            if !f.is_finite() {
                return err("target_fitness", "a finite number", f.to_string());
            }
        }
        Ok(())
    }
}
