//! The calibration search: methods behind one [`Solver`] trait, one executor
//! with observers, and the polish after.
//!
//! - [`Solver`]: a method as pure state transitions in ask/tell form (ask a
//!   batch, tell its costs), all randomness from one seeded `ChaCha8Rng`.
//!   [`GeneticAlgorithm`] and [`Cmaes`] implement it; [`Method`] registers
//!   them under the names a campaign uses.
//! - [`BatchCost`]: scores a whole batch at once (GPU-friendly).
//! - [`Executor`]: drives any solver against a cost, calls [`Observer`]s, writes
//!   [`Checkpoint`]s, stops on generations / evaluations / target / stall /
//!   wall time / the method's own end / interrupt and says why
//!   ([`TerminationReason`]).
//! - [`Polish`]: Levenberg–Marquardt on a [`ResidualCost`] from the search's
//!   best distinct candidates, and the [`Uncertainty`] of each gene at the
//!   optimum; run by the same executor after the search
//!   ([`Executor::then_polish`]), under the same observers, interrupt flag and
//!   termination reason.
//!
//! ```
//! use rigfit::base::Scale;
//! use rigfit::search::{Executor, FnCost, GeneSpec, GeneticAlgorithm, SearchSettings, TerminationReason};
//! let settings: SearchSettings =
//!     serde_json::from_str(r#"{"population": 40, "generations": 60, "seed": 7}"#).unwrap();
//! let genes = vec![
//!     GeneSpec::new("x", -5.0, 5.0, Scale::Linear),
//!     GeneSpec::new("k", 1e-2, 1e2, Scale::Log),
//! ];
//! let ga = GeneticAlgorithm::new(settings, genes).unwrap();
//! let cost = FnCost(|g: &[f64]| (g[0] - 1.0).powi(2) + g[1].ln().powi(2));
//! let outcome = Executor::new(ga, cost).run().unwrap();
//! assert_eq!(outcome.termination, TerminationReason::MaxGenerations);
//! assert!(outcome.best_cost < 1e-3);
//! ```

mod checkpoint;
mod cmaes;
mod cost;
mod error;
mod executor;
mod ga;
pub mod genes;
pub mod islands;
mod methods;
mod observers;
pub mod operators;
mod polish;
pub mod profile;
mod progress;
pub mod report;
mod settings;
mod solver;
mod state;
pub mod uncertainty;

pub use checkpoint::{Checkpoint, Fingerprint};
pub use cmaes::{Cmaes, CmaesSettings};
pub use cost::{BatchCost, CostBatch, FnCost};
pub use error::SearchError;
pub use executor::{DIVERGED_WARN_SHARE, Executor};
pub use ga::{GeneticAlgorithm, Offspring};
pub use genes::GeneSpec;
pub use islands::{IslandSettings, Migration};
pub use methods::{Method, first_candidates};
pub use observers::{
    HISTORY_COLUMNS, HistoryCsvObserver, Observer, ObserverMode, history_csv, write_history_csv,
};
pub use polish::{
    FnResiduals, Polish, PolishIteration, PolishOutcome, PolishStop, ResidualCost, StartReport,
    distinct_starts,
};
pub use profile::{ProfileOutcome, ProfileSettings, Profiles};
pub use progress::ProgressObserver;
pub use report::{EliteSpread, GenerationReport, SearchOutcome, TerminationReason};
pub use settings::{
    CrossoverSettings, GaSettings, InitKind, MutationSettings, PolishSettings, SearchSettings,
    SettingsError,
};
pub use solver::Solver;
pub use state::SearchState;
pub use uncertainty::{AtBound, GeneUncertainty, ResidualBlock, Uncertainty, Z95};
