//! The fitness pass of a [`GpuEvaluator`]: the batch uploaded, the kernel
//! chosen (specialised to the batch where that pays), the run state reset,
//! the chunks dispatched and one `1 − R²` per run read back as [`Scores`].

use crate::eval::{Batch, DIVERGED, EvalError, Scores};

use super::pack::{from_real_bytes, real_size, to_real_bytes};
use super::pipeline::{self, Kernelled};
use super::shaders::Kernel;
use super::specialise;
use super::{GpuError, GpuEvaluator};

/// Fitness-buffer value of a run that has not finished (the kernel writes ≥ 0,
/// or -1 for a diverged run).
const UNFINISHED: f64 = -2.0;

/// A fitness kernel with the values it has baked in.
#[derive(Debug)]
pub(super) struct Specialised {
    pub(super) baked: Vec<Option<f64>>,
    pub(super) kernel: Kernelled,
}

impl GpuEvaluator {
    /// Which specialised kernel scores the batch just uploaded (an index into
    /// `specialised`, built first where needed), or `None` for the generic one.
    /// The kernel depends only on the batch, never on the batches before it,
    /// so the same batch always gets the same bits.
    pub(super) fn specialise_for(&mut self, runs: usize) -> Result<Option<usize>, GpuError> {
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

    /// Compiles the generic fitness kernel, the first time a batch needs it.
    fn compile_generic_fitness(&mut self) -> Result<(), GpuError> {
        if self.fitness_kernel.is_none() {
            let kernel =
                pipeline::compile(&self.ctx, &self.fitness_generic, Some(&self.fitness_layout))?;
            self.fitness_kernel = Some(kernel);
        }
        Ok(())
    }

    /// Runs the fitness kernel over the batch and returns its raw value per
    /// run.
    pub(super) fn run_fitness(&mut self, batch: &Batch) -> Result<Vec<f64>, GpuError> {
        let runs = self.dispatch_fitness(batch, None)?;
        let rb = self.runs.as_ref().expect("uploaded");
        let size = runs as u64 * real_size(self.precision);
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
        pipeline::read_back(&self.ctx, &rb.readback, size, |b| {
            from_real_bytes(b, self.precision)
        })
    }

    /// The first chunks of the batch's fitness pass, enough for `steps`
    /// steps, run and waited for, their values never read; returns the most
    /// steps a run advanced. With one step it is the batch's warm-up: the
    /// kernel that scores the batch built, its buffers sized and the kernel
    /// run once on them (a driver that compiles a pipeline's machine code at
    /// its first dispatch, as lavapipe does, compiles it here), at the cost
    /// of one chunk instead of a whole pass.
    pub(super) fn part_fitness(&mut self, batch: &Batch, steps: usize) -> Result<usize, GpuError> {
        let chunk = self.chunk_steps() as usize;
        let chunks = steps.div_ceil(chunk).max(1);
        self.dispatch_fitness(batch, Some(u32::try_from(chunks).unwrap_or(u32::MAX)))?;
        self.wait(None)?;
        Ok(chunks * chunk)
    }

    /// Uploads the batch, builds the kernel that scores it (specialised
    /// where that pays), resets the runs and submits the pass's chunks, at
    /// most `most_chunks` of them. Returns the batch's runs.
    fn dispatch_fitness(
        &mut self,
        batch: &Batch,
        most_chunks: Option<u32>,
    ) -> Result<usize, GpuError> {
        let max_steps = self.upload(batch)?;
        let runs = batch.candidates * self.problem.experiments.len();
        let chosen = self.specialise_for(runs)?;
        if chosen.is_none() {
            self.compile_generic_fitness()?;
        }
        let kernel = match chosen {
            Some(i) => &self.specialised[i].kernel,
            None => self.fitness_kernel.as_ref().expect("compiled above"),
        };
        let dispatches = self
            .dispatches(max_steps)
            .min(most_chunks.unwrap_or(u32::MAX));
        let rb = self.runs.as_ref().expect("uploaded");
        // The parts this batch uses, with their run counts and workgroups.
        let mut parts = Vec::new();
        for part in rb.parts.iter().take_while(|p| p.first < runs) {
            let count = rb.per_pass.min(runs - part.first);
            let groups = pipeline::workgroups(&self.ctx, count, kernel.workgroup_x)?;
            parts.push((part, count, groups));
        }
        // A run that never reached its last sample would leave this sentinel.
        let unfinished = to_real_bytes(&vec![UNFINISHED; runs], self.precision);
        pipeline::scoped(&self.ctx, "fitness pass", || {
            for &(part, count, _) in &parts {
                let settings = self.settings(count, 0, super::layout::RECORD_FULL);
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
        let binds: Vec<(&wgpu::BindGroup, u32)> = parts
            .iter()
            .map(|&(part, _, groups)| (&part.bind, groups))
            .collect();
        self.submit_chunks(kernel, &binds, dispatches)?;
        Ok(runs)
    }

    /// The scores of a fitness pass's raw values: a blown-up run (-1, or
    /// NaN/Inf, which only a blown-up run gives) scores [`DIVERGED`]; a run
    /// left [`UNFINISHED`] is an error.
    pub(super) fn scores(&self, raw: Vec<f64>) -> Result<Scores, EvalError> {
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
}
