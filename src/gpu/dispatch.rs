//! Dispatch and chunking: a pass of a [`GpuEvaluator`] advances every run by
//! [`GpuOptions::chunk_steps`] steps per dispatch, so that no single dispatch
//! runs long enough to trip a display driver's watchdog, and reads the cancel
//! flag between chunks.

use std::sync::atomic::Ordering;

use super::layout::{BLOCK_SAMPLES, Settings};
use super::pipeline::{self, Kernelled};
use super::{GpuError, GpuEvaluator};
#[cfg(doc)]
use {super::GpuOptions, crate::eval::Evaluator};

impl GpuEvaluator {
    /// Whether the flag given to [`Evaluator::set_cancel`] is raised.
    pub(super) fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// Blocks until `submission` (or everything submitted) has run.
    pub(super) fn wait(&self, submission: Option<wgpu::SubmissionIndex>) -> Result<(), GpuError> {
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
    pub(super) fn chunk_steps(&self) -> u32 {
        let block = BLOCK_SAMPLES * self.problem.substeps as u32;
        self.options.chunk_steps.max(1).div_ceil(block) * block
    }

    /// The settings of a pass over `runs` runs, with history records
    /// `hist_stride` samples apart (0: no history) holding `record`
    /// ([`super::layout::RECORD_FULL`] or [`super::layout::RECORD_SCORED`]).
    pub(super) fn settings(&self, runs: usize, hist_stride: u32, record: u32) -> Settings {
        Settings {
            runs: runs as u32,
            experiments: self.problem.experiments.len() as u32,
            chunk_steps: self.chunk_steps(),
            hist_stride,
            substeps: self.problem.substeps as u32,
            record,
            _pad: [0; 2],
        }
    }

    /// Number of dispatches that finish runs of up to `max_steps` steps.
    pub(super) fn dispatches(&self, max_steps: usize) -> u32 {
        (max_steps.div_ceil(self.chunk_steps() as usize) + 1) as u32
    }

    /// Runs `dispatches` chunks of `kernel` over each (bind group,
    /// workgroups) of `binds`, one submit per chunk, and returns once all
    /// have run; [`GpuError::Cancelled`] when the cancel flag is raised
    /// before a chunk is submitted.
    pub(super) fn submit_chunks(
        &self,
        kernel: &Kernelled,
        binds: &[(&wgpu::BindGroup, u32)],
        dispatches: u32,
    ) -> Result<(), GpuError> {
        // The next chunk is queued while one runs, so that the device never
        // waits for the host and an interrupt waits for at most the chunk
        // running and the one queued.
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
                encode_dispatches(&mut enc, "rk4 chunk", kernel, binds, 1);
                self.ctx.queue.submit([enc.finish()])
            })?;
            if let Some(previous) = queued.replace(submitted) {
                self.wait(Some(previous))?;
            }
        }
        Ok(())
    }
}

/// Encodes into `encoder` one compute pass of `kernel` that dispatches each
/// (bind group, workgroups) of `binds` `times` times in a row (the runs of
/// different bind groups are independent, so their order does not matter).
pub(super) fn encode_dispatches(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    kernel: &Kernelled,
    binds: &[(&wgpu::BindGroup, u32)],
    times: u32,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: None,
    });
    pass.set_pipeline(&kernel.pipeline);
    for &(bind, groups) in binds {
        pass.set_bind_group(0, bind, &[]);
        for _ in 0..times {
            pass.dispatch_workgroups(groups, 1, 1);
        }
    }
}
