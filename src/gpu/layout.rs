//! Host mirrors of the kernels' buffers: the Pod uniform/storage structs and the
//! index constants of the flat per-run parameter and state arrays. The shader
//! stitcher (`shaders.rs`) emits the same constants into the WGSL prelude, so they
//! are written once, here.
//!
//! Keep in sync with `shaders/shared/bindings.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Run settings for one pass (uniform, binding 0).
/// Keep in sync with `struct Settings` in `shaders/shared/bindings.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct Settings {
    /// Number of (candidate, experiment) runs in this pass.
    pub runs: u32,
    /// Experiments per candidate.
    pub experiments: u32,
    /// RK4 steps each invocation advances per dispatch.
    pub chunk_steps: u32,
    /// History pass: samples per selected candidate over all experiments.
    pub hist_stride: u32,
    /// RK4 steps per sample interval (`Problem::substeps`).
    pub substeps: u32,
    /// History pass: [`RECORD_FULL`] or [`RECORD_SCORED`].
    pub record: u32,
    /// Padding to a 16-byte multiple.
    pub _pad: [u32; 2],
}
const _: () = assert!(std::mem::size_of::<Settings>() == 32);

/// One experiment (storage, binding 1).
/// Keep in sync with `struct ExpInfo` in `shaders/shared/bindings.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct ExpInfo {
    /// Samples reported, `0..window.end`.
    pub samples: u32,
    /// First sample of the fit window.
    pub win_start: u32,
    /// One past the last sample of the fit window.
    pub win_end: u32,
    /// Index of sample 0's measured output in the data buffer.
    pub data_offset: u32,
    /// Force drive: index of the breakpoint times in the data buffer (values follow).
    pub table_offset: u32,
    /// Force drive: number of breakpoints.
    pub table_len: u32,
    /// [`DRIVE_VELOCITY`] or [`DRIVE_FORCE`].
    pub drive_kind: u32,
    /// History pass: offset of this experiment's samples in a candidate's block.
    pub hist_offset: u32,
    /// Padding to a 16-byte multiple.
    pub _pad: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<ExpInfo>() == 48);

/// `ExpInfo::drive_kind` of a velocity-driven experiment.
pub const DRIVE_VELOCITY: u32 = 0;
/// `ExpInfo::drive_kind` of a force-driven experiment.
pub const DRIVE_FORCE: u32 = 1;

/// `Settings::record`: the history kernel writes time, every output and the
/// full state at each sample.
pub const RECORD_FULL: u32 = 0;
/// `Settings::record`: the history kernel writes the scored output alone at
/// each sample (what the polish's residuals need).
pub const RECORD_SCORED: u32 = 1;

/// Progress flag: the run has finished (or diverged).
pub const FLAG_DONE: u32 = 1;
/// Progress flag: a step took more than `MAX_EVENTS_PER_STEP` located switches
/// (compiled rigs); the run counts as diverged.
pub const FLAG_CHATTER: u32 = 4;

/// Samples per chunk unit: a chunk of dispatches is a whole number of these
/// (and so of [`RIG_BLOCK_SAMPLES`]).
pub const BLOCK_SAMPLES: u32 = 32;

/// Samples per block of the compiled rigs' run loop
/// (`shaders/shared/rig_run.wgsl`); divides [`BLOCK_SAMPLES`], so a chunk is
/// a whole number of these blocks too. Shorter than the hand-written
/// kernels' blocks because a run that crosses a switch waits out the rest of
/// its block: on lavapipe 16 gave about 3 % more throughput than 32 in f64
/// and about 1 % in f32 with the per-pair test; with the windows
/// (`rig_window`) 32 measured the same in f32 and 8 slower (README, "on the
/// GPU").
pub const RIG_BLOCK_SAMPLES: u32 = 16;
const _: () = assert!(BLOCK_SAMPLES.is_multiple_of(RIG_BLOCK_SAMPLES));

/// The grid header at the start of every run's parameter block, in order; the
/// model's slots follow at [`RUN_HEADER`]. Each becomes `const R_<NAME>: u32`.
pub const RUN_SLOTS: [&str; 7] = ["T0", "H", "HP", "PRO", "DT", "LIMIT", "SS_TOT"];
/// Values in the grid header (padded).
pub const RUN_HEADER: u32 = 8;

/// Values per run in the parameter buffer for a model with `model_slots` slots.
pub fn run_stride(model_slots: usize) -> u32 {
    RUN_HEADER + model_slots as u32
}

/// Integer constants shared with WGSL, as `(name, value)`, for a model with
/// these slots, state stride and history record size.
pub fn shared_constants(
    model_slots: &[String],
    state_stride: u32,
    hist_values: u32,
) -> Vec<(String, u32)> {
    let mut c: Vec<(String, u32)> = vec![
        (
            "LOCATE_ITERATIONS".into(),
            crate::compile::exec::events::LOCATE_ITERATIONS as u32,
        ),
        ("RIG_BLOCK_SAMPLES".into(), RIG_BLOCK_SAMPLES),
        ("FLAG_DONE".into(), FLAG_DONE),
        ("FLAG_CHATTER".into(), FLAG_CHATTER),
        (
            "MAX_EVENTS".into(),
            crate::compile::MAX_EVENTS_PER_STEP as u32,
        ),
        ("DRIVE_VELOCITY".into(), DRIVE_VELOCITY),
        ("DRIVE_FORCE".into(), DRIVE_FORCE),
        ("RECORD_SCORED".into(), RECORD_SCORED),
        ("STATE_STRIDE".into(), state_stride),
        ("HIST_VALUES".into(), hist_values),
        ("RUN_STRIDE".into(), run_stride(model_slots.len())),
    ];
    for (i, name) in RUN_SLOTS.iter().enumerate() {
        c.push((format!("R_{name}"), i as u32));
    }
    for (i, name) in model_slots.iter().enumerate() {
        c.push((format!("P_{name}"), RUN_HEADER + i as u32));
    }
    c
}
