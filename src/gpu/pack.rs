//! Host-side packing: experiments, measured data and per-run parameters in the
//! layouts of `layout.rs`, and conversion of f64 values to the kernel's `real`.

use std::borrow::Cow;

use crate::base::Drive;
use crate::eval::{Batch, Precision, Problem};
use crate::model::GpuModel;

use super::layout::{DRIVE_FORCE, DRIVE_VELOCITY, ExpInfo, RUN_HEADER, run_stride};

/// Experiments and the data buffer's contents (measured outputs, then drive
/// tables), with each experiment's blow-up limit and SS_tot.
#[derive(Debug, Clone)]
pub struct PackedProblem {
    /// One per experiment.
    pub experiments: Vec<ExpInfo>,
    /// Measured outputs of every experiment, then each force-drive table
    /// (times, then values).
    pub data: Vec<f64>,
    /// `ExperimentData::blowup_limit` per experiment.
    pub limit: Vec<f64>,
    /// `ExperimentData::ss_tot` per experiment.
    pub ss_tot: Vec<f64>,
    /// Samples per candidate over all experiments (history pass).
    pub hist_stride: u32,
}

/// Packs a problem's experiments for `model`'s kernels (whose own tables come
/// first in the data buffer).
pub fn pack_problem(problem: &Problem, model: &GpuModel) -> PackedProblem {
    let mut data = model.table_data().to_vec();
    let mut experiments = Vec::new();
    let mut hist_offset = 0u32;
    for exp in &problem.experiments {
        let samples = exp.window.end as u32;
        experiments.push(ExpInfo {
            samples,
            win_start: exp.window.start as u32,
            win_end: exp.window.end as u32,
            data_offset: data.len() as u32,
            drive_kind: DRIVE_VELOCITY,
            hist_offset,
            ..ExpInfo::zeroed_default()
        });
        data.extend_from_slice(&exp.measured);
        hist_offset += samples;
    }
    for (info, exp) in experiments.iter_mut().zip(&problem.experiments) {
        if let Drive::Force(table) = &exp.drive {
            info.drive_kind = DRIVE_FORCE;
            // `table_header` reads the header just before the breakpoints.
            data.push(table.kernel_header());
            info.table_offset = data.len() as u32;
            info.table_len = table.t.len() as u32;
            data.extend_from_slice(&table.t);
            data.extend_from_slice(&table.value);
        }
    }
    PackedProblem {
        experiments,
        data,
        limit: problem
            .experiments
            .iter()
            .map(|e| e.blowup_limit())
            .collect(),
        ss_tot: problem.experiments.iter().map(|e| e.ss_tot()).collect(),
        hist_stride: hist_offset,
    }
}

impl ExpInfo {
    fn zeroed_default() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

/// Packs every (candidate, experiment) run of `batch`, run `i·E + e`, into
/// `out` (cleared first): the grid header (`RUN_SLOTS`) computed exactly as
/// `SampleGrid` does, then the model's slots. Returns the largest number of RK4
/// steps of any run.
pub fn pack_runs(
    problem: &Problem,
    packed: &PackedProblem,
    model: &GpuModel,
    batch: &Batch,
    out: &mut Vec<f64>,
) -> usize {
    out.clear();
    let stride = run_stride(model.slot_names().len()) as usize;
    out.reserve(stride * batch.candidates * problem.experiments.len());
    let mut max_steps = 0;
    for i in 0..batch.candidates {
        for (e, exp) in problem.experiments.iter().enumerate() {
            let start = out.len();
            let grid = exp.grid(batch.offsets[e][i], problem.substeps);
            let pro = grid.prologue_steps();
            let hp = if pro > 0 { grid.t0 / pro as f64 } else { 0.0 };
            max_steps = max_steps.max(grid.total_steps());
            out.extend_from_slice(&[
                grid.t0,
                grid.step(),
                hp,
                pro as f64,
                grid.dt,
                packed.limit[e],
                packed.ss_tot[e],
            ]);
            out.resize(start + RUN_HEADER as usize, 0.0);
            model.pack(batch.params_of(e, i), out);
            debug_assert_eq!(out.len() - start, stride);
        }
    }
    max_steps
}

/// Bytes of `values` as the kernel's `real`.
pub fn to_real_bytes(values: &[f64], precision: Precision) -> Vec<u8> {
    match precision {
        Precision::F64 => bytemuck::cast_slice(values).to_vec(),
        Precision::F32 => {
            let v: Vec<f32> = values.iter().map(|&x| x as f32).collect();
            bytemuck::cast_slice(&v).to_vec()
        }
    }
}

/// Values of the kernel's `real` read back as f64.
pub fn from_real_bytes(bytes: &[u8], precision: Precision) -> Vec<f64> {
    let reals = Reals::new(bytes, precision);
    (0..reals.len()).map(|i| reals.get(i)).collect()
}

/// The kernel's `real`s in read-back bytes, read where they lie (copied only
/// where the bytes are not aligned for them).
#[derive(Debug)]
pub enum Reals<'a> {
    /// f32 kernels.
    F32(Cow<'a, [f32]>),
    /// f64 kernels.
    F64(Cow<'a, [f64]>),
}

impl<'a> Reals<'a> {
    /// `bytes` as `precision`'s values.
    pub fn new(bytes: &'a [u8], precision: Precision) -> Self {
        fn view<'a, T: bytemuck::Pod>(bytes: &'a [u8]) -> Cow<'a, [T]> {
            match bytemuck::try_cast_slice(bytes) {
                Ok(v) => Cow::Borrowed(v),
                Err(_) => Cow::Owned(bytemuck::pod_collect_to_vec(bytes)),
            }
        }
        match precision {
            Precision::F32 => Reals::F32(view(bytes)),
            Precision::F64 => Reals::F64(view(bytes)),
        }
    }

    /// Value `i` as f64.
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Reals::F32(v) => f64::from(v[i]),
            Reals::F64(v) => v[i],
        }
    }

    /// How many values.
    fn len(&self) -> usize {
        match self {
            Reals::F32(v) => v.len(),
            Reals::F64(v) => v.len(),
        }
    }
}

/// Size in bytes of one `real`.
pub fn real_size(precision: Precision) -> u64 {
    match precision {
        Precision::F32 => 4,
        Precision::F64 => 8,
    }
}
