//! The GPU evaluator: pipelines and buffers built once, reused every generation.
//!
//! A fitness pass is submitted chunk by chunk (each chunk advances every run by
//! [`GpuOptions::chunk_steps`] steps), at most two chunks in flight, and the
//! cancel flag is read before each chunk is submitted: an interrupt ends the
//! pass within two chunks. A batch larger than one dispatch covers (the
//! device's workgroup count, or the largest storage binding) is split into
//! parts, each bound to its own slice of the run buffers; every run computes
//! the same bits as in an unsplit pass.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::base::Drive;
use crate::eval::{
    Batch, DIVERGED, EvalError, Evaluator, EvaluatorInfo, History, Precision, Problem, Scores,
};
use crate::model::GpuModel;

use super::layout::{BLOCK_SAMPLES, Settings};
use super::pack::{
    PackedProblem, from_real_bytes, pack_problem, pack_runs, real_size, to_real_bytes,
};
use super::pipeline::{self, Binding, Kernelled};
use super::shaders::{Kernel, ProblemShape, RECORD_BINDING};
use super::specialise;
use super::{GpuContext, GpuError};

/// Fitness-buffer value of a run that has not finished (the kernel writes ≥ 0,
/// or -1 for a diverged run).
const UNFINISHED: f64 = -2.0;

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
    /// Let the compiled rigs' fitness kernel read the measured values from a
    /// uniform-buffer copy of them where they fit the device's uniform
    /// binding (see [`super::shaders::record_fn`]); `false` reads them from
    /// the storage buffer, as a longer record does. The same bits either way.
    pub uniform_record: bool,
}

impl Default for GpuOptions {
    fn default() -> Self {
        Self {
            chunk_steps: 2048,
            specialise: true,
            max_runs_per_pass: None,
            uniform_record: true,
        }
    }
}

/// Bindings of the fitness kernel (`shared/bindings.wgsl`, then `fitness`,
/// then `record` at [`RECORD_BINDING`], which only the compiled rigs' kernel
/// reads).
const FITNESS_BINDINGS: [Binding; 8] = [
    Binding::Uniform,
    Binding::Read,
    Binding::Read,
    Binding::Read,
    Binding::ReadWrite,
    Binding::ReadWrite,
    Binding::ReadWrite,
    Binding::Uniform,
];
const _: () = assert!(RECORD_BINDING as usize == FITNESS_BINDINGS.len() - 1);

/// Bindings of the history kernel (`shared/bindings.wgsl`, then `history`,
/// `selection`): explicit, as a rig without tables never reads `data`.
const HISTORY_BINDINGS: [Binding; 8] = [
    Binding::Uniform,
    Binding::Read,
    Binding::Read,
    Binding::Read,
    Binding::ReadWrite,
    Binding::ReadWrite,
    Binding::ReadWrite,
    Binding::Read,
];

/// A fitness kernel with the values it has baked in.
#[derive(Debug)]
struct Specialised {
    baked: Vec<Option<f64>>,
    kernel: Kernelled,
}

/// One dispatch's share of the run buffers: runs `first..first + per_pass`,
/// with its own settings (its run count) and a bind group over its slices.
#[derive(Debug)]
struct Part {
    first: usize,
    settings: wgpu::Buffer,
    bind: wgpu::BindGroup,
}

/// Buffers sized for a number of runs; grown when a batch needs more.
#[derive(Debug)]
struct RunBuffers {
    capacity: usize,
    params: wgpu::Buffer,
    state: wgpu::Buffer,
    progress: wgpu::Buffer,
    fitness: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Runs per part (a multiple of the experiments per candidate).
    per_pass: usize,
    parts: Vec<Part>,
}

