//! rigfit calibrates lumped mass-spring-damper models of mechanical test rigs to
//! measured force histories.
//!
//! Data flows campaign → validated model and data → evaluator (CPU or GPU) →
//! search → results; see `ARCHITECTURE.md`.

pub mod campaign;
pub mod compile;
pub mod data;
pub mod eval;
pub mod fixtures;
pub mod fsutil;
pub mod gpu;
pub mod integrate;
pub mod job;
pub mod model;
pub mod modes;
pub mod precal;
pub mod report;
pub mod rig;
pub mod search;
pub mod text;
