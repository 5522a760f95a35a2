//! The calibration search: a real-coded genetic algorithm shaped as a solver loop
//! with observers.

mod settings;

pub use settings::{CrossoverSettings, GaSettings, InitKind, MutationSettings, SettingsError};