/// Scores candidates with the ensemble kernels of `shaders/`.
#[derive(Debug)]
pub struct GpuEvaluator {
    ctx: GpuContext,
    problem: Problem,
    packed: PackedProblem,
    model: GpuModel,
    precision: Precision,
    options: GpuOptions,
    shape: ProblemShape,
    fitness_layout: pipeline::Layout,
    fitness_kernel: Kernelled,
    /// Specialised fitness kernels built so far, oldest first.
    specialised: Vec<Specialised>,
    /// The one that scored the last batch.
    last_specialised: Option<usize>,
    history_layout: pipeline::Layout,
    history_kernel: Kernelled,
    experiments: wgpu::Buffer,
    data: wgpu::Buffer,
    /// The uniform copy of `data` the compiled rigs' fitness kernel reads
    /// (`shape.record_vec4s`), or 16 bytes that no kernel reads.
    record: wgpu::Buffer,
    runs: Option<RunBuffers>,
    host: Vec<f64>,
    cancel: Option<Arc<AtomicBool>>,
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
        };
        let fitness_layout = pipeline::layout(&ctx, "fitness layout", &FITNESS_BINDINGS);
        let fitness_kernel = pipeline::build(
            &ctx,
            Some((&model, shape, &[])),
            precision,
            Kernel::Fitness,
            Some(&fitness_layout),
        )?;
        let history_layout = pipeline::layout(&ctx, "history layout", &HISTORY_BINDINGS);
        let history_kernel = pipeline::build(
            &ctx,
            Some((&model, shape, &[])),
            precision,
            Kernel::History,
            Some(&history_layout),
        )?;
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
            fitness_kernel,
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

    /// The problem being scored.
    pub fn problem(&self) -> &Problem {
        &self.problem
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

    /// How many per-run values the kernel that scored the last batch had baked
    /// in; `None` when the generic kernel scored it.
    pub fn specialised_constants(&self) -> Option<usize> {
        self.last_specialised
            .map(|i| specialise::count(&self.specialised[i].baked))
    }

    fn stride(&self) -> u64 {
        super::layout::run_stride(self.model.slot_names().len()) as u64
    }

    /// Makes room for `runs` runs and uploads the batch's parameters; returns
    /// the largest step count of any run.
    fn upload(&mut self, batch: &Batch) -> Result<usize, GpuError> {
        let runs = batch.candidates * self.problem.experiments.len();
        if self.runs.as_ref().is_none_or(|r| r.capacity < runs) {
            let most = self.most_runs();
            if runs > most {
                return Err(GpuError::TooLarge { runs, max: most });
            }
            self.runs = Some(self.allocate(runs.next_power_of_two().min(most))?);
        }
        let max_steps = pack_runs(
            &self.problem,
            &self.packed,
            &self.model,
            batch,
            &mut self.host,
        );
        let bytes = to_real_bytes(&self.host, self.precision);
        let rb = self.runs.as_ref().expect("allocated above");
        self.ctx.queue.write_buffer(&rb.params, 0, &bytes);
        Ok(max_steps)
    }

    /// Bytes per run of each run buffer: parameters, state, progress, fitness.
    fn run_bytes(&self) -> [u64; 4] {
        let real = real_size(self.precision);
        [
            self.stride() * real,
            self.model.state_stride() as u64 * real,
            16,
            real,
        ]
    }

    /// Most runs one batch can hold: the device's largest buffer.
    fn most_runs(&self) -> usize {
        let widest = self.run_bytes().into_iter().max().unwrap_or(16);
        (self.ctx.device.limits().max_buffer_size / widest) as usize
    }

    /// Runs per dispatch: what the device's workgroup count and largest
    /// storage binding allow (and [`GpuOptions::max_runs_per_pass`]), rounded
    /// down to a multiple of the experiments per candidate (so that a part
    /// starts at a candidate's first run) and of the storage offset alignment
    /// (so that every slice may be bound). 0 when no such number fits.
    fn runs_per_pass(&self) -> usize {
        let limits = self.ctx.device.limits();
        let groups = limits.max_compute_workgroups_per_dimension as usize;
        let widest = self.run_bytes().into_iter().max().unwrap_or(16);
        let mut n = (groups * self.fitness_kernel.workgroup_x as usize)
            .min((limits.max_storage_buffer_binding_size / widest) as usize);
        if let Some(m) = self.options.max_runs_per_pass {
            n = n.min(m);
        }
        let ne = self.problem.experiments.len().max(1);
        let align = limits.min_storage_buffer_offset_alignment.max(1) as usize;
        let unit = ne / gcd(ne, align) * align;
        n / unit * unit
    }

    fn allocate(&self, capacity: usize) -> Result<RunBuffers, GpuError> {
        let ctx = &self.ctx;
        let real = real_size(self.precision);
        let n = capacity as u64;
        // With no aligned part size below the limits, one part: the pass
        // then refuses what one dispatch cannot cover.
        let per_pass = match self.runs_per_pass() {
            0 => capacity,
            p => p,
        };
        let parts = capacity.div_ceil(per_pass);
        use wgpu::BufferUsages as U;
        pipeline::scoped(ctx, "run buffers", || {
            let params = pipeline::buffer(
                ctx,
                "run params",
                n * self.stride() * real,
                U::STORAGE | U::COPY_DST,
            );
            let state = pipeline::buffer(
                ctx,
                "run state",
                n * self.model.state_stride() as u64 * real,
                U::STORAGE | U::COPY_DST,
            );
            let progress = pipeline::buffer(ctx, "run progress", n * 16, U::STORAGE | U::COPY_DST);
            let fitness = pipeline::buffer(
                ctx,
                "fitness",
                n * real,
                U::STORAGE | U::COPY_SRC | U::COPY_DST,
            );
            let readback = pipeline::buffer(
                ctx,
                "fitness read-back",
                n * real,
                U::MAP_READ | U::COPY_DST,
            );
            let bytes = self.run_bytes();
            let parts = (0..parts)
                .map(|k| {
                    let first = k * per_pass;
                    let count = per_pass.min(capacity - first) as u64;
                    let settings = pipeline::buffer(
                        ctx,
                        "fitness settings",
                        size_of::<Settings>() as u64,
                        U::UNIFORM | U::COPY_DST,
                    );
                    fn slice(
                        b: &wgpu::Buffer,
                        first: u64,
                        count: u64,
                        bytes: u64,
                    ) -> wgpu::BufferBinding<'_> {
                        wgpu::BufferBinding {
                            buffer: b,
                            offset: first * bytes,
                            size: wgpu::BufferSize::new(count * bytes),
                        }
                    }
                    let f = first as u64;
                    let whole = wgpu::Buffer::as_entire_buffer_binding;
                    let bindings = [
                        whole(&settings),
                        whole(&self.experiments),
                        slice(&params, f, count, bytes[0]),
                        whole(&self.data),
                        slice(&state, f, count, bytes[1]),
                        slice(&progress, f, count, bytes[2]),
                        slice(&fitness, f, count, bytes[3]),
                        whole(&self.record),
                    ];
                    let entries: Vec<wgpu::BindGroupEntry<'_>> = bindings
                        .into_iter()
                        .enumerate()
                        .map(|(i, b)| wgpu::BindGroupEntry {
                            binding: i as u32,
                            resource: wgpu::BindingResource::Buffer(b),
                        })
                        .collect();
                    let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("fitness bind group"),
                        layout: &self.fitness_layout.group,
                        entries: &entries,
                    });
                    Part {
                        first,
                        settings,
                        bind,
                    }
                })
                .collect();
            RunBuffers {
                capacity,
                params,
                state,
                progress,
                fitness,
                readback,
                per_pass,
                parts,
            }
        })
    }

    /// Whether the flag given to [`Evaluator::set_cancel`] is raised.
    fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// Blocks until `submission` (or everything submitted) has run.
    fn wait(&self, submission: Option<wgpu::SubmissionIndex>) -> Result<(), GpuError> {
        self.ctx
            .device
            .poll(wgpu::PollType::Wait {
                submission_index: submission,
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| GpuError::Device {
                during: "waiting for the GPU".into(),
                message: e.to_string(),
            })
    }

    /// Steps per dispatch: `options.chunk_steps` rounded up to whole blocks of
    /// [`BLOCK_SAMPLES`] samples, so that no block of the run loop outlasts its
    /// chunk's budget with every lane idle.
    fn chunk_steps(&self) -> u32 {
        let block = BLOCK_SAMPLES * self.problem.substeps as u32;
        self.options.chunk_steps.max(1).div_ceil(block) * block
    }

    /// Number of dispatches that finish runs of up to `max_steps` steps.
    fn dispatches(&self, max_steps: usize) -> u32 {
        (max_steps.div_ceil(self.chunk_steps() as usize) + 1) as u32
    }

    /// Encodes the chunked dispatches of one pass into `encoder`.
    fn encode_pass(
        encoder: &mut wgpu::CommandEncoder,
        kernel: &Kernelled,
        bind: &wgpu::BindGroup,
        groups: u32,
        dispatches: u32,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("rk4 chunks"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&kernel.pipeline);
        pass.set_bind_group(0, bind, &[]);
        for _ in 0..dispatches {
            pass.dispatch_workgroups(groups, 1, 1);
        }
    }

    /// Which specialised kernel scores the batch just uploaded (an index into
    /// `specialised`, built first where needed), or `None` for the generic one.
    /// The kernel depends only on the batch, never on the batches before it,
    /// so the same batch always gets the same bits.
    fn specialise_for(&mut self, runs: usize) -> Result<Option<usize>, GpuError> {
        self.last_specialised = None;
        if !self.options.specialise || runs < specialise::MIN_RUNS {
            return Ok(None);
        }
        let stride = self.stride() as usize;
        let baked = specialise::constant_slots(&self.host, stride, self.precision);
        if let Some(i) = self
            .specialised
            .iter()
            .position(|s| specialise::same(&s.baked, &baked))
        {
            self.last_specialised = Some(i);
            return Ok(Some(i));
        }
        log::info!(
            "specialising the {} fitness kernel: {} of {stride} per-run values are the same in every run",
            super::shaders::real_type(self.precision),
            specialise::count(&baked)
        );
        let kernel = pipeline::build(
            &self.ctx,
            Some((&self.model, self.shape, &baked)),
            self.precision,
            Kernel::Fitness,
            Some(&self.fitness_layout),
        )?;
        if self.specialised.len() >= specialise::MAX_KERNELS {
            self.specialised.remove(0);
        }
        self.specialised.push(Specialised { baked, kernel });
        let i = self.specialised.len() - 1;
        self.last_specialised = Some(i);
        Ok(Some(i))
    }

    fn run_fitness(&mut self, batch: &Batch) -> Result<Vec<f64>, GpuError> {
        let max_steps = self.upload(batch)?;
        let runs = batch.candidates * self.problem.experiments.len();
        let kernel = match self.specialise_for(runs)? {
            Some(i) => &self.specialised[i].kernel,
            None => &self.fitness_kernel,
        };
        let dispatches = self.dispatches(max_steps);
        let rb = self.runs.as_ref().expect("uploaded");
        // The parts this batch uses, with their run counts and workgroups.
        let mut parts = Vec::new();
        for part in rb.parts.iter().take_while(|p| p.first < runs) {
            let count = rb.per_pass.min(runs - part.first);
            let groups = pipeline::workgroups(&self.ctx, count, kernel.workgroup_x)?;
            parts.push((part, count, groups));
        }
        let size = runs as u64 * real_size(self.precision);
        // A run that never reached its last sample would leave this sentinel.
        let unfinished = to_real_bytes(&vec![UNFINISHED; runs], self.precision);
        pipeline::scoped(&self.ctx, "fitness pass", || {
            for &(part, count, _) in &parts {
                let settings = Settings {
                    runs: count as u32,
                    experiments: self.problem.experiments.len() as u32,
                    chunk_steps: self.chunk_steps(),
                    hist_stride: 0,
                    substeps: self.problem.substeps as u32,
                    _pad: [0; 3],
                };
                self.ctx
                    .queue
                    .write_buffer(&part.settings, 0, bytemuck::bytes_of(&settings));
            }
            self.ctx.queue.write_buffer(&rb.fitness, 0, &unfinished);
            let mut enc = self
                .ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("fitness reset"),
                });
            enc.clear_buffer(&rb.state, 0, None);
            enc.clear_buffer(&rb.progress, 0, None);
            self.ctx.queue.submit([enc.finish()]);
        })?;
        // One submit per chunk, the next queued while one runs, so that the
        // device never waits for the host and an interrupt waits for at most
        // the chunk running and the one queued.
        let mut queued: Option<wgpu::SubmissionIndex> = None;
        for _ in 0..dispatches {
            if self.cancelled() {
                self.wait(None)?;
                return Err(GpuError::Cancelled);
            }
            let submitted = pipeline::scoped(&self.ctx, "fitness chunk", || {
                let mut enc =
                    self.ctx
                        .device
                        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                            label: Some("fitness chunk"),
                        });
                {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("rk4 chunk"),
                        timestamp_writes: None,
                    });
                    pass.set_pipeline(&kernel.pipeline);
                    for &(part, _, groups) in &parts {
                        pass.set_bind_group(0, &part.bind, &[]);
                        pass.dispatch_workgroups(groups, 1, 1);
                    }
                }
                self.ctx.queue.submit([enc.finish()])
            })?;
            if let Some(previous) = queued.replace(submitted) {
                self.wait(Some(previous))?;
            }
        }
        pipeline::scoped(&self.ctx, "fitness read-back", || {
            let mut enc = self
                .ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("fitness copy"),
                });
            enc.copy_buffer_to_buffer(&rb.fitness, 0, &rb.readback, 0, size);
            self.ctx.queue.submit([enc.finish()]);
        })?;
        let bytes = pipeline::read_back(&self.ctx, &rb.readback, size)?;
        Ok(from_real_bytes(&bytes, self.precision))
    }

    /// The runs per dispatch of the batches scored so far (for tests and
    /// reports): `None` before the first batch.
    pub fn runs_per_pass_in_use(&self) -> Option<usize> {
        self.runs.as_ref().map(|r| r.per_pass)
    }

    fn run_histories(&mut self, batch: &Batch, which: &[usize]) -> Result<Vec<f64>, GpuError> {
        let max_steps = self.upload(batch)?;
        let ne = self.problem.experiments.len();
        let runs = which.len() * ne;
        let groups = pipeline::workgroups(&self.ctx, runs, self.history_kernel.workgroup_x)?;
        let settings = Settings {
            runs: runs as u32,
            experiments: ne as u32,
            chunk_steps: self.chunk_steps(),
            hist_stride: self.packed.hist_stride,
            substeps: self.problem.substeps as u32,
            _pad: [0; 3],
        };
        let real = real_size(self.precision);
        let size = (which.len() * self.packed.hist_stride as usize) as u64
            * self.model.hist_values() as u64
            * real;
        let selection: Vec<u32> = which.iter().map(|&i| i as u32).collect();
        let dispatches = self.dispatches(max_steps);
        let ctx = &self.ctx;
        let rb = self.runs.as_ref().expect("uploaded");
        use wgpu::BufferUsages as U;
        let readback = pipeline::scoped(ctx, "history pass", || {
            let uniform = pipeline::buffer(
                ctx,
                "history settings",
                size_of::<Settings>() as u64,
                U::UNIFORM | U::COPY_DST,
            );
            ctx.queue
                .write_buffer(&uniform, 0, bytemuck::bytes_of(&settings));
            let state = pipeline::buffer(
                ctx,
                "history state",
                runs as u64 * self.model.state_stride() as u64 * real,
                U::STORAGE | U::COPY_DST,
            );
            let progress = pipeline::buffer(
                ctx,
                "history progress",
                runs as u64 * 16,
                U::STORAGE | U::COPY_DST,
            );
            let history = pipeline::buffer(ctx, "history", size, U::STORAGE | U::COPY_SRC);
            let readback =
                pipeline::buffer(ctx, "history read-back", size, U::MAP_READ | U::COPY_DST);
            let sel =
                pipeline::storage_init(ctx, "selection", bytemuck::cast_slice(&selection), false);
            let bind = pipeline::bind_with(
                ctx,
                "history bind group",
                &self.history_layout.group,
                &[
                    &uniform,
                    &self.experiments,
                    &rb.params,
                    &self.data,
                    &state,
                    &progress,
                    &history,
                    &sel,
                ],
            );
            let mut enc = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("history"),
                });
            enc.clear_buffer(&state, 0, None);
            enc.clear_buffer(&progress, 0, None);
            Self::encode_pass(&mut enc, &self.history_kernel, &bind, groups, dispatches);
            enc.copy_buffer_to_buffer(&history, 0, &readback, 0, size);
            ctx.queue.submit([enc.finish()]);
            readback
        })?;
        let bytes = pipeline::read_back(ctx, &readback, size)?;
        Ok(from_real_bytes(&bytes, self.precision))
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

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

