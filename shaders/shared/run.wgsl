// The chunked run loop shared by the ensemble kernels: advances one run by up to
// `settings.chunk_steps` RK4 steps, keeping its state in `state`/`progress`
// between dispatches. Mirrors `Integrator::run` in src/integrate/rk4.rs: the
// prologue from t = 0 to t0 when t0 > 0, then `substeps` steps per sample with
// every step time computed from its index.
//
// The kernel file provides `observe(slot, ex, k, t, limit, rig, y, acc) -> bool`
// (true stops the run) and `finish(slot, base, acc)`. The experiment and the
// blow-up limit are passed in, loaded once per dispatch: on CPU drivers every
// storage load in the per-sample path is a per-lane gather, and the measured
// force is the only one left there.

fn advance(slot: u32, base: u32, e: u32) {
    var prog = progress[slot];
    if (prog.z & FLAG_DONE) != 0u {
        return;
    }
    let ex = experiments[e];
    var rig = rig_load(base, ex);
    if (prog.z & FLAG_BROKEN) != 0u {
        rig_fire(&rig);
    }
    let sb = slot * STATE_STRIDE;
    var y = State(
        vec4<real>(state[sb], state[sb + 1u], state[sb + 2u], state[sb + 3u]),
        vec4<real>(state[sb + 4u], state[sb + 5u], state[sb + 6u], state[sb + 7u]),
    );
    var acc = state[sb + 8u];
    let t0 = param(base, R_T0);
    let h = param(base, R_H);
    let hp = param(base, R_HP);
    let dt = param(base, R_DT);
    let pro = u32(param(base, R_PRO));
    let limit = param(base, R_LIMIT);
    var budget = settings.chunk_steps;
    var done = false;

    if prog.x < pro {
        let n = min(pro - prog.x, budget);
        y = rk4_switch_steps(&rig, real(0.0), prog.x, n, hp, y);
        prog.x += n;
        budget -= n;
    }
    if prog.x >= pro {
        if prog.y == 0u && ex.samples > 0u {
            done = observe(slot, ex, 0u, t0, limit, rig, y, &acc);
            prog.y = 1u;
        }
        while !done && prog.y < ex.samples && budget > 0u {
            let first = (prog.y - 1u) * settings.substeps;
            y = rk4_switch_steps(&rig, t0, first, settings.substeps, h, y);
            budget -= min(budget, settings.substeps);
            done = observe(slot, ex, prog.y, t0 + real(prog.y) * dt, limit, rig, y, &acc);
            prog.y += 1u;
        }
        if prog.y >= ex.samples {
            done = true;
        }
    }

    state[sb] = y.q.x;
    state[sb + 1u] = y.q.y;
    state[sb + 2u] = y.q.z;
    state[sb + 3u] = y.q.w;
    state[sb + 4u] = y.v.x;
    state[sb + 5u] = y.v.y;
    state[sb + 6u] = y.v.z;
    state[sb + 7u] = y.v.w;
    state[sb + 8u] = acc;
    var flags = prog.z;
    if rig_is_broken(rig) {
        flags |= FLAG_BROKEN;
    }
    if done {
        flags |= FLAG_DONE;
        finish(slot, base, acc);
    }
    progress[slot] = vec4<u32>(prog.x, prog.y, flags, 0u);
}
