//! Rig models. Each model is one module here and one WGSL file under `shaders/`,
//! registered in [`registry`]; the integrator, the fitness and the search only
//! ever see the [`RigModel`] trait.

pub mod compiled;
mod drive;
mod params;
pub mod tensile;
mod tensile_gpu;
mod tensile_params;

use std::ops::ControlFlow;

pub use drive::{Drive, PiecewiseLinear};
pub use params::{ParamInfo, ParamScope, Scale};

use crate::integrate::SampleGrid;

/// What a model reports at each measurement sample.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    /// Sample index on the grid.
    pub index: usize,
    /// Model time (s).
    pub t: f64,
    /// Full state vector (see [`RigModel::state_names`]).
    pub state: &'a [f64],
    /// Observed outputs (see [`RigModel::output_names`]); output 0 is the quantity
    /// fitted against the measured history.
    pub outputs: &'a [f64],
}

/// Output 0 of a group of runs at one sample ([`RigModel::simulate_fitted`]).
#[derive(Debug, Clone, Copy)]
pub struct FittedSample<'a> {
    /// The run `values[0]` belongs to; `values[j]` is run `first + j`'s.
    pub first: usize,
    /// Sample index on the grid.
    pub index: usize,
    /// Sample time (s).
    pub t: f64,
    /// Output 0 of each run of the group (NaN for a run that chattered).
    pub values: &'a [f64],
}

/// Runs `0..n` of a group as `live` bits ([`RigModel::simulate_fitted`];
/// `n ≤ 64`).
pub fn lane_bits(n: usize) -> u64 {
    assert!(n <= 64, "at most 64 runs to a group");
    if n == 64 { u64::MAX } else { (1 << n) - 1 }
}

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

/// What [`RigModel::simulate_many`] reports at each sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Report {
    /// Every output and the full state.
    Full,
    /// Output 0 alone, the quantity fitted to the measurement: the sample's
    /// `outputs` holds only it and its `state` is empty, which spares a
    /// lane-batched model the rest of the report (the fitness needs no more).
    Fitted,
}

impl Report {
    /// `s` cut down to what this report holds.
    pub fn of<'a>(self, s: &Sample<'a>) -> Sample<'a> {
        match self {
            Self::Full => *s,
            Self::Fitted => Sample {
                state: &[],
                outputs: &s.outputs[..s.outputs.len().min(1)],
                ..*s
            },
        }
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
    /// Identifier used in campaign files (`"model": "tensile4"`).
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
        for (i, p) in params.iter().enumerate() {
            self.simulate(p, drive, grid, &mut |s| observe(i, &report.of(s)));
        }
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

/// A model's plug-in for the GPU ensemble kernels (see `crate::gpu`).
#[derive(Debug, Clone)]
pub enum GpuModel {
    /// A hand-written model file for the fixed-size run loop
    /// (`shaders/shared/rk4.wgsl`, `run.wgsl`): at most four degrees of freedom
    /// and one located switch.
    Handwritten {
        /// WGSL source defining `Rig`, `rig_load`, `rig_actuator`, `rig_actuators`
        /// (the `Actuation` of a whole step), the drive clock carried between
        /// steps (`rig_clock`, `rig_clock_half`, `rig_clock_next`,
        /// `rig_actuators_clocked`), `rig_deriv`, `rig_switch`, `rig_fire`,
        /// `rig_is_broken`, `rig_outputs` and `rig_full_state` (one of the
        /// constants in `crate::gpu::shaders`).
        wgsl: &'static str,
        /// Names of the packed per-run values, in order; the shader stitcher
        /// emits a `const P_<NAME>: u32` index for each.
        slots: &'static [&'static str],
        /// Packs one full parameter vector into `slots.len()` values (f64,
        /// converted to the kernel's precision afterwards), appending to `out`.
        pack: fn(params: &[f64], out: &mut Vec<f64>),
    },
    /// A compiled rig description: generated functions for the event run loop
    /// (`shaders/shared/rig_run.wgsl`), any state size, any number of switches.
    Compiled(std::sync::Arc<crate::compile::GpuRig>),
}

impl GpuModel {
    /// Names of the packed per-run values, in order.
    pub fn slots(&self) -> Vec<String> {
        match self {
            GpuModel::Handwritten { slots, .. } => slots.iter().map(|s| s.to_string()).collect(),
            GpuModel::Compiled(r) => r.slot_names(),
        }
    }

    /// Appends one run's packed values for the full parameter vector `params`.
    pub fn pack(&self, params: &[f64], out: &mut Vec<f64>) {
        match self {
            GpuModel::Handwritten { pack, .. } => pack(params, out),
            GpuModel::Compiled(r) => r.pack(params, out),
        }
    }

    /// Values per run in the kernels' state buffer.
    pub fn state_stride(&self) -> u32 {
        match self {
            GpuModel::Handwritten { .. } => crate::gpu::layout::STATE_STRIDE,
            GpuModel::Compiled(r) => r.state_stride(),
        }
    }

    /// Values per history record (t, the outputs, the full state).
    pub fn hist_values(&self) -> u32 {
        match self {
            GpuModel::Handwritten { .. } => crate::gpu::layout::HIST_VALUES,
            GpuModel::Compiled(r) => r.hist_values(),
        }
    }

    /// How many of the model's `outputs` and `states` a history record holds.
    pub fn hist_layout(&self, outputs: usize, states: usize) -> (usize, usize) {
        match self {
            GpuModel::Handwritten { .. } => (outputs.min(2), states.min(8)),
            GpuModel::Compiled(_) => (outputs, states),
        }
    }

    /// Values the data buffer holds before the experiments' (a compiled rig's
    /// inline tables).
    pub fn table_data(&self) -> &[f64] {
        match self {
            GpuModel::Handwritten { .. } => &[],
            GpuModel::Compiled(r) => r.table_data(),
        }
    }

    /// Whether two plug-ins are the same kernels.
    pub fn same(&self, other: &GpuModel) -> bool {
        match (self, other) {
            (GpuModel::Handwritten { wgsl: a, .. }, GpuModel::Handwritten { wgsl: b, .. }) => {
                std::ptr::eq(*a, *b)
            }
            (GpuModel::Compiled(a), GpuModel::Compiled(b)) => std::sync::Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// Every model rigfit knows, by id.
pub fn registry() -> Vec<&'static dyn RigModel> {
    vec![&tensile::TENSILE4]
}

/// Looks a model up by its campaign id.
pub fn by_id(id: &str) -> Option<&'static dyn RigModel> {
    registry().into_iter().find(|m| m.id() == id)
}

/// Index of a parameter by name in a model's parameter list.
pub fn param_index(model: &dyn RigModel, name: &str) -> Option<usize> {
    model.params().iter().position(|p| p.name == name)
}
