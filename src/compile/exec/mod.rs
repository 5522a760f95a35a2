//! The executors of a program on the CPU: the f64 tape and its event stepper,
//! the lane-batched register code and its runner, the math both share, the
//! initial modes.

pub mod events;
pub mod initial;
pub mod lane_code;
pub mod lanes;
pub mod math;
pub mod tape;
