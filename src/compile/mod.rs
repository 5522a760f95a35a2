//! The rig compiler: a rig description lowered to one SSA graph of scalar
//! operations per drive mode ([`ir`], [`lower`]), evaluated by the f64 CPU
//! reference ([`tape`], [`events`]) and written as WGSL for the ensemble
//! kernels ([`wgsl`]), in the same order.
//!
//! ```text
//! rigs/*.json ─► rig::RigDesc ─► lower ─► Program (Graph + roots + Transitions) ─┬► Tape ─► EventStepper (f64 CPU)
//!                                                                                └► GpuRig ─► WGSL (shared/rig_run.wgsl)
//! ```

pub mod events;
pub mod expr;
pub mod initial;
pub mod interval;
pub mod ir;
pub mod lane_code;
pub mod lanes;
pub mod liveness;
pub mod lower;
pub mod math;
pub mod native;
pub mod native_c;
pub mod program;
pub mod tangent;
pub mod tape;
pub mod wgsl;

pub use events::{EventStepper, Fired, MAX_EVENTS_PER_STEP};
pub use initial::initial_state;
pub use ir::{Graph, Id, Input, Op};
pub use lane_code::LaneCode;
pub use lanes::{Isa, LANES, LaneRunner};
pub use lower::{Lowered, lower};
pub use native::{Native, NativeError};
pub use native_c::Arith;
pub use program::{Direction, ModeVar, Program, Transition};
pub use tape::{Frame, Point, Tape};
pub use wgsl::{EmitError, GpuRig};
