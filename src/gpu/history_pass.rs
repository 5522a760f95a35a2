//! The history pass of a [`GpuEvaluator`]: records of chosen candidates at
//! every sample, in buffers of their own and one submit, read back either in
//! full (time, outputs, states) as [`History`]s or as the scored output alone.

use crate::eval::{Batch, History};
use crate::model::CompiledRig;

use super::dispatch::encode_dispatches;
use super::layout::{RECORD_FULL, RECORD_SCORED, Settings};
use super::pack::{Reals, real_size};
use super::pipeline;
use super::{GpuError, GpuEvaluator};

impl GpuEvaluator {
    /// Runs the history kernel over candidates `which` of the batch and
    /// returns one [`History`] per candidate and experiment, read from the
    /// mapped records.
    pub(super) fn run_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, GpuError> {
        self.run_records(batch, which, RECORD_FULL, |ev, raw| {
            ev.unpack_histories(raw, which.len())
        })
    }

    /// Runs the history kernel over candidates `which` of the batch writing
    /// the scored output alone, and returns it per candidate and experiment
    /// over samples `0..window.end`: a `1 / HIST_VALUES` share of the bytes
    /// [`Self::run_histories`] writes, maps and unpacks.
    pub(super) fn run_scored(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, GpuError> {
        self.run_records(batch, which, RECORD_SCORED, |ev, raw| {
            ev.unpack_scored(raw, which.len())
        })
    }

    /// The history kernel over candidates `which` writing `record`, its
    /// mapped records handed to `unpack`.
    fn run_records<T>(
        &mut self,
        batch: &Batch,
        which: &[usize],
        record: u32,
        unpack: impl FnOnce(&Self, &Reals<'_>) -> T,
    ) -> Result<T, GpuError> {
        let values = match record {
            RECORD_SCORED => 1,
            _ => self.model.hist_values(),
        };
        let max_steps = self.upload(batch)?;
        let ne = self.problem.experiments.len();
        let runs = which.len() * ne;
        // A handle's copy, so that the kernel outlives the borrow of `self`.
        let kernel = self.history_kernel.wait()?.clone();
        let groups = pipeline::workgroups(&self.ctx, runs, kernel.workgroup_x)?;
        let settings = self.settings(runs, self.packed.hist_stride, record);
        let real = real_size(self.precision);
        let run_bytes = self.run_bytes();
        let size =
            (which.len() * self.packed.hist_stride as usize) as u64 * u64::from(values) * real;
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
                runs as u64 * run_bytes[1],
                U::STORAGE | U::COPY_DST,
            );
            let progress = pipeline::buffer(
                ctx,
                "history progress",
                runs as u64 * run_bytes[2],
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
            encode_dispatches(
                &mut enc,
                "rk4 chunks",
                &kernel,
                &[(&bind, groups)],
                dispatches,
            );
            enc.copy_buffer_to_buffer(&history, 0, &readback, 0, size);
            ctx.queue.submit([enc.finish()]);
            readback
        })?;
        pipeline::read_back(ctx, &readback, size, |bytes| {
            unpack(self, &Reals::new(bytes, self.precision))
        })
    }

    /// `raw` scored outputs (one value per sample) of `candidates`
    /// candidates, per candidate and experiment.
    fn unpack_scored(&self, raw: &Reals<'_>, candidates: usize) -> Vec<Vec<Vec<f64>>> {
        let stride = self.packed.hist_stride as usize;
        (0..candidates)
            .map(|j| {
                self.packed
                    .experiments
                    .iter()
                    .map(|ex| {
                        let base = j * stride + ex.hist_offset as usize;
                        (0..ex.samples as usize)
                            .map(|k| raw.get(base + k))
                            .collect()
                    })
                    .collect()
            })
            .collect()
    }

    /// `raw` records of `candidates` candidates as one [`History`] per
    /// candidate and experiment.
    fn unpack_histories(&self, raw: &Reals<'_>, candidates: usize) -> Vec<Vec<History>> {
        let (n_out, n_state) = (
            self.problem.model.output_names().len(),
            self.problem.model.state_names().len(),
        );
        let hv = self.model.hist_values() as usize;
        (0..candidates)
            .map(|j| {
                self.packed
                    .experiments
                    .iter()
                    .zip(&self.problem.experiments)
                    .map(|(ex, exp)| {
                        let base =
                            (j * self.packed.hist_stride as usize + ex.hist_offset as usize) * hv;
                        let rec = |k: usize, v: usize| raw.get(base + k * hv + v);
                        let n = ex.samples as usize;
                        History {
                            t: (0..n).map(|k| rec(k, 0)).collect(),
                            // The kernels of a channel's rig list its
                            // measured output first: back in the rig's order.
                            outputs: (0..n_out)
                                .map(|o| CompiledRig::scoring_order(exp.output, o))
                                .map(|o| (0..n).map(|k| rec(k, 1 + o)).collect())
                                .collect(),
                            states: (0..n_state)
                                .map(|s| (0..n).map(|k| rec(k, 1 + n_out + s)).collect())
                                .collect(),
                        }
                    })
                    .collect()
            })
            .collect()
    }
}
