//! The back ends: a program written as C for the native lanes (and built and
//! loaded), and as WGSL for the GPU kernels.

pub mod c;
pub mod native;
pub mod native_cache;
pub mod wgsl;
