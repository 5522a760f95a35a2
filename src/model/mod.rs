//! The rig model: a compiled rig file, [`CompiledRig`], the one rig type the
//! fitness, the search and the campaign see, with its stability bound, its
//! linearisation and the modal analysis built on it.

pub mod compiled;
mod linearise;
pub mod modes;
mod stability;
pub mod step_error;

use std::ops::ControlFlow;

pub use compiled::CompiledRig;

use crate::base::{Drive, MeasuredSample, Report, Sample, SampleGrid};

/// [`crate::model::CompiledRig::simulate_measured`] one run after the other, in f64 (its
/// default).
pub fn measured_one_by_one(
    model: &CompiledRig,
    params: &[&[f64]],
    drive: &Drive,
    grid: &SampleGrid,
    observe: &mut dyn FnMut(&MeasuredSample<'_>, &mut u64),
) {
    for (i, p) in params.iter().enumerate() {
        model.simulate(p, drive, grid, &mut |s| {
            let mut live = 1;
            let values = [s.outputs[0]];
            let sample = MeasuredSample {
                first: i,
                index: s.index,
                t: s.t,
                values: &values,
            };
            observe(&sample, &mut live);
            if live == 0 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
    }
}

/// [`crate::model::CompiledRig::simulate_many`] one run after the other (its default).
pub fn many_one_by_one(
    model: &CompiledRig,
    params: &[&[f64]],
    drive: &Drive,
    grid: &SampleGrid,
    report: Report,
    observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
) {
    for (i, p) in params.iter().enumerate() {
        model.simulate(p, drive, grid, &mut |s| observe(i, &report.of(s)));
    }
}

/// Linearised rig for modal analysis: `M·ẍ + K·x = 0` with a diagonal mass matrix.
#[derive(Debug, Clone)]
pub struct Linearised {
    /// Name of each degree of freedom.
    pub dofs: Vec<String>,
    /// Diagonal of the mass matrix (kg).
    pub mass: Vec<f64>,
    /// Stiffness matrix, row-major, `dofs.len()²` (N/m).
    pub stiffness: Vec<f64>,
}

/// A rig's kernels for the GPU ensemble (see `crate::gpu`): the compiled rig
/// written as WGSL for the event run loop (`shaders/shared/rig_run.wgsl`).
pub type GpuModel = std::sync::Arc<crate::compile::GpuRig>;

/// Index of a parameter by name in a model's parameter list.
pub fn param_index(model: &CompiledRig, name: &str) -> Option<usize> {
    model.params().iter().position(|p| p.name == name)
}
