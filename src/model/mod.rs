//! The rig model: a compiled rig file ([`compiled::CompiledRig`]) behind the
//! [`RigModel`] interface the fitness and the search see.

pub mod compiled;
mod linearise;
pub mod modes;
mod stability;

use std::ops::ControlFlow;

use crate::base::{Drive, FittedSample, ParamInfo, Report, Sample, SampleGrid};

/// [`RigModel::simulate_fitted`] one run after the other, in f64 (its
/// default).
pub fn fitted_one_by_one<M: RigModel + ?Sized>(
    model: &M,
    params: &[&[f64]],
    drive: &Drive,
    grid: &SampleGrid,
    observe: &mut dyn FnMut(&FittedSample<'_>, &mut u64),
) {
    for (i, p) in params.iter().enumerate() {
        model.simulate(p, drive, grid, &mut |s| {
            let mut live = 1;
            let values = [s.outputs[0]];
            let sample = FittedSample {
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

/// [`RigModel::simulate_many`] one run after the other (its default).
pub fn many_one_by_one<M: RigModel + ?Sized>(
    model: &M,
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
    pub dofs: Vec<&'static str>,
    /// Diagonal of the mass matrix (kg).
    pub mass: Vec<f64>,
    /// Stiffness matrix, row-major, `dofs.len()²` (N/m).
    pub stiffness: Vec<f64>,
}

/// A lumped rig model: its parameters, its equations and how to pack them for the
/// GPU.
pub trait RigModel: Send + Sync + std::fmt::Debug {
    /// The rig's id (its file's `"id"`).
    fn id(&self) -> &'static str;

    /// The model's parameters, in the order of every parameter vector.
    fn params(&self) -> &'static [ParamInfo];

    /// Names of the state variables.
    fn state_names(&self) -> &'static [&'static str];

    /// Names and units of the outputs; output 0 is fitted to the measurement.
    fn output_names(&self) -> &'static [(&'static str, &'static str)];

    /// Checks a full parameter vector for physical sense (positive masses, …).
    /// Returns the offending parameter's name and what was expected.
    fn check(&self, params: &[f64]) -> Result<(), (&'static str, String)>;

    /// Integrates one run from rest with the f64 RK4 reference, calling `observe`
    /// at every sample of `grid`.
    fn simulate(
        &self,
        params: &[f64],
        drive: &Drive,
        grid: &SampleGrid,
        observe: &mut dyn FnMut(&Sample<'_>) -> ControlFlow<()>,
    );

    /// Runs several parameter vectors on one grid, calling `observe(run,
    /// sample)` at every sample of each until its observer breaks, with what
    /// `report` asks for in each sample. By default one run after the other;
    /// a model with a lane-batched ensemble (see [`RigModel::lanes`]) advances
    /// them together, with the same results.
    fn simulate_many(
        &self,
        params: &[&[f64]],
        drive: &Drive,
        grid: &SampleGrid,
        report: Report,
        observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ) {
        many_one_by_one(self, params, drive, grid, report, observe);
    }

    /// Output 0 alone of several runs on one grid, each sample's values for a
    /// group of runs handed to `observe` at once (what the fitness needs,
    /// without a call per run and sample). `live` has a bit per run of the
    /// group (bit `j`: run `first + j`) still observed: the observer clears a
    /// run's bit to stop observing it, and the group ends when none is left.
    /// With `f32`, in f32 arithmetic where the model has an f32 path here (a
    /// compiled rig whose lane code the C compiler built), held to the f32
    /// tolerance of the f64 reference as the GPU's f32 kernels are. Returns
    /// whether it ran in f32. By default one run after the other, in f64.
    fn simulate_fitted(
        &self,
        params: &[&[f64]],
        drive: &Drive,
        grid: &SampleGrid,
        f32: bool,
        observe: &mut dyn FnMut(&FittedSample<'_>, &mut u64),
    ) -> bool {
        let _ = f32;
        fitted_one_by_one(self, params, drive, grid, observe);
        false
    }

    /// How many runs [`RigModel::simulate_many`] advances together (1: no
    /// gain from grouping runs).
    fn lanes(&self) -> usize {
        1
    }

    /// The rig linearised about its engaged, unbroken configuration.
    fn linearise(&self, params: &[f64], drive: &Drive) -> Linearised;

    /// What [`RigModel::linearise`] linearises about, in words, for the header
    /// of `rigfit modes`.
    fn linearisation_point(&self) -> String {
        format!("rig {} linearised about rest", self.id())
    }

    /// Upper bound on the highest natural frequency (rad/s) of any parameter
    /// vector inside `[lower, upper]`, with the name of the parameter that limits
    /// it most. Used to choose or refuse the RK4 step.
    fn omega_bound(&self, lower: &[f64], upper: &[f64], drive: &Drive) -> (f64, &'static str);

    /// [`Self::omega_bound`] for a run of model time `0..t_end` (s): a model
    /// whose stiffness grows with a displacement may bound that displacement by
    /// what the drive reaches in that time. The default ignores `t_end`.
    fn omega_bound_in_run(
        &self,
        lower: &[f64],
        upper: &[f64],
        drive: &Drive,
        _t_end: f64,
    ) -> (f64, &'static str) {
        self.omega_bound(lower, upper, drive)
    }

    /// Whether the model can run under `drive` (a rig without a force-mode
    /// drive cannot take a force table).
    fn supports(&self, _drive: &Drive) -> bool {
        true
    }

    /// How the model runs in the GPU ensemble kernels under `drive` (every
    /// experiment of a GPU batch must get the same kernels); `None` keeps it
    /// CPU-only.
    fn gpu(&self, _drive: &Drive) -> Option<GpuModel> {
        None
    }
}

/// A rig's kernels for the GPU ensemble (see `crate::gpu`): the compiled rig
/// written as WGSL for the event run loop (`shaders/shared/rig_run.wgsl`).
pub type GpuModel = std::sync::Arc<crate::compile::GpuRig>;

/// Index of a parameter by name in a model's parameter list.
pub fn param_index(model: &dyn RigModel, name: &str) -> Option<usize> {
    model.params().iter().position(|p| p.name == name)
}
