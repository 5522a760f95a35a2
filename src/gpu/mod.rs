//! The GPU ensemble evaluator: a whole population of candidate rigs integrated
//! in one WGSL compute pipeline (wgpu), one invocation per (candidate,
//! experiment) run, returning one `1 − R²` per run.
//!
//! A compiled rig's kernels are stitched together in one place
//! ([`shaders::source`]): the prelude, the shared pieces under
//! `shaders/shared/`, the rig file that `crate::compile::back::wgsl` emits for
//! the rig's program, and a kernel (`shaders/rig_fitness.wgsl` or
//! `shaders/rig_history.wgsl`). The run loop (`shaders/shared/rig_run.wgsl`)
//! takes every step as the f64 CPU reference does
//! ([`crate::compile::exec::events::EventStepper`] on
//! [`crate::base::walk_grid`]'s times): the same RK4 stages, step times from the
//! step index, the prologue when `t0 > 0`, every located switch found inside
//! its step on the step's cubic Hermite interpolant and the step redone to it,
//! a controller's sample instants taken as
//! [`crate::compile::exec::sampling::SampleClock`] takes them, the blow-up
//! guard on the scored output and `SS_res / SS_tot` over the fit window,
//! accumulated on the device against the measured record. The history kernel
//! writes full histories of chosen candidates ([`with_best`] adds the best
//! one). `shaders/TWINS.md` lists each hand-kept WGSL function with the Rust
//! function it must agree with. Long runs are split
//! into chunks of [`GpuOptions::chunk_steps`] steps, one submit each with the
//! next queued behind it, the cancel flag read between them (an interrupt
//! stops a pass within two chunks); a batch past one dispatch's workgroup
//! limit is split into several dispatches over slices of the buffers; the
//! [`GpuContext`] (device) and the evaluator's pipelines and buffers are built
//! once per job and reused every generation. The fitness kernel is
//! specialised to the batch ([`specialise`]): values shared by every run are
//! compiled in as constants (the same results to rounding).
//!
//! Candidates whose scored output leaves the experiment's blow-up limit (or
//! becomes NaN/Inf), or that chatter (more than the run loop's events in one
//! step), stop integrating and score [`crate::eval::DIVERGED`]; they are
//! counted in `Scores::diverged`.
//!
//! # Limits
//! - At most [`crate::compile::back::wgsl::MAX_SWITCHES`] located switches per
//!   program (`rig_hits` is a 32-bit mask); a rig past it has no kernels
//!   ([`GpuError::TooManySwitches`]).
//! - Force drives are supported (table in the data buffer); kernels for
//!   velocity-only problems are compiled without the force-drive code. A
//!   compiled rig has kernels per drive mode; a job that mixes modes runs one
//!   pipeline per mode ([`GpuByDrive`]), one after the other each generation.
//! - In f32, step indices and prologue step counts are exact up to 2^24.
//! - On CPU drivers (lavapipe) both sides of every branch run, every loop body
//!   runs at least once and a loop tested at its head runs one extra masked
//!   pass, so the sampled part of a run is one flat loop of RK4 steps per block
//!   of samples (`run_block` in `shaders/shared/rig_run.wgsl`) that leaves the
//!   block at a step with a switch or a sample instant inside it, which
//!   `run_crossed` then takes in pieces.
//!
//! # Precision
//! `f32` everywhere; `f64` where the adapter has `SHADER_F64`. Exponentials,
//! logarithms, sines and cosines use our own (`shaders/shared/exp.wgsl`,
//! `shaders/shared/math.wgsl`) in f64 because lavapipe's f64 transcendental
//! functions are wrong. Histories agree with the f64 CPU reference within
//! [`F64_HISTORY_TOLERANCE`] (f64) and [`F32_HISTORY_TOLERANCE`] (f32) of the
//! history's largest magnitude (`tests/gpu_cpu_parity.rs`,
//! `tests/gpu_rig_parity.rs`). Where the histories differ, the driver may
//! evaluate polynomials in a different order (Estrin in our own exp) and fuse
//! multiply-adds.
//!
//! # Throughput
//! Reference problem (998 RK4 steps per candidate), `RIGFIT_BENCH_TABLE_ONLY=1
//! cargo bench --bench evaluator_throughput` on the 2-core development machine
//! (lavapipe, LLVM 15, 256-bit), idle, populations 1024–16384: f32 ≈ 1.2e8, f64
//! ≈ 6.0e7 candidate-steps/s (CPU reference: 1.0e7 on one thread, 2.0e7 on
//! both). On lavapipe the f64 kernel is bound by the latency of the dependent
//! RK4 stages more than by operation count, hence Estrin's scheme in
//! `shaders/shared/exp.wgsl`.
//!
//! # Backend selection
//! [`open_evaluator`] implements `auto | gpu | cpu`. `auto` uses the GPU when an
//! adapter exists, otherwise the CPU evaluator with a one-line note. Setting the
//! environment variable **`RIGFIT_REQUIRE_GPU=1`** turns "no adapter" into an
//! error even for `auto`; the GPU tests then fail instead of skipping (CI sets it).
//! `WGPU_BACKEND` picks the wgpu backends (default: Vulkan, Metal, DX12).
//! `--adapter` or **`RIGFIT_ADAPTER`** picks the adapter among them (index,
//! PCI bus id or a piece of the name, as `rigfit devices` lists them); Vulkan
//! does not honour `CUDA_VISIBLE_DEVICES`.

