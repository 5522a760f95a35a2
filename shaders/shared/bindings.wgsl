// Bindings shared by the ensemble kernels (group 0, bindings 0–5).
// Keep in sync with src/gpu/layout.rs (Settings, ExpInfo, R_* slots).

// Run settings for one pass. Keep in sync with `Settings` in src/gpu/layout.rs.
struct Settings {
    // Number of (candidate, experiment) runs in this pass.
    runs: u32,
    // Experiments per candidate; run `i·experiments + e` is experiment `e`.
    experiments: u32,
    // RK4 steps each invocation advances per dispatch (chunking).
    chunk_steps: u32,
    // History kernel: samples per selected candidate over all experiments.
    hist_stride: u32,
    // RK4 steps per sample interval (the problem's, shared by all experiments;
    // a uniform, so the step loop's trip count is uniform too).
    substeps: u32,
    // History kernel: RECORD_FULL or RECORD_SCORED.
    record: u32,
    _pad1: u32,
    _pad2: u32,
}

// One experiment. Keep in sync with `ExpInfo` in src/gpu/layout.rs.
struct ExpInfo {
    // Samples reported, 0..window.end.
    samples: u32,
    // Fit window [win_start, win_end).
    win_start: u32,
    win_end: u32,
    // Index of sample 0's measured output in `data`.
    data_offset: u32,
    // Force drive: breakpoint times at data[table_offset..+table_len], values after.
    table_offset: u32,
    table_len: u32,
    // DRIVE_VELOCITY or DRIVE_FORCE.
    drive_kind: u32,
    // History kernel: offset of this experiment's samples in a candidate's block.
    hist_offset: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    _pad3: u32,
}

@group(0) @binding(0) var<uniform> settings: Settings;
@group(0) @binding(1) var<storage, read> experiments: array<ExpInfo>;
// Per-run parameters, RUN_STRIDE values per run: the R_* grid header then the
// model's P_* slots.
@group(0) @binding(2) var<storage, read> run_params: array<real>;
// Measured forces and drive tables of all experiments.
@group(0) @binding(3) var<storage, read> data: array<real>;
// Integrator state between dispatches, STATE_STRIDE values per run.
@group(0) @binding(4) var<storage, read_write> state: array<real>;
// Progress per run: (prologue steps done, next sample, FLAG_* bits, unused).
@group(0) @binding(5) var<storage, read_write> progress: array<vec4<u32>>;
