// History kernel of the compiled rigs: integrates a few selected candidates and
// writes, at every sample, HIST_VALUES values: t, every output, then the full
// state; or, when settings.record is RECORD_SCORED, the scored output alone
// (the polish's residuals need nothing else). Never stops early, like
// simulate_history in src/eval/fitness.rs; a run that chattered keeps its last
// state.

// Selected runs' sample records, [selection][experiment block][sample][HIST_VALUES]
// (a single value per sample with RECORD_SCORED).
@group(0) @binding(6) var<storage, read_write> history: array<real>;
// Candidate index of each selected slot.
@group(0) @binding(7) var<storage, read> selection: array<u32>;

fn observe(
    slot: u32,
    ex: ExpInfo,
    k: u32,
    t: real,
    limit: real,
    kc: RunConsts,
    y: RigState,
    rg: RigRegime,
    ck: DriveClocks,
    chattered: bool,
    acc: ptr<function, real>,
) -> bool {
    let j = slot / settings.experiments;
    let at = (j * settings.hist_stride) + ex.hist_offset + k;
    if settings.record == RECORD_SCORED {
        history[at] = rig_output0_c(kc, t, y, rg, ck);
        return false;
    }
    let o = at * HIST_VALUES;
    let rep = rig_report_c(kc, t, y, rg, ck);
    history[o] = t;
    for (var i = 0u; i < RIG_REPORT; i += 1u) {
        history[o + 1u + i] = rep.v[i];
    }
    return false;
}

fn finish(slot: u32, base: u32, acc: real) {}

// 16 runs a workgroup: lavapipe gives each workgroup to one of its threads, and
// a polish pass is a few dozen runs, which 64 would put on one thread.
@compute @workgroup_size(16)
fn history_main(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let slot = gid.x;
    if slot >= settings.runs {
        return;
    }
    let e = slot % settings.experiments;
    let run = selection[slot / settings.experiments] * settings.experiments + e;
    advance(slot, run * RUN_STRIDE, e, lane);
}