mod by_drive;
mod context;
mod dispatch;
mod evaluator;
mod fitness_pass;
mod history_pass;
pub mod layout;
mod pack;
pub mod pipeline;
mod probe;
mod run_buffers;
pub mod shaders;
pub mod specialise;

pub use by_drive::{GpuByDrive, KernelGroup, kernel_groups};
pub use context::{
    ADAPTER_ENV, AdapterChoice, AdapterSummary, GpuContext, adapter_list, choose_adapter, instance,
    list_adapters, requested_adapter,
};
pub use evaluator::{GpuEvaluator, GpuOptions};
pub use pack::{from_real_bytes, real_size, to_real_bytes};
pub use probe::{Probed, probe_exp, probe_math};
pub use shaders::Threads;

use crate::eval::{Backend, CpuEvaluator, Precision, PrecisionChoice, Problem, Scores, Timed};
use crate::model::GpuModel;

/// f32 histories agree with the f64 CPU reference within this fraction of the
/// history's largest magnitude (measured in `tests/gpu_cpu_parity.rs`).
pub const F32_HISTORY_TOLERANCE: f64 = 2e-4;
/// f64 histories agree with the f64 CPU reference within this fraction of the
/// history's largest magnitude.
pub const F64_HISTORY_TOLERANCE: f64 = 1e-9;

/// Name of the environment variable that makes a missing adapter an error.
pub const REQUIRE_GPU_ENV: &str = "RIGFIT_REQUIRE_GPU";

/// Errors of the GPU path.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter was found.
    #[error("no GPU adapter found ({0})")]
    NoAdapter(String),
    /// `--adapter` or `RIGFIT_ADAPTER` names no single adapter.
    #[error("{selected_by}: {why}; the adapters are: {adapters}")]
    NoSuchAdapter {
        /// The flag or variable and its value.
        selected_by: String,
        /// Why it matches none (or several).
        why: String,
        /// The adapters, as `rigfit devices` lists them.
        adapters: String,
    },
    /// The adapter refused a device.
    #[error("could not open a device: {0}")]
    RequestDevice(String),
    /// f64 was asked for on an adapter without `SHADER_F64`.
    #[error("adapter {0} has no SHADER_F64; use precision f32")]
    NoF64(String),
    /// The model has no GPU kernels.
    #[error("model `{0}` has no GPU implementation")]
    UnsupportedModel(String),
    /// The rig has more located switches than the kernels hold.
    #[error(
        "rig `{rig}` has {count} located switches in its {mode} drive mode; the GPU kernels \
         hold at most {limit}"
    )]
    TooManySwitches {
        /// The rig's id.
        rig: String,
        /// The drive mode (`velocity`, `force`).
        mode: String,
        /// Its located switches.
        count: usize,
        /// [`crate::compile::back::wgsl::MAX_SWITCHES`].
        limit: usize,
    },
    /// One [`GpuEvaluator`] was asked to score experiments that need
    /// different kernels of a rig (velocity and force drives of a compiled
    /// rig); [`GpuByDrive`] (what [`open_evaluator`] opens) takes them.
    #[error(
        "rig `{0}` runs its drive modes in separate GPU kernels; one GpuEvaluator takes experiments of one drive mode (GpuByDrive takes a mix)"
    )]
    MixedDrives(String),
    /// A shader failed to parse or validate.
    #[error("shader {kernel} is invalid:\n{message}")]
    Shader {
        /// Kernel file.
        kernel: &'static str,
        /// naga's diagnostic.
        message: String,
    },
    /// The device reported an error.
    #[error("GPU error during {during}: {message}")]
    Device {
        /// What was being done.
        during: String,
        /// wgpu's message.
        message: String,
    },
    /// The cancel flag was raised while a pass was in flight.
    #[error("evaluation cancelled by an interrupt")]
    Cancelled,
    /// The batch needs more workgroups or buffer space than the device allows.
    #[error("{runs} runs exceed the device's limit of {max} runs per pass")]
    TooLarge {
        /// Runs asked for.
        runs: usize,
        /// Most runs one dispatch covers.
        max: usize,
    },
}

