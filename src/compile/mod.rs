//! The rig compiler: a rig description lowered to one SSA graph of scalar
//! operations per drive mode ([`ir`], [`lower`]), evaluated by the f64 CPU
//! reference ([`exec::tape`], [`exec::events`]) and written as WGSL for the
//! ensemble kernels ([`back::wgsl`]), in the same order.
//!
//! Its modules are layers, each importing only those before it (ARCHITECTURE.md,
//! "Compile layers"; `tests/layers.rs`): [`math`], [`ir`], [`program`],
//! [`front`], [`exec`], [`analysis`], [`back`].
//!
//! ```text
//! rigs/*.json ─► rig::RigDesc ─► lower ─► Program (Graph + roots + Transitions) ─┬► Tape ─► EventStepper (f64 CPU)
//!                                                                                └► GpuRig ─► WGSL (shared/rig_run.wgsl)
//! ```

pub mod analysis;
pub mod back;
pub mod exec;
pub mod front;
pub mod ir;
pub mod math;
pub mod program;

pub use back::native::NativeError;
pub use back::wgsl::{EmitError, GpuRig};
pub use exec::events::{EventStepper, Fired, MAX_EVENTS_PER_STEP};
pub use exec::initial::initial_state;
pub use exec::lane_code::LaneCode;
pub use exec::lanes::{Isa, LANES, LaneRunner};
pub use exec::native_calls::{Arith, Native};
pub use exec::tape::{Frame, Point, Tape};
pub use front::{Lowered, lower};
pub use ir::{Graph, Id, Input, Op};
pub use program::{Direction, Program, RegimeVar, Transition};
