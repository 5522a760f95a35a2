//! The GPU evaluator: pipelines and buffers built once, reused every generation.

use crate::eval::{
    Batch, DIVERGED, EvalError, Evaluator, EvaluatorInfo, History, Precision, Problem, Scores,
};
use crate::model::{Drive, GpuModel};

use super::layout::{BLOCK_SAMPLES, Settings};
use super::pack::{
    PackedProblem, from_real_bytes, pack_problem, pack_runs, real_size, to_real_bytes,
};
use super::pipeline::{self, Binding, Kernelled};
use super::shaders::Kernel;
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
}

impl Default for GpuOptions {
    fn default() -> Self {
        Self {
            chunk_steps: 2048,
            specialise: true,
        }
    }
}

/// Bindings of the fitness kernel (`shared/bindings.wgsl`, then `fitness`).
const FITNESS_BINDINGS: [Binding; 7] = [
    Binding::Uniform,
    Binding::Read,
    Binding::Read,
    Binding::Read,
    Binding::ReadWrite,
    Binding::ReadWrite,
    Binding::ReadWrite,
];

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

/// Buffers sized for a number of runs; grown when a batch needs more.
#[derive(Debug)]
struct RunBuffers {
    capacity: usize,
    params: wgpu::Buffer,
    state: wgpu::Buffer,
    progress: wgpu::Buffer,
    fitness: wgpu::Buffer,
    readback: wgpu::Buffer,
    bind: wgpu::BindGroup,
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
    force_drive: bool,
    fitness_layout: pipeline::Layout,
    fitness_kernel: Kernelled,
    /// Specialised fitness kernels built so far, oldest first.
    specialised: Vec<Specialised>,
    /// The one that scored the last batch.
    last_specialised: Option<usize>,
    history_layout: pipeline::Layout,
    history_kernel: Kernelled,
    settings: wgpu::Buffer,
    experiments: wgpu::Buffer,
    data: wgpu::Buffer,
    runs: Option<RunBuffers>,
    host: Vec<f64>,
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
        let fitness_layout = pipeline::layout(&ctx, "fitness layout", &FITNESS_BINDINGS);
        let fitness_kernel = pipeline::build(
            &ctx,
            Some((&model, force, &[])),
            precision,
            Kernel::Fitness,
            Some(&fitness_layout),
        )?;
        let history_layout = pipeline::layout(&ctx, "history layout", &HISTORY_BINDINGS);
        let history_kernel = pipeline::build(
            &ctx,
            Some((&model, force, &[])),
            precision,
            Kernel::History,
            Some(&history_layout),
        )?;
        let packed = pack_problem(&problem, &model);
        let (settings, experiments, data) = pipeline::scoped(&ctx, "problem buffers", || {
            (
                pipeline::buffer(
                    &ctx,
                    "settings",
                    size_of::<Settings>() as u64,
                    wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                ),
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
            )
        })?;
        Ok(Self {
            ctx,
            problem,
            packed,
            model,
            precision,
            options,
            force_drive: force,
            fitness_layout,
            fitness_kernel,
            specialised: Vec::new(),
            last_specialised: None,
            history_layout,
            history_kernel,
            settings,
            experiments,
            data,
            runs: None,
            host: Vec::new(),
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

    /// How many per-run values the kernel that scored the last batch had baked
    /// in; `None` when the generic kernel scored it.
    pub fn specialised_constants(&self) -> Option<usize> {
        self.last_specialised
            .map(|i| specialise::count(&self.specialised[i].baked))
    }

    fn stride(&self) -> u64 {
        super::layout::run_stride(self.model.slots().len()) as u64
    }

    /// Makes room for `runs` runs and uploads the batch's parameters; returns
    /// the largest step count of any run.
    fn upload(&mut self, batch: &Batch) -> Result<usize, GpuError> {
        let runs = batch.candidates * self.problem.experiments.len();
        if self.runs.as_ref().is_none_or(|r| r.capacity < runs) {
            self.runs = Some(self.allocate(runs.next_power_of_two())?);
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

    fn allocate(&self, capacity: usize) -> Result<RunBuffers, GpuError> {
        let ctx = &self.ctx;
        let real = real_size(self.precision);
        let n = capacity as u64;
        let largest = n * self.stride() * real;
        let limit = ctx.device.limits().max_storage_buffer_binding_size;
        if largest > limit {
            return Err(GpuError::TooLarge {
                runs: capacity,
                max: (limit / (self.stride() * real)) as usize,
            });
        }
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
            let bind = pipeline::bind_with(
                ctx,
                "fitness bind group",
                &self.fitness_layout.group,
                &[
                    &self.settings,
                    &self.experiments,
                    &params,
                    &self.data,
                    &state,
                    &progress,
                    &fitness,
                ],
            );
            RunBuffers {
                capacity,
                params,
                state,
                progress,
                fitness,
                readback,
                bind,
            }
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
            Some((&self.model, self.force_drive, &baked)),
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
        let groups = pipeline::workgroups(&self.ctx, runs, kernel.workgroup_x)?;
        let settings = Settings {
            runs: runs as u32,
            experiments: self.problem.experiments.len() as u32,
            chunk_steps: self.chunk_steps(),
            hist_stride: 0,
            substeps: self.problem.substeps as u32,
            _pad: [0; 3],
        };
        let dispatches = self.dispatches(max_steps);
        let rb = self.runs.as_ref().expect("uploaded");
        let size = runs as u64 * real_size(self.precision);
        // A run that never reached its last sample would leave this sentinel.
        let unfinished = to_real_bytes(&vec![UNFINISHED; runs], self.precision);
        pipeline::scoped(&self.ctx, "fitness pass", || {
            self.ctx
                .queue
                .write_buffer(&self.settings, 0, bytemuck::bytes_of(&settings));
            self.ctx.queue.write_buffer(&rb.fitness, 0, &unfinished);
            let mut enc = self
                .ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("fitness"),
                });
            enc.clear_buffer(&rb.state, 0, None);
            enc.clear_buffer(&rb.progress, 0, None);
            Self::encode_pass(&mut enc, kernel, &rb.bind, groups, dispatches);
            enc.copy_buffer_to_buffer(&rb.fitness, 0, &rb.readback, 0, size);
            self.ctx.queue.submit([enc.finish()]);
        })?;
        let bytes = pipeline::read_back(&self.ctx, &rb.readback, size)?;
        Ok(from_real_bytes(&bytes, self.precision))
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
    EvalError::Device(e.to_string())
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
        let (n_out, n_state) = self.model.hist_layout(
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
}