/// The kernels that run `problem` in one [`GpuEvaluator`]: its model's GPU
/// plug-in, the same for every experiment. A problem whose experiments need
/// several ([`kernel_groups`]) gets [`GpuError::MixedDrives`]; whether the GPU
/// can run a problem at all is [`kernel_groups`]`(…).is_ok()`.
pub fn gpu_model(problem: &Problem) -> Result<GpuModel, GpuError> {
    let id = problem.model.id().to_string();
    let mut found: Option<GpuModel> = None;
    for e in 0..problem.experiments.len() {
        let g = kernels_for(problem, e)?;
        match &found {
            Some(f) if !std::sync::Arc::ptr_eq(f, &g) => return Err(GpuError::MixedDrives(id)),
            Some(_) => {}
            None => found = Some(g),
        }
    }
    found.ok_or(GpuError::UnsupportedModel(id))
}

/// The kernels that score experiment `e` of `problem` (its rig for its drive,
/// compiled for its measured output: [`Problem::scoring_model`]), or why it
/// has none: more located switches than the kernels hold
/// ([`GpuError::TooManySwitches`]), or no kernels at all.
pub fn kernels_for(problem: &Problem, e: usize) -> Result<GpuModel, GpuError> {
    let model = &problem.scoring_model(e);
    let drive = &problem.experiments[e].drive;
    if let Some(g) = model.gpu(drive) {
        return Ok(g);
    }
    let program = model.program_for(drive).map(|i| &model.lowered.programs[i]);
    match program {
        Some(p) if p.transitions.len() > crate::compile::back::wgsl::MAX_SWITCHES => {
            Err(GpuError::TooManySwitches {
                rig: model.id().to_string(),
                mode: p.mode.to_string(),
                count: p.transitions.len(),
                limit: crate::compile::back::wgsl::MAX_SWITCHES,
            })
        }
        _ => Err(GpuError::UnsupportedModel(model.id().to_string())),
    }
}

/// Whether `RIGFIT_REQUIRE_GPU` is set to something other than `0`/empty.
pub fn gpu_required() -> bool {
    std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| !v.is_empty() && v != "0")
}

/// An opened evaluator with a note for the user (e.g. why `auto` fell back to
/// the CPU), to print once.
pub struct Opened {
    /// The evaluator, which `auto`'s trial can time.
    pub evaluator: Box<dyn Timed>,
    /// One line to tell the user, if any.
    pub note: Option<String>,
    /// Whether the evaluator runs on a discrete GPU (which runs tens of
    /// thousands of runs at once: [`underfilled`]).
    pub discrete_gpu: bool,
}

/// Runs per batch under which a discrete GPU is far from full: such a GPU
/// keeps tens of thousands of invocations resident (an NVIDIA H200: 132
/// multiprocessors of up to 2 048 threads), so a batch of fewer than this
/// many runs takes about as long as one this size.
pub const UNDERFILLED_RUNS: usize = 8192;

/// What to tell a job on a discrete GPU whose batches of `runs` runs
/// (`population` candidates × `experiments`) leave it far from full
/// ([`UNDERFILLED_RUNS`]); `None` where they do not.
pub fn underfilled(population: usize, experiments: usize, device: &str) -> Option<String> {
    let runs = population * experiments;
    (runs < UNDERFILLED_RUNS).then(|| {
        format!(
            "{runs} runs per generation (population {population} × {experiments} \
             experiment{}) fill a small part of {device}, which runs tens of thousands at \
             once: a population up to about {} would cost little more time per generation there",
            if experiments == 1 { "" } else { "s" },
            UNDERFILLED_RUNS / experiments.max(1)
        )
    })
}

impl std::fmt::Debug for Opened {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Opened")
            .field("evaluator", &self.evaluator.info())
            .field("note", &self.note)
            .field("discrete_gpu", &self.discrete_gpu)
            .finish()
    }
}

/// The candidates whose histories to write out: `which`, with the best
/// candidate of `scores` (lowest weighted sum over experiments, weights from
/// `problem`) put first when it is not already there.
pub fn with_best(problem: &Problem, scores: &Scores, which: &[usize]) -> Vec<usize> {
    let ne = scores.experiments.max(1);
    let weights = problem.relative_weights();
    let joint = |i: usize| -> f64 { (0..ne).map(|e| weights[e] * scores.get(i, e)).sum() };
    let best = (0..scores.values.len() / ne).min_by(|&a, &b| joint(a).total_cmp(&joint(b)));
    let mut out = Vec::with_capacity(which.len() + 1);
    if let Some(b) = best.filter(|b| !which.contains(b)) {
        out.push(b);
    }
    out.extend_from_slice(which);
    out
}

