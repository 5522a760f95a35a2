// Classic RK4 with the one-way switch (fracture) located inside the step.
// Mirrors src/integrate/rk4.rs operation for operation: same stage times, same
// Hermite cubic, same CROSSING_ITERATIONS bisection halvings.
//
// The model file provides `Rig`, `rig_actuators` (→ `Actuation`), `rig_deriv`, `rig_switch`,
// `rig_fire` and `rig_is_broken`.

// Up to four degrees of freedom: positions q and velocities v.
struct State {
    q: vec4<real>,
    v: vec4<real>,
}

// One plain RK4 step of length h from (t, y). The actuator is evaluated once per
// distinct stage time (t, t + h/2, t + h), by the model in one call.
fn rk4(rig: Rig, t: real, h: real, y: State) -> State {
    let hh = real(0.5) * h;
    let act = rig_actuators(rig, t, h);
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
    let h6 = h / real(6.0);
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

// One step of length h from (t, y), split at the switch if it fires inside.
//
// Written as a loop around a single `rk4` so the kernel holds one copy of the
// stage code: CPU drivers such as lavapipe execute both sides of a divergent
// branch, so three inlined copies would triple the cost of every step. Phases:
// 0 the whole step; 1 (only when the switch crossed) from t to the crossing;
// 2 from the crossing to t + h in the post-switch regime.
fn rk4_switch_step(rig: ptr<function, Rig>, t: real, h: real, y: State) -> State {
    var pending = !rig_is_broken(*rig);
    var g0 = vec2<real>(real(0.0), real(0.0));
    if pending {
        g0 = rig_switch(*rig, y);
        if g0.x >= real(0.0) {
            rig_fire(rig);
            pending = false;
        }
    }
    var phase = 0u;
    var ys = y;
    var ts = t;
    var hs = h;
    var s = real(0.0);
    var out = y;
    loop {
        let next = rk4(*rig, ts, hs, ys);
        if phase == 0u && pending {
            let g1 = rig_switch(*rig, next);
            if g1.x >= real(0.0) {
                s = hermite_crossing(g0.x, g0.y * h, g1.x, g1.y * h) * h;
                hs = s;
                phase = 1u;
                continue;
            }
        }
        if phase == 1u {
            rig_fire(rig);
            ys = next;
            ts = t + s;
            hs = h - s;
            phase = 2u;
            continue;
        }
        out = next;
        break;
    }
    return out;
}
