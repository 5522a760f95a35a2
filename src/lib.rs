//! rigfit calibrates lumped mass-spring-damper models of mechanical test rigs to
//! measured force histories.
//!
//! Data flows campaign → validated model and data → evaluator (CPU or GPU) →
//! search → results; see `ARCHITECTURE.md`.

pub mod eval;
pub mod fixtures;
pub mod gpu;
pub mod integrate;
pub mod model;
pub mod search;