/// Resolves a precision choice against a context.
pub fn resolve_precision(ctx: &GpuContext, choice: PrecisionChoice) -> Result<Precision, GpuError> {
    match choice {
        PrecisionChoice::F32 => Ok(Precision::F32),
        PrecisionChoice::F64 if !ctx.has_f64() => Err(GpuError::NoF64(ctx.describe())),
        PrecisionChoice::F64 => Ok(Precision::F64),
        PrecisionChoice::Auto if ctx.has_f64() => Ok(Precision::F64),
        PrecisionChoice::Auto => Ok(Precision::F32),
    }
}

/// Opens the evaluator for `backend`: `cpu` → the f64 reference on all cores;
/// `gpu` → the GPU or an error; `auto` → the GPU when an adapter exists (and the
/// model has GPU kernels), otherwise the CPU with a note — unless
/// `RIGFIT_REQUIRE_GPU=1`, which makes a missing adapter an error. Experiments
/// that need different kernels (drive modes of a compiled rig) are scored by a
/// [`GpuByDrive`], one pipeline per kernel group.
pub fn open_evaluator(
    problem: Problem,
    backend: Backend,
    precision: PrecisionChoice,
) -> Result<Opened, GpuError> {
    open_evaluator_on(problem, backend, precision, None)
}

/// [`open_evaluator`] on the adapter `adapter` (`--adapter`) or else
/// `RIGFIT_ADAPTER` names ([`GpuContext::select`]); a selector that names no
/// adapter is an error even for `auto`. The evaluator's device description
/// (result.json's `device`) names the adapter chosen and how.
pub fn open_evaluator_on(
    problem: Problem,
    backend: Backend,
    precision: PrecisionChoice,
    adapter: Option<&str>,
) -> Result<Opened, GpuError> {
    let cpu = |problem: Problem, note: Option<String>| Opened {
        evaluator: Box::new(CpuEvaluator::new(problem, 0)),
        note,
        discrete_gpu: false,
    };
    if backend == Backend::Cpu {
        return Ok(cpu(problem, None));
    }
    if backend == Backend::Auto
        && let Err(e) = kernel_groups(&problem)
    {
        return Ok(cpu(problem, Some(format!("{e}; using the CPU"))));
    }
    let ctx = match GpuContext::select(adapter) {
        Ok(found) => found,
        Err(e @ GpuError::NoSuchAdapter { .. }) => return Err(e),
        Err(e) if backend == Backend::Auto && !gpu_required() => {
            return Ok(cpu(problem, Some(format!("{e}; using the CPU"))));
        }
        Err(e) => return Err(e),
    };
    let discrete_gpu = ctx.info.device_type == wgpu::DeviceType::DiscreteGpu;
    Ok(Opened {
        evaluator: evaluator_on_context(ctx, problem, precision)?,
        note: None,
        discrete_gpu,
    })
}

/// The GPU evaluator of `problem` on a device already opened: the jobs of a
/// series share one ([`crate::series`]); [`open_evaluator_on`] opens its own.
pub fn evaluator_on_context(
    ctx: GpuContext,
    problem: Problem,
    precision: PrecisionChoice,
) -> Result<Box<dyn Timed>, GpuError> {
    let precision = resolve_precision(&ctx, precision)?;
    let evaluator: Box<dyn Timed> = if kernel_groups(&problem)?.len() > 1 {
        Box::new(GpuByDrive::new(
            ctx,
            problem,
            precision,
            GpuOptions::default(),
        )?)
    } else {
        Box::new(GpuEvaluator::new(
            ctx,
            problem,
            precision,
            GpuOptions::default(),
        )?)
    };
    Ok(evaluator)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_generation_on_a_discrete_gpu_is_said_to_leave_it_far_from_full() {
        let note = underfilled(128, 1, "NVIDIA H200 (Vulkan, DiscreteGpu)").unwrap();
        assert!(
            note.starts_with("128 runs per generation (population 128 × 1 experiment)"),
            "{note}"
        );
        assert!(
            note.contains("NVIDIA H200") && note.contains("about 8192"),
            "{note}"
        );
        // Runs count every experiment.
        let note = underfilled(1024, 4, "a GPU").unwrap();
        assert!(
            note.contains("4096 runs") && note.contains("4 experiments"),
            "{note}"
        );
        assert!(note.contains("about 2048"), "{note}");
        assert_eq!(underfilled(2048, 4, "a GPU"), None);
        assert_eq!(underfilled(UNDERFILLED_RUNS, 1, "a GPU"), None);
    }
}
