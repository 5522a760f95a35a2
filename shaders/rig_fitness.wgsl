// Fitness kernel of the compiled rigs: one invocation per (candidate,
// experiment) run integrates the rig (shared/rig_run.wgsl) and accumulates the
// residual sum of the scored output (`rig_output0_c`) against the measured
// record; a finished run writes SS_res / SS_tot (or -1 when it blew up or
// chattered) to `fitness`. Mirrors FitnessAccumulator in src/eval/fitness.rs.
// The generated `datum` (see datum_fn in src/gpu/shaders.rs) reads the
// measured values.

// 1 − R² per run, written once the run is done; -1 marks a diverged run.
@group(0) @binding(6) var<storage, read_write> fitness: array<real>;

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
    let f = rig_output0_c(kc, t, y, rg, ck);
    if chattered || !(abs(f) <= limit) {
        *acc = real(-1.0);
        return true;
    }
    if k >= ex.win_start && k < ex.win_end {
        let r = f - datum(ex.data_offset + k);
        *acc += r * r;
    }
    return false;
}

fn finish(slot: u32, base: u32, acc: real) {
    if acc < real(0.0) {
        fitness[slot] = real(-1.0);
    } else {
        fitness[slot] = acc / param(base, R_SS_TOT);
    }
}

@compute @workgroup_size(64)
fn fitness_main(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let slot = gid.x;
    if slot >= settings.runs {
        return;
    }
    advance(slot, slot * RUN_STRIDE, slot % settings.experiments, lane);
}
