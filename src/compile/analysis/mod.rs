//! Analyses of a lowered program: interval bounds of its Jacobian, the events
//! that can no longer reach the measured output, forward-mode tangents.

pub mod interval;
pub mod liveness;
pub mod tangent;
