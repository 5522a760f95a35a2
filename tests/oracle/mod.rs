//! An independent implementation of the tensile rig, outside the product: its
//! equations written out by hand (`tensile.rs`) on a classic RK4 of their own
//! (`rk4.rs`), with the canonical systems that hold that RK4 to closed forms
//! (`systems.rs`). Tests compare the compiled `rigs/tensile4.json` with it.
#![allow(dead_code, reason = "each test file uses a different subset")]

pub mod rk4;
pub mod systems;
pub mod tensile;
