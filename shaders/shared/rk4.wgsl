// Classic RK4 with the one-way switch (fracture) located inside the step.
// Mirrors src/integrate/rk4.rs operation for operation: same stage times, same
// Hermite cubic, same CROSSING_ITERATIONS bisection halvings.
//
// The model file provides `Rig`, `rig_actuators` (→ `Actuation`), `rig_deriv`, `rig_switch`,
// `rig_fire` and `rig_is_broken`; shared/run.wgsl also uses its drive clock
// (`rig_clock`, `rig_clock_half`, `rig_clock_next`, `rig_actuators_clocked`).

// Up to four degrees of freedom: positions q and velocities v.
struct State {
    q: vec4<real>,
    v: vec4<real>,
}

// One plain RK4 step of length h from (t, y). The actuator is evaluated once per
// distinct stage time (t, t + h/2, t + h), by the model in one call.
fn rk4(rig: Rig, t: real, h: real, y: State) -> State {
    return rk4_act(rig, rig_actuators(rig, t, h), h, y);
}

// One plain RK4 step of length h from y with the actuator `act` at its stage times.
fn rk4_act(rig: Rig, act: Actuation, h: real, y: State) -> State {
    let hh = real(0.5) * h;
    let a0 = act.a0;
    let am = act.am;
    let a1 = act.a1;
    // acc = ((k1 + 2·k2) + 2·k3) + k4, summed in the CPU's order while each k
    // is live, so only y, acc and one k stay in registers.
    var k = rig_deriv(rig, a0, y);
    var acc = k;
    k = rig_deriv(rig, am, State(y.q + hh * k.q, y.v + hh * k.v));
    acc = State(acc.q + real(2.0) * k.q, acc.v + real(2.0) * k.v);
    k = rig_deriv(rig, am, State(y.q + hh * k.q, y.v + hh * k.v));
    acc = State(acc.q + real(2.0) * k.q, acc.v + real(2.0) * k.v);
    k = rig_deriv(rig, a1, State(y.q + h * k.q, y.v + h * k.v));
    let h6 = h * real(1.0 / 6.0);
    return State(y.q + h6 * (acc.q + k.q), y.v + h6 * (acc.v + k.v));
}

// Fraction θ ∈ [0, 1] of the step where the cubic Hermite interpolant of the
// switching function crosses zero (g0 < 0 ≤ g1, derivatives scaled by h).
fn hermite_crossing(g0: real, d0: real, g1: real, d1: real) -> real {
    var lo = real(0.0);
    var hi = real(1.0);
    for (var i = 0u; i < CROSSING_ITERATIONS; i += 1u) {
        let s = real(0.5) * (lo + hi);
        let s2 = s * s;
        let s3 = s2 * s;
        let p = (real(2.0) * s3 - real(3.0) * s2 + real(1.0)) * g0
            + (s3 - real(2.0) * s2 + s) * d0
            + (real(-2.0) * s3 + real(3.0) * s2) * g1
            + (s3 - s2) * d1;
        if p < real(0.0) {
            lo = s;
        } else {
            hi = s;
        }
    }
    return real(0.5) * (lo + hi);
}

// n steps of length h from y, step i (0 ≤ i < n) starting at
// t_base + (first + i)·h, each split at the switch if it fires inside. Used for
// the prologue (a few steps per run); the sampled part of a run takes plain
// steps in blocks and locates a crossing after the block (shared/run.wgsl).
//
// One loop around a single `rk4`, one sub-step per iteration, so the kernel
// holds one copy of the stage code here and no nested loop per step: CPU
// drivers such as lavapipe execute both sides of every branch and every loop
// body at least once. Phases of a step: 0 the whole step; 1 (only when the
// switch crossed) from t to the crossing; 2 from the crossing to t + h in the
// post-switch regime. The loop state is updated with selects.
fn rk4_switch_steps(
    rig: ptr<function, Rig>,
    t_base: real,
    first: u32,
    n: u32,
    h: real,
    y: State,
) -> State {
    var ys = y;
    var i = 0u;
    var phase = 0u;
    var s = real(0.0);
    var g0 = vec2<real>(real(0.0), real(0.0));
    var pending = false;
    loop {
        if i >= n {
            break;
        }
        let t = t_base + real(first + i) * h;
        if phase == 0u {
            g0 = rig_switch(*rig, ys);
            pending = !rig_is_broken(*rig) && g0.x < real(0.0);
            if !rig_is_broken(*rig) && g0.x >= real(0.0) {
                rig_fire(rig);
            }
        }
        let ts = select(t, t + s, phase == 2u);
        let hs = select(select(h, s, phase == 1u), h - s, phase == 2u);
        let next = rk4(*rig, ts, hs, ys);
        let g1 = rig_switch(*rig, next);
        let crossed = phase == 0u && pending && g1.x >= real(0.0);
        if crossed {
            s = hermite_crossing(g0.x, g0.y * h, g1.x, g1.y * h) * h;
        }
        let resume = phase == 1u;
        if resume {
            rig_fire(rig);
        }
        ys = State(select(next.q, ys.q, crossed), select(next.v, ys.v, crossed));
        phase = select(select(0u, 1u, crossed), 2u, resume);
        i = select(i + 1u, i, crossed || resume);
    }
    return ys;
}
