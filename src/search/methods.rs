//! The search methods a campaign can name, each registered once: its name in
//! `"search": {"method": …}` and `--method`, and how it is built.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::SearchError;
use super::cmaes::Cmaes;
use super::ga::GeneticAlgorithm;
use super::genes::GeneSpec;
use super::settings::SearchSettings;
use super::solver::Solver;

/// A search method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// The real-coded genetic algorithm of Yoo et al., "Application of
    /// Model-based Design Approach on Dynamic Tensile Testing" ([`GeneticAlgorithm`]).
    #[default]
    Ga,
    /// The covariance matrix adaptation evolution strategy (Hansen), with
    /// restarts of growing population as an option ([`Cmaes`]).
    Cmaes,
}

impl Method {
    /// Every method, in the order `--help` lists them.
    pub const ALL: [Method; 2] = [Method::Ga, Method::Cmaes];

    /// The name a campaign and `--method` use.
    pub fn name(self) -> &'static str {
        match self {
            Method::Ga => "ga",
            Method::Cmaes => "cmaes",
        }
    }

    /// The method's short name in sentences ("the GA's best").
    pub fn label(self) -> &'static str {
        match self {
            Method::Ga => "GA",
            Method::Cmaes => "CMA-ES",
        }
    }

    /// One line for `--help`.
    pub fn about(self) -> &'static str {
        match self {
            Method::Ga => "the genetic algorithm (tournament, SBX crossover, polynomial mutation)",
            Method::Cmaes => {
                "CMA-ES: learns the correlations between parameters; IPOP restarts with search.cmaes.restarts"
            }
        }
    }

    /// The largest batch the method asks for under `settings`: what the
    /// memory a job needs is sized by (CMA-ES's restarts grow its batch).
    pub fn largest_batch(self, settings: &SearchSettings) -> usize {
        match self {
            Method::Ga => settings.population,
            Method::Cmaes => Cmaes::largest_population(settings),
        }
    }

    /// The method's solver over `genes`, its settings checked.
    pub fn solver(
        self,
        settings: &SearchSettings,
        genes: Vec<GeneSpec>,
    ) -> Result<Box<dyn Solver>, SearchError> {
        Ok(match self {
            Method::Ga => Box::new(GeneticAlgorithm::new(settings.clone(), genes)?),
            Method::Cmaes => Box::new(Cmaes::new(settings, genes)?),
        })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                format!(
                    "unknown search method `{s}`; expected one of: {}",
                    names.join(", ")
                )
            })
    }
}

/// The first `n` candidates (values) of the search `settings` describe, as
/// its executor draws them from the seed: what `--backend auto` times, so
/// that the path kept has already scored them. `None` when the settings
/// cannot build a search.
pub fn first_candidates(
    settings: &SearchSettings,
    genes: &[GeneSpec],
    n: usize,
) -> Option<Vec<Vec<f64>>> {
    let mut solver = settings.method.solver(settings, genes.to_vec()).ok()?;
    let mut rng = super::state::SearchState::start(settings.seed).rng;
    let batch = solver.ask(&mut rng);
    Some(
        batch
            .iter()
            .take(n)
            .map(|g| super::genes::genome_values(genes, g))
            .collect(),
    )
}
