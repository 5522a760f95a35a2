//! rigfit calibrates lumped mass-spring-damper models of mechanical test rigs to
//! measured force histories.
//!
//! Data flows campaign → validated model and data → evaluator (CPU or GPU) →
//! search → results; see `ARCHITECTURE.md`.

pub mod base;
pub mod campaign;
pub mod compile;
pub mod design;
pub mod eval;
pub mod gpu;
pub mod identify;
pub mod job;
pub mod model;
pub mod record;
pub mod report;
pub mod rig;
pub mod search;
pub mod series;
