//! The GPU evaluator: pipelines and buffers built once, reused every generation.
//!
//! A fitness pass is submitted chunk by chunk (each chunk advances every run by
//! [`GpuOptions::chunk_steps`] steps), at most two chunks in flight, and the
//! cancel flag is read before each chunk is submitted: an interrupt ends the
//! pass within two chunks. A batch larger than one dispatch covers (the
//! device's workgroup count, or the largest storage binding) is split into
//! parts, each bound to its own slice of the run buffers; every run computes
//! the same bits as in an unsplit pass.
//!
//! The run buffers and their parts are in `run_buffers.rs`, the chunked
//! dispatch in `dispatch.rs`, the fitness pass in `fitness_pass.rs` and the
//! history pass in `history_pass.rs`.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use crate::base::Drive;
use crate::eval::{
    Batch, EvalError, Evaluator, EvaluatorInfo, History, Precision, Problem, Scores, Timed,
};
use crate::model::GpuModel;

use super::fitness_pass::Specialised;
use super::pack::{PackedProblem, pack_problem, real_size, to_real_bytes};
use super::pipeline::{self, Binding, Kernelled, Pending, Prepared};
use super::run_buffers::RunBuffers;
use super::shaders::{Kernel, ProblemShape, RECORD_BINDING, Threads};
use super::specialise;
use super::{GpuContext, GpuError};

/// Tuning of the GPU evaluator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpuOptions {
    /// RK4 steps each invocation advances per dispatch. Long runs are split into
    /// several dispatches (all in one submit) so that no single dispatch runs long
    /// enough to trip a display driver's watchdog. Rounded up to whole blocks of
    /// the run loop (32 samples of `substeps` steps each).
    pub chunk_steps: u32,
    /// Bake the per-run values that are the same in every run of a batch into
    /// the fitness kernel (see `specialise.rs`); batches of fewer than
    /// [`specialise::MIN_RUNS`] runs always use the generic kernel.
    pub specialise: bool,
    /// At most this many runs per dispatch, below what the device allows
    /// (`None`: the device's limits alone). Tests set a small value so that
    /// the split path runs on any adapter.
    pub max_runs_per_pass: Option<usize>,
    /// Let the compiled rigs' fitness kernel read the measured values and the
    /// tables from a uniform-buffer copy of them where they fit the device's uniform
    /// binding (see [`super::shaders::datum_fn`]); `false` reads them from
    /// the storage buffer, as a longer record does. The same bits either way.
    pub uniform_record: bool,
    /// The fitness kernel's workgroup size and vote groups (see
    /// [`Threads`]: the same fitness with any, to within the kernels'
    /// tolerance).
    pub threads: Threads,
    /// Keep wgpu's runtime checks in the kernels (the default): an index into
    /// an array in function memory clamped, every loop bounded by a trip
    /// counter. `false` compiles the kernels with none
    /// ([`wgpu::Device::create_shader_module_trusted`]), for speed alone: the
    /// kernels index their arrays within bounds and end every loop by
    /// construction (`docs/engineering/kernels.md`, "Unsafe code"), and
    /// storage and uniform reads stay inside their buffers by the device's
    /// robust buffer access either way. The same bits either way
    /// (`tests/gpu_uniform_record.rs`).
    pub runtime_checks: bool,
}

impl Default for GpuOptions {
    fn default() -> Self {
        Self {
            chunk_steps: 2048,
            specialise: true,
            max_runs_per_pass: None,
            uniform_record: true,
            threads: Threads::default(),
            runtime_checks: true,
        }
    }
}

/// Bindings 0–6 of every ensemble kernel (`shared/bindings.wgsl`: settings,
/// experiments, params, data, state, progress and the kernel's output), then
/// the kernel's own binding 7.
const fn ensemble_bindings(last: Binding) -> [Binding; 8] {
    [
        Binding::Uniform,
        Binding::Read,
        Binding::Read,
        Binding::Read,
        Binding::ReadWrite,
        Binding::ReadWrite,
        Binding::ReadWrite,
        last,
    ]
}

/// Bindings of the fitness kernel: `fitness` as its output, then `record` at
/// [`RECORD_BINDING`], which only the compiled rigs' kernel reads.
const FITNESS_BINDINGS: [Binding; 8] = ensemble_bindings(Binding::Uniform);
const _: () = assert!(RECORD_BINDING as usize == FITNESS_BINDINGS.len() - 1);

/// Bindings of the history kernel: `history` as its output, then
/// `selection`; explicit, as a rig without tables never reads `data`.
const HISTORY_BINDINGS: [Binding; 8] = ensemble_bindings(Binding::Read);

