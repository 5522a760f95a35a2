// History kernel: integrates a few selected candidates and writes, at every
// sample, HIST_VALUES values: t, the model's two outputs and the full state.
// Never stops early, like simulate_history in src/eval/fitness.rs.

// Selected runs' sample records, [selection][experiment block][sample][HIST_VALUES].
@group(0) @binding(6) var<storage, read_write> history: array<real>;
// Candidate index of each selected slot.
@group(0) @binding(7) var<storage, read> selection: array<u32>;

fn observe(
    slot: u32,
    ex: ExpInfo,
    k: u32,
    t: real,
    limit: real,
    rig: Rig,
    y: State,
    acc: ptr<function, real>,
) -> bool {
    let j = slot / settings.experiments;
    let o = ((j * settings.hist_stride) + ex.hist_offset + k) * HIST_VALUES;
    let out = rig_outputs(rig, t, y);
    let full = rig_full_state(rig, t, y);
    history[o] = t;
    history[o + 1u] = out.x;
    history[o + 2u] = out.y;
    history[o + 3u] = full.q.x;
    history[o + 4u] = full.q.y;
    history[o + 5u] = full.q.z;
    history[o + 6u] = full.q.w;
    history[o + 7u] = full.v.x;
    history[o + 8u] = full.v.y;
    history[o + 9u] = full.v.z;
    history[o + 10u] = full.v.w;
    return false;
}

fn finish(slot: u32, base: u32, acc: real) {}

@compute @workgroup_size(64)
fn history_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = gid.x;
    if slot >= settings.runs {
        return;
    }
    let e = slot % settings.experiments;
    let run = selection[slot / settings.experiments] * settings.experiments + e;
    advance(slot, run * RUN_STRIDE, e);
}
