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
//
// Samples are taken in blocks of BLOCK_SAMPLES intervals (from the prelude; the
// host makes a chunk a whole number of blocks): one flat loop of
// BLOCK_SAMPLES · substeps iterations, one RK4 step each, every step checking
// the switching function at its end and every completed interval observed.
// A run whose step crosses the switch stops advancing for the rest of the
// block, keeping the state and switching function at that step's start; after
// the block the crossing is located (Hermite cubic, as the CPU), and the next
// block's first two iterations redo the step in two parts (phase 1: t → t + s,
// then fire; phase 2: t + s → t + h). The drive's clock (the model's
// rig_clock) is computed at the start of a block and advanced by a product per
// step, with its own factors over the two parts.
//
// Why this shape: CPU drivers such as lavapipe run every loop body and both
// sides of every branch for all lanes, and a loop whose exit test sits at its
// head runs one more masked pass of its body. So the hot loop holds one copy
// of the step and no nested loop, tests its trip count at its end, and keeps
// runs apart with selects rather than breaks; the crossing code runs once per
// block. A run that crossed waits at most one block.

// Index of the first step of the interval that ends at sample k (k ≥ 1).
fn interval_start(k: u32) -> u32 {
    return (k - 1u) * settings.substeps;
}

// Start time of step n (counted from t0), from its index, as the CPU computes
// it. The block's clock, the steps and a crossing's redo all take their times
// from here, so they agree bit for bit.
fn step_time(t0: real, h: real, n: u32) -> real {
    return t0 + real(n) * h;
}

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
        // g: the switching function (value, rate) at the current state, which
        // starts a step; fire at once if it is already reached, as the CPU
        // does at a step start.
        var g = rig_switch(rig, y);
        if !rig_is_broken(rig) && g.x >= real(0.0) {
            rig_fire(&rig);
        }
        let half = rig_clock_half(rig, h);
        // Step i of the current interval is step idx from t0.
        var i = 0u;
        var idx = interval_start(prog.y);
        // A crossing being redone: phase 1 takes t → t + s, phase 2 t + s → t + h;
        // fa and fb are the drive clock's factors over half of each part.
        var phase = 0u;
        var s = real(0.0);
        var fa = real(1.0);
        var fb = real(1.0);
        loop {
            if done || prog.y >= ex.samples || budget == 0u {
                break;
            }
            // A run whose step crosses the switch stops advancing (crossed) with
            // y and g at that step's start and gc at its end.
            var crossed = false;
            var gc = g;
            var clock = rig_clock(rig, step_time(t0, h, idx));
            var n = 0u;
            loop {
                let live = !crossed && !done && prog.y < ex.samples && budget > 0u;
                let first = phase == 1u;
                let second = phase == 2u;
                let t = step_time(t0, h, idx);
                let ts = select(t, t + s, second);
                let hs = select(select(h, s, first), h - s, second);
                let hf = select(half, select(fa, fb, second), phase != 0u);
                let next = rk4_act(rig, rig_actuators_clocked(rig, ts, hs, clock, hf), hs, y);
                let gn = rig_switch(rig, next);
                let hit = live && phase == 0u && !rig_is_broken(rig) && gn.x >= real(0.0);
                crossed = crossed || hit;
                gc = select(gc, gn, hit);
                let take = live && !hit;
                y = State(select(y.q, next.q, take), select(y.v, next.v, take));
                g = select(g, gn, take);
                clock = select(clock, rig_clock_next(clock, hf), take);
                if take && first {
                    rig_fire(&rig);
                }
                phase = select(phase, select(0u, 2u, first), take && phase != 0u);
                let stepped = take && !first;
                idx += select(0u, 1u, stepped);
                i += select(0u, 1u, stepped);
                if stepped && i == settings.substeps {
                    budget -= min(budget, settings.substeps);
                    done = observe(slot, ex, prog.y, t0 + real(prog.y) * dt, limit, rig, y, &acc);
                    prog.y += 1u;
                    i = 0u;
                }
                continuing {
                    n += 1u;
                    break if n >= BLOCK_SAMPLES * settings.substeps;
                }
            }
            if crossed {
                // Locate the crossing in step idx (Hermite cubic, as the CPU); the
                // next block redoes the step in two parts.
                s = hermite_crossing(g.x, g.y * h, gc.x, gc.y * h) * h;
                fa = rig_clock_half(rig, s);
                fb = rig_clock_half(rig, h - s);
                phase = 1u;
            }
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