/// Scores candidates with the ensemble kernels of `shaders/`.
#[derive(Debug)]
pub struct GpuEvaluator {
    pub(super) ctx: GpuContext,
    pub(super) problem: Problem,
    pub(super) packed: PackedProblem,
    pub(super) model: GpuModel,
    pub(super) precision: Precision,
    pub(super) options: GpuOptions,
    pub(super) shape: ProblemShape,
    pub(super) fitness_layout: pipeline::Layout,
    /// The generic fitness kernel, validated; compiled into `fitness_kernel`
    /// when a batch first needs it.
    pub(super) fitness_generic: Prepared,
    pub(super) fitness_kernel: Option<Kernelled>,
    /// Specialised fitness kernels built so far, oldest first.
    pub(super) specialised: Vec<Specialised>,
    /// The one that scored the last batch.
    pub(super) last_specialised: Option<usize>,
    pub(super) history_layout: pipeline::Layout,
    pub(super) history_kernel: Pending,
    pub(super) experiments: wgpu::Buffer,
    pub(super) data: wgpu::Buffer,
    /// The uniform copy of `data` the compiled rigs' fitness kernel reads
    /// (`shape.record_vec4s`), or 16 bytes that no kernel reads.
    pub(super) record: wgpu::Buffer,
    pub(super) runs: Option<RunBuffers>,
    pub(super) host: Vec<f64>,
    pub(super) cancel: Option<Arc<AtomicBool>>,
}

impl GpuEvaluator {
    /// Builds the pipelines and the problem's buffers on `ctx`.
    pub fn new(
        ctx: GpuContext,
        problem: Problem,
        precision: Precision,
        options: GpuOptions,
    ) -> Result<Self, GpuError> {
        let model = super::gpu_model(&problem)?;
        if let Some(why) = options.threads.refusal() {
            return Err(GpuError::Device {
                during: "choosing the fitness kernel's threads".into(),
                message: why,
            });
        }
        if precision == Precision::F64 && !ctx.has_f64() {
            return Err(GpuError::NoF64(ctx.describe()));
        }
        let force = problem
            .experiments
            .iter()
            .any(|e| matches!(e.drive, Drive::Force(_)));
        let packed = pack_problem(&problem, &model);
        let shape = ProblemShape {
            force_drive: force,
            record_vec4s: record_vec4s(&ctx, &packed, precision, options),
            exact_tables: exact_tables(&problem, &model),
            threads: options.threads,
            trusted: !options.runtime_checks,
        };
        // Each kernel on an explicit layout, so that its specialised variants
        // share one bind group with it. Both are validated here; the generic
        // fitness kernel is compiled where a batch first needs it (a
        // calibration's batches take specialised ones), the history kernel on
        // a thread of its own while the search begins.
        let prepare =
            |kernel: Kernel| pipeline::prepare(Some((&model, shape, &[])), precision, kernel);
        let fitness_generic = prepare(Kernel::Fitness)?;
        let fitness_layout = pipeline::layout(&ctx, "fitness layout", &FITNESS_BINDINGS);
        let history_layout = pipeline::layout(&ctx, "history layout", &HISTORY_BINDINGS);
        let history_kernel = Pending::spawn(&ctx, prepare(Kernel::History)?, &history_layout);
        let (experiments, data, record) = pipeline::scoped(&ctx, "problem buffers", || {
            // Zero-padded to whole vec4s; 16 bytes where no kernel reads it.
            let mut copy = match shape.record_vec4s {
                Some(_) => packed.data.clone(),
                None => vec![],
            };
            copy.resize(4 * shape.record_vec4s.unwrap_or(1) as usize, 0.0);
            (
                pipeline::storage_init(
                    &ctx,
                    "experiments",
                    bytemuck::cast_slice(&packed.experiments),
                    false,
                ),
                pipeline::storage_init(
                    &ctx,
                    "measured data",
                    &to_real_bytes(&packed.data, precision),
                    false,
                ),
                pipeline::uniform_init(
                    &ctx,
                    "measured data (uniform copy)",
                    &to_real_bytes(&copy, precision),
                ),
            )
        })?;
        Ok(Self {
            ctx,
            problem,
            packed,
            model,
            precision,
            options,
            shape,
            fitness_layout,
            fitness_generic,
            fitness_kernel: None,
            specialised: Vec::new(),
            last_specialised: None,
            history_layout,
            history_kernel,
            experiments,
            data,
            record,
            runs: None,
            host: Vec::new(),
            cancel: None,
        })
    }

    /// The device context.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Whether the fitness kernels read the measured values from their
    /// uniform copy ([`GpuOptions::uniform_record`]) rather than from the
    /// storage buffer.
    pub fn record_in_uniform(&self) -> bool {
        self.shape.record_vec4s.is_some()
    }

