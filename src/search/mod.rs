//! The calibration search: a real-coded genetic algorithm shaped as a solver loop
//! with observers.
//!
//! - [`GeneticAlgorithm`]: pure state transitions (initial population, next
//!   population from costs), all randomness from one seeded `ChaCha8Rng`.
//! - [`BatchCost`]: scores a whole generation at once (GPU-friendly).
//! - [`Executor`]: drives both, calls [`Observer`]s, writes [`Checkpoint`]s,
//!   stops on generations / target / stall / wall time / interrupt and says why
//!   ([`TerminationReason`]).
//! - [`Polish`]: Levenberg–Marquardt on a [`ResidualCost`] from the GA's best
//!   distinct candidates, and the [`Uncertainty`] of each gene at the optimum;
//!   run by the same executor after the GA ([`Executor::then_polish`]), under
//!   the same observers, interrupt flag and termination reason.
//!
//! ```
//! use rigfit::base::Scale;
//! use rigfit::search::{Executor, FnCost, GaSettings, GeneSpec, GeneticAlgorithm, TerminationReason};
//! let settings: GaSettings =
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
mod cost;
mod error;
mod executor;
mod ga;
pub mod genes;
mod observers;
pub mod operators;
mod polish;
mod progress;
pub mod report;
mod settings;
mod state;
pub mod uncertainty;

pub use checkpoint::{Checkpoint, Fingerprint};
pub use cost::{BatchCost, CostBatch, FnCost};
pub use error::SearchError;
pub use executor::{DIVERGED_WARN_SHARE, Executor};
pub use ga::{GeneticAlgorithm, Offspring};
pub use genes::GeneSpec;
pub use observers::{
    HISTORY_COLUMNS, HistoryCsvObserver, Observer, ObserverMode, history_csv, write_history_csv,
};
pub use polish::{
    FnResiduals, Polish, PolishIteration, PolishOutcome, PolishStop, ResidualCost, StartReport,
    distinct_starts,
};
pub use progress::ProgressObserver;
pub use report::{EliteSpread, GenerationReport, SearchOutcome, TerminationReason};
pub use settings::{
    CrossoverSettings, GaSettings, InitKind, MutationSettings, PolishSettings, SettingsError,
};
pub use state::SearchState;
pub use uncertainty::{AtBound, GeneUncertainty, ResidualBlock, Uncertainty, Z95};