impl Evaluator for GpuEvaluator {
    fn info(&self) -> EvaluatorInfo {
        EvaluatorInfo {
            backend: "gpu".into(),
            device: self.ctx.describe(),
            precision: self.precision,
        }
    }

    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        self.problem.check_batch(batch)?;
        let raw = self.run_fitness(batch).map_err(device_error)?;
        if let Some(j) = raw.iter().position(|&v| v == UNFINISHED) {
            return Err(EvalError::Device(format!(
                "run {j} did not finish (chunking bug or lost device)"
            )));
        }
        let mut diverged = 0;
        let values = raw
            .into_iter()
            .map(|v| {
                // -1 marks a blown-up run; NaN/Inf can only come from one.
                if (0.0..DIVERGED).contains(&v) {
                    v
                } else {
                    diverged += 1;
                    DIVERGED
                }
            })
            .collect();
        Ok(Scores {
            experiments: self.problem.experiments.len(),
            values,
            diverged,
        })
    }

    fn histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        self.problem.check_batch(batch)?;
        batch.check_indices(which)?;
        if which.is_empty() {
            return Ok(Vec::new());
        }
        let raw = self.run_histories(batch, which).map_err(device_error)?;
        let (n_out, n_state) = (
            self.problem.model.output_names().len(),
            self.problem.model.state_names().len(),
        );
        let hv = self.model.hist_values() as usize;
        Ok((0..which.len())
            .map(|j| {
                self.packed
                    .experiments
                    .iter()
                    .map(|ex| {
                        let base =
                            (j * self.packed.hist_stride as usize + ex.hist_offset as usize) * hv;
                        let rec = |k: usize, v: usize| raw[base + k * hv + v];
                        let n = ex.samples as usize;
                        History {
                            t: (0..n).map(|k| rec(k, 0)).collect(),
                            outputs: (0..n_out)
                                .map(|o| (0..n).map(|k| rec(k, 1 + o)).collect())
                                .collect(),
                            states: (0..n_state)
                                .map(|s| (0..n).map(|k| rec(k, 1 + n_out + s)).collect())
                                .collect(),
                        }
                    })
                    .collect()
            })
            .collect())
    }

    fn set_cancel(&mut self, flag: Arc<AtomicBool>) {
        self.cancel = Some(flag);
    }
}