    /// Whether the kernels were built with every table on an exactly uniform
    /// grid ([`ProblemShape::exact_tables`]): lookups without a search.
    pub fn tables_exact(&self) -> bool {
        self.shape.exact_tables
    }

    /// How many per-run values the kernel that scored the last batch had baked
    /// in; `None` when the generic kernel scored it.
    pub fn specialised_constants(&self) -> Option<usize> {
        self.last_specialised
            .map(|i| specialise::count(&self.specialised[i].baked))
    }

    /// The WGSL of the fitness kernel that scored the last batch (the generic
    /// kernel's before any batch), with whether it was compiled without
    /// wgpu's runtime checks ([`GpuOptions::runtime_checks`]): what the
    /// driver compiled, for tools that read the driver's statistics of it.
    pub fn fitness_source(&self) -> (String, bool) {
        let src = match self.last_specialised {
            Some(i) => super::shaders::source(
                &self.model,
                self.precision,
                Kernel::Fitness,
                self.shape,
                &self.specialised[i].baked,
            ),
            None => self.fitness_generic.source().to_string(),
        };
        (src, self.shape.trusted)
    }

    /// The runs per dispatch of the batches scored so far (for tests and
    /// reports): `None` before the first batch.
    pub fn runs_per_pass_in_use(&self) -> Option<usize> {
        self.runs.as_ref().map(|r| r.per_pass)
    }

    /// Per-run values of the parameter buffer.
    pub(super) fn stride(&self) -> u64 {
        super::layout::run_stride(self.model.slot_names().len()) as u64
    }
}

/// The description every GPU evaluator gives of itself.
pub(super) fn gpu_info(ctx: &GpuContext, precision: Precision) -> EvaluatorInfo {
    EvaluatorInfo {
        backend: "gpu".into(),
        device: ctx.describe(),
        precision,
    }
}

fn device_error(e: GpuError) -> EvalError {
    match e {
        GpuError::Cancelled => EvalError::Cancelled,
        e => EvalError::Device(e.to_string()),
    }
}

/// The vec4s of the uniform copy of the measured data: `None` when `options`
/// turn it off, or when the data do not fit the device's largest uniform
/// binding.
fn record_vec4s(
    ctx: &GpuContext,
    packed: &PackedProblem,
    precision: Precision,
    options: GpuOptions,
) -> Option<u32> {
    if !options.uniform_record {
        return None;
    }
    let n = packed.data.len().div_ceil(4).max(1) as u64;
    let fits = n * 4 * real_size(precision) <= ctx.device.limits().max_uniform_buffer_binding_size;
    (fits && n <= u64::from(u32::MAX)).then_some(n as u32)
}

impl Evaluator for GpuEvaluator {
    fn info(&self) -> EvaluatorInfo {
        gpu_info(&self.ctx, self.precision)
    }

    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        self.problem.check_batch(batch)?;
        let raw = self.run_fitness(batch).map_err(device_error)?;
        self.scores(raw)
    }

    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        if which.is_empty() {
            return Ok(Vec::new());
        }
        self.run_histories(batch, which).map_err(device_error)
    }

    fn checked_scored_outputs(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, EvalError> {
        if which.is_empty() {
            return Ok(Vec::new());
        }
        self.run_scored(batch, which).map_err(device_error)
    }

    fn set_cancel(&mut self, flag: Arc<AtomicBool>) {
        self.cancel = Some(flag);
    }

    fn problem(&self) -> &Problem {
        &self.problem
    }
}

impl Timed for GpuEvaluator {
    /// The batch's first chunk alone ([`Timed::fitness_part`] of one step).
    fn warm_up(&mut self, batch: &Batch) -> Result<(), EvalError> {
        self.fitness_part(batch, 1).map(|_| ())
    }

    fn fitness_part(&mut self, batch: &Batch, steps: usize) -> Result<Option<usize>, EvalError> {
        self.problem.check_batch(batch)?;
        self.part_fitness(batch, steps)
            .map(Some)
            .map_err(device_error)
    }

    fn kernel_variants(&self) -> &'static [&'static str] {
        crate::eval::KERNEL_VARIANTS
    }

    fn use_kernel_variant(&mut self, variant: &str) {
        match variant {
            "specialised" => self.options.specialise = true,
            "generic" => self.options.specialise = false,
            _ => {}
        }
    }
}

/// Whether every table the kernels read lies on an exactly uniform grid: the
/// experiments' drive tables and the rig file's own (their headers in the
/// model's table data).
fn exact_tables(problem: &Problem, model: &crate::model::GpuModel) -> bool {
    let drives = problem.experiments.iter().all(|e| match &e.drive {
        Drive::Force(t) => t.kernel_header() > 0.0,
        Drive::Velocity => true,
    });
    drives && model.inline_table_headers().all(|h| h > 0.0)
}
