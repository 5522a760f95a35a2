//! The run buffers of a [`GpuEvaluator`]: sized for a number of runs, grown
//! when a batch needs more, split into parts that one dispatch each covers,
//! and the batch's parameters packed and uploaded into them.

use crate::eval::Batch;

use super::layout::Settings;
use super::pack::{pack_runs, real_size, to_real_bytes};
use super::pipeline;
use super::{GpuError, GpuEvaluator};

/// One dispatch's share of the run buffers: runs `first..first + per_pass`,
/// with its own settings (its run count) and a bind group over its slices.
#[derive(Debug)]
pub(super) struct Part {
    pub(super) first: usize,
    pub(super) settings: wgpu::Buffer,
    pub(super) bind: wgpu::BindGroup,
}

/// Buffers sized for a number of runs; grown when a batch needs more.
#[derive(Debug)]
pub(super) struct RunBuffers {
    pub(super) capacity: usize,
    pub(super) params: wgpu::Buffer,
    pub(super) state: wgpu::Buffer,
    pub(super) progress: wgpu::Buffer,
    pub(super) fitness: wgpu::Buffer,
    pub(super) readback: wgpu::Buffer,
    /// Runs per part (a multiple of the experiments per candidate).
    pub(super) per_pass: usize,
    pub(super) parts: Vec<Part>,
}

impl GpuEvaluator {
    /// Makes room for `runs` runs and uploads the batch's parameters; returns
    /// the largest step count of any run.
    pub(super) fn upload(&mut self, batch: &Batch) -> Result<usize, GpuError> {
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
    pub(super) fn run_bytes(&self) -> [u64; 4] {
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
    /// storage binding allow (and [`super::GpuOptions::max_runs_per_pass`]), rounded
    /// down to a multiple of the experiments per candidate (so that a part
    /// starts at a candidate's first run) and of the storage offset alignment
    /// (so that every slice may be bound). 0 when no such number fits.
    fn runs_per_pass(&self) -> usize {
        let limits = self.ctx.device.limits();
        let groups = limits.max_compute_workgroups_per_dimension as usize;
        let widest = self.run_bytes().into_iter().max().unwrap_or(16);
        let mut n = (groups * self.fitness_generic.workgroup_x as usize)
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
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}
