//! The executors of a program on the CPU: the f64 tape and its event stepper,
//! the lane-batched register code, its interpreter, the vector instruction sets
//! it is built for and its runner, the calls into its native build, the initial
//! regimes.

pub mod events;
pub mod initial;
mod interp;
mod isa;
pub mod lane_code;
pub mod lanes;
pub mod native_calls;
pub mod sampling;
pub mod tape;
